// Unit tests of the World's node shares on two threads: repeatable and following one thread,
// a substep in one pass of the shares, shares cut at contacts, a rejected step's rollback.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "msm_sim/dynamics/collider.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

// What one run of the scene below leaves behind.
struct SharedRun {
  Eigen::Matrix3Xd positions, velocities;
  Eigen::Vector3d sphere_force;
};

// Adds a block of 1,152 nodes (above the node-share threshold), with dampers and restitution
// 0.5, 1 mm above the ground to `world`; returns its body index.
int AddBlockAboveGround(World* world) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.06, 0.06, 0.04);
  lattice_options.lattice.spacing = 0.005;
  const auto block = std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.45, 1100.0), lattice_options));
  EXPECT_GE(block->num_nodes(), 1'000);
  BodyOptions body_options;
  body_options.damping_beta = 1e-4;
  body_options.restitution = 0.5;
  const int body = world->AddBody("block", block, body_options);
  Collider ground;
  ground.pose.translation().z() =
      block->rest_positions().row(2).minCoeff() - world->border(body).radii[0] - 1e-3;
  world->AddCollider(ground);
  return body;
}

// A 1 cm sphere (Coulomb coefficient `friction`) 8 mm above the top of the block `body`, moving
// down at 10 cm/s, and a push of (0.5, -0.3, -1) N for 8 ms near the top at (5, 1) cm; returns the
// sphere's collider index.
int PressAndPush(World* world, int body, double friction) {
  const Model& block = world->model(body);
  const double top = block.rest_positions().row(2).maxCoeff();
  Collider sphere;
  sphere.shape = ColliderShape::Sphere(0.01);
  sphere.pose.translation() =
      Eigen::Vector3d(0.03, 0.03, top + world->border(body).radii[0] + 0.008);
  sphere.linear_velocity = Eigen::Vector3d(0.0, 0.0, -0.1);
  sphere.friction = friction;
  const int finger = world->AddCollider(sphere);
  world->ApplyForce(body, Eigen::Vector3d(0.05, 0.01, top), Eigen::Vector3d(0.5, -0.3, -1.0), 0.008,
                    1.0);
  return finger;
}

// The block above dropped onto the ground, with restitution left pending at every contact, a
// sphere pressing into its top, a push on nodes near the top and a kinematic group across both
// halves of the node order, for 60 ms on `threads` threads.
SharedRun RunSharedScene(int threads) {
  WorldOptions options;
  options.threads = threads;
  World world(options);
  const int body = AddBlockAboveGround(&world);
  const Model& block = world.model(body);
  const int finger = PressAndPush(&world, body, 0.5);
  // The nodes of the side x < 3 mm from bottom to top, in both shares, swaying in y.
  world.AddKinematicGroup(
      body, KinematicGroup{
                "side",
                NodesInHalfSpace(block, Eigen::Vector3d(0.003, 0.0, 0.0), Eigen::Vector3d::UnitX()),
                [](double t) {
                  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
                  pose.translation().y() = 1e-3 * std::sin(40.0 * t);
                  return pose;
                }});
  SharedRun run;
  for (int step = 0; step < 60; ++step) {
    const StepReport report = world.Step(1e-3);
    EXPECT_TRUE(report.accepted) << report.reason;
  }
  run.positions = world.state(body).positions;
  run.velocities = world.state(body).velocities;
  run.sphere_force = world.wrenches(body)[finger].force;
  return run;
}

// The explicit integrator's per-node stages (drift, restitution, kinematic placement, pushes,
// kick) run on each node share's thread (internal::NodeStages). Two threads repeat
// bit for bit, and follow one thread to the float loops' rounding: the summation order differs
// at the shares' boundary, and 60 ms of contact dynamics amplify that to nanometres (4e-9 m
// measured), far below what a stage left out or applied twice gives (a push missed on one share
// moved nodes by half a millimetre).
TEST(World, NodeSharesOnTwoThreadsRepeatAndFollowOneThread) {
  const SharedRun one = RunSharedScene(1);
  const SharedRun two = RunSharedScene(2);
  const SharedRun again = RunSharedScene(2);
  EXPECT_EQ(two.positions, again.positions);
  EXPECT_EQ(two.velocities, again.velocities);
  EXPECT_EQ(two.sphere_force, again.sphere_force);
  const double moved = (one.positions - RunSharedScene(1).positions).cwiseAbs().maxCoeff();
  EXPECT_EQ(moved, 0.0);
  const double difference = (two.positions - one.positions).cwiseAbs().maxCoeff();
  std::printf(
      "  two threads against one after 60 ms: %.3g m apart at most; sphere force %.4f N "
      "against %.4f N\n",
      difference, two.sphere_force.norm(), one.sphere_force.norm());
  EXPECT_LT(difference, 1e-7);
  EXPECT_GT(one.sphere_force.norm(), 0.1);
  EXPECT_NEAR(two.sphere_force.norm(), one.sphere_force.norm(), 0.01 * one.sphere_force.norm());
}

// The block above dropped onto the ground under a sphere pressing into its top and a push, for
// 60 ms on `threads` threads; `far_body`: with a second block 1 m away (two bodies: stage by
// stage instead of World::SubstepInOnePass).
struct OnePassRun {
  Eigen::Matrix3Xd positions, velocities;
  std::vector<ContactWrench> wrenches;
  int microcollisions = 0;
};
OnePassRun RunOnePassScene(int threads, bool far_body, bool cut_shares = false) {
  WorldOptions options;
  options.threads = threads;
  options.cut_shares_at_contacts = cut_shares;
  World world(options);
  const int body = AddBlockAboveGround(&world);
  const Model& block = world.model(body);
  if (far_body) {
    Eigen::Isometry3d away = Eigen::Isometry3d::Identity();
    away.translation().x() = 1.0;
    BodyOptions far_options;
    far_options.damping_beta = 1e-4;
    world.AddBody("far", std::make_shared<const Model>(TransformedModel(block, away)), far_options);
  }
  PressAndPush(&world, body, 0.8);
  OnePassRun run;
  for (int step = 0; step < 60; ++step) {
    const StepReport report = world.Step(1e-3);
    EXPECT_TRUE(report.accepted) << report.reason;
    // The far block's microcollisions (it lands 1 mm below, as this one) count in the step's too.
    if (!far_body) run.microcollisions += report.microcollisions;
  }
  run.positions = world.state(body).positions;
  run.velocities = world.state(body).velocities;
  run.wrenches = world.wrenches(body);
  return run;
}

// One body alone takes each substep in one pass of its node shares (World::SubstepInOnePass:
// the contact stage and the last drift inside the force loops' shares); two bodies take them
// stage by stage. Contacts with restitution pending, friction, a moving sphere and a push, on
// one and two threads: the one-pass substep must give the block's stage-by-stage motion and
// wrenches to the bit (a share's contacts recorded out of order, a rebound lost between the
// shares or a drift missed would all show).
TEST(World, ASubstepInOnePassGivesTheStageByStageResults) {
  for (const int threads : {1, 2}) {
    const OnePassRun fused = RunOnePassScene(threads, false);
    const OnePassRun staged = RunOnePassScene(threads, true);
    EXPECT_EQ(fused.positions, staged.positions) << threads;
    EXPECT_EQ(fused.velocities, staged.velocities) << threads;
    ASSERT_EQ(fused.wrenches.size(), 2u);
    ASSERT_EQ(staged.wrenches.size(), 2u);
    for (std::size_t c = 0; c < fused.wrenches.size(); ++c) {
      EXPECT_EQ(fused.wrenches[c].force, staged.wrenches[c].force) << threads << " " << c;
      EXPECT_EQ(fused.wrenches[c].torque, staged.wrenches[c].torque) << threads << " " << c;
      EXPECT_EQ(fused.wrenches[c].centroid, staged.wrenches[c].centroid) << threads << " " << c;
      EXPECT_EQ(fused.wrenches[c].microcollisions, staged.wrenches[c].microcollisions);
    }
    // Resting on the ground and pressed by the sphere (the 1 mm drop with restitution 0.5 left
    // rebounds pending: without applying them ahead the velocities differ).
    EXPECT_GT(fused.wrenches[0].normal_force, 0.0) << threads;
    EXPECT_GT(fused.wrenches[1].normal_force, 0.0) << threads;
    EXPECT_GT(fused.microcollisions, 0) << threads;
  }
}

// WorldOptions::cut_shares_at_contacts (on by default): on two threads the one-pass substeps
// of a block resting on the ground run in shares cut at its contacts, which moves where the
// float sums meet: the motion repeats to the bit, differs from equal shares' in its rounding
// only, and one thread has nothing to cut.
TEST(World, SharesCutAtContactsChangeTheRoundingOnly) {
  const OnePassRun cut = RunOnePassScene(2, false, true);
  const OnePassRun again = RunOnePassScene(2, false, true);
  const OnePassRun equal = RunOnePassScene(2, false, false);
  EXPECT_EQ(cut.positions, again.positions);
  EXPECT_EQ(cut.velocities, again.velocities);
  EXPECT_NE(cut.positions, equal.positions) << "no cut on two threads";
  const double moved = (cut.positions - equal.positions).cwiseAbs().maxCoeff();
  std::printf("  largest position difference, cut against equal shares: %.3g m\n", moved);
  EXPECT_LT(moved, 1e-7);
  EXPECT_NEAR(cut.wrenches[0].normal_force, equal.wrenches[0].normal_force,
              1e-4 * std::abs(equal.wrenches[0].normal_force));
  EXPECT_EQ(RunOnePassScene(1, false, true).positions, RunOnePassScene(1, false, false).positions);
}

// The step's rollback copy is taken per node share, each on its share's thread
// (World::SaveForRollback): on two threads a rejected step must still restore every node of
// both shares bit for bit.
TEST(World, ARejectedStepOnTwoThreadsRestoresBothShares) {
  WorldOptions options;
  options.threads = 2;
  World world(options);
  const int body = AddBlockAboveGround(&world);
  for (int step = 0; step < 10; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
  const State before = world.state(body);
  // Moving everywhere: a restored node that kept its old value would show.
  ASSERT_GT(before.velocities.row(2).cwiseAbs().minCoeff(), 0.0);
  const double top = world.model(body).rest_positions().row(2).maxCoeff();
  world.ApplyForce(body, Eigen::Vector3d(0.03, 0.03, top), Eigen::Vector3d(1e12, 0.0, 0.0), 0.01,
                   0.0);
  const StepReport report = world.Step(1e-3);
  ASSERT_FALSE(report.accepted);
  // A push in flight is dropped, not worked around with finer substeps.
  EXPECT_TRUE(report.refined_because.empty());
  EXPECT_EQ(world.substep_refinement(), 1);
  EXPECT_EQ(world.state(body).positions, before.positions);
  EXPECT_EQ(world.state(body).velocities, before.velocities);
  EXPECT_TRUE(world.Step(1e-3).accepted) << "the next step goes on from the kept state";
}

}  // namespace
}  // namespace msm_sim::core
