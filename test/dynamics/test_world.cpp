// Unit tests of the dynamics building blocks: collider shapes, dampers, the stable step,
// border nodes, kinematic groups and their reactions, pushes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/collider.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/stable_time_step.h"
#include "msm_sim/model/model_builder.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

void ExpectDistance(const ColliderShape& shape, const Eigen::Vector3d& p, double distance,
                    const Eigen::Vector3d& normal) {
  Eigen::Vector3d n, closest;
  EXPECT_NEAR(shape.SignedDistance(p, &n, &closest), distance, 1e-12) << p.transpose();
  EXPECT_LT((n - normal).norm(), 1e-12) << p.transpose() << " normal " << n.transpose();
  // The closest point lies at the signed distance back along the normal.
  EXPECT_LT((closest + distance * n - p).norm(), 1e-12) << p.transpose();
}

TEST(ColliderShape, SignedDistancesOfThePrimitives) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), z = Eigen::Vector3d::UnitZ();
  ExpectDistance(ColliderShape::Plane(), Eigen::Vector3d(3, 4, 0.2), 0.2, z);
  ExpectDistance(ColliderShape::Plane(), Eigen::Vector3d(3, 4, -0.2), -0.2, z);
  const ColliderShape box = ColliderShape::Box(Eigen::Vector3d(2, 2, 2));
  ExpectDistance(box, Eigen::Vector3d(1.5, 0, 0), 0.5, x);
  ExpectDistance(box, Eigen::Vector3d(0.9, 0.2, 0.1), -0.1, x);
  ExpectDistance(box, Eigen::Vector3d(2, 2, 0), std::sqrt(2.0),
                 Eigen::Vector3d(1, 1, 0).normalized());
  ExpectDistance(ColliderShape::Sphere(0.5), Eigen::Vector3d(0, 0, 2), 1.5, z);
  ExpectDistance(ColliderShape::Sphere(0.5), Eigen::Vector3d(0.3, 0, 0), -0.2, x);
  const ColliderShape capsule = ColliderShape::Capsule(0.1, 1.0);
  ExpectDistance(capsule, Eigen::Vector3d(0.3, 0, 0.2), 0.2, x);
  ExpectDistance(capsule, Eigen::Vector3d(0, 0, 0.8), 0.2, z);
  const ColliderShape cylinder = ColliderShape::Cylinder(0.5, 1.0);
  ExpectDistance(cylinder, Eigen::Vector3d(1, 0, 0.1), 0.5, x);
  ExpectDistance(cylinder, Eigen::Vector3d(0.1, 0, 0.9), 0.4, z);
  ExpectDistance(cylinder, Eigen::Vector3d(0.1, 0, 0.45), -0.05, z);
  ExpectDistance(cylinder, Eigen::Vector3d(0.4, 0, 0), -0.1, x);
  EXPECT_THROW(ColliderShape::Sphere(0.0), std::invalid_argument);
  EXPECT_THROW(ColliderShape::Box(Eigen::Vector3d(1, std::nan(""), 1)), std::invalid_argument);
}

TEST(ColliderShape, MeshColliderMatchesTheSphereItApproximates) {
  const auto mesh = std::make_shared<const SolidMesh>(MakeIcosphereMesh(1.0, 5));
  const ColliderShape shape = ColliderShape::Mesh(mesh);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 1.3), Eigen::Vector3d(0.5, -0.4, 0.2),
                                   Eigen::Vector3d(-1.1, 0.6, 0.3)}) {
    Eigen::Vector3d n, closest;
    const double d = shape.SignedDistance(p, &n, &closest);
    EXPECT_NEAR(d, p.norm() - 1.0, 2e-3) << p.transpose();
    EXPECT_GT(n.dot(p.normalized()), 0.999);
  }
}

TEST(ForceEvaluator, DampersPullWithBetaKTimesTheStretchRate) {
  ModelBuilder builder(Material::FromYoungsPoisson(1e5, 0.25, 1000.0));
  builder.AddNode(Eigen::Vector3d::Zero(), 1.0);
  builder.AddNode(Eigen::Vector3d(1, 0, 0), 1.0);
  builder.AddSpring(0, 1, 200.0);
  const Model model = builder.Build(1.0, 1.0);
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd x = model.rest_positions();
  Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 2);
  v.col(1) = Eigen::Vector3d(0.5, 0.3, 0.0);  // lengthening at 0.5 m/s (the 0.3 is a rotation)
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 2);
  evaluator.AccumulateForces(x, v, 0.01, &f);
  // t = beta k dL/dt = 0.01 * 200 * 0.5 = 1 N, pulling the ends together.
  EXPECT_NEAR(evaluator.total_tensions()[0], 1.0, 1e-12);
  EXPECT_LT((f.col(0) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LT((f.col(1) + Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
}

TEST(StableTimeStep, MatchesTheLargestEigenfrequency) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.3, 0.2, 0.2);
  lattice_options.lattice.spacing = 0.05;
  for (const double nu : {0.25, 0.45}) {
    const Model model =
        BuildCubicLattice(Material::FromYoungsPoisson(1e5, nu, 1000.0), lattice_options);
    // Dense M^-1/2 K M^-1/2, column by column.
    ForceEvaluator evaluator(model);
    evaluator.Linearize(model.rest_positions());
    const int n = 3 * model.num_nodes();
    Eigen::MatrixXd a(n, n);
    for (int column = 0; column < n; ++column) {
      Eigen::Matrix3Xd unit = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
      unit(column % 3, column / 3) = 1.0 / std::sqrt(model.masses()[column / 3]);
      Eigen::Matrix3Xd k_unit(3, model.num_nodes());
      evaluator.ApplyStiffness(unit, &k_unit);
      for (int row = 0; row < n; ++row) {
        a(row, column) = k_unit(row % 3, row / 3) / std::sqrt(model.masses()[row / 3]);
      }
    }
    const double lambda = a.eigenvalues().real().maxCoeff();
    StableTimeStepOptions options;
    options.safety = 1.0;
    EXPECT_NEAR(StableTimeStep(model, options) / (2.0 / std::sqrt(lambda)), 1.0, 0.01)
        << "nu " << nu;
    // Dampers shorten it.
    options.damping_beta = 1e-3;
    EXPECT_LT(StableTimeStep(model, options), 2.0 / std::sqrt(lambda));
  }
}

TEST(BorderNodes, SurfaceOfACubicLatticeWithMeanHalfSpringRadii) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(0.4);
  lattice_options.lattice.spacing = 0.1;  // 4 x 4 x 4 nodes, 8 inside
  const Model model =
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.25, 1000.0), lattice_options);
  const BorderNodes border = FindBorderNodes(model);
  EXPECT_EQ(border.nodes.size(), 56u);
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    EXPECT_GT(border.radii[k], 0.05);                        // half the A spring
    EXPECT_LT(border.radii[k], 0.5 * std::sqrt(2.0) * 0.1);  // half the B spring
  }
}

// A lattice cut by a curved surface: no collision sphere stands a spacing proud of the others.
// The cut cells' nodes lie up to half a spacing outside the surface; with the mean half-spring
// radius alone a row of them stood a whole spacing past its neighbours' spheres and carried a
// pad's squeeze by itself. Each sphere now ends halfway between the surface and its cell's outer
// face (docs/physics.md §7): at most the largest mean half-length (half a face diagonal) less
// half the thinnest cell (min_fraction 0.1) past the surface, within the flat-cut approximation.
TEST(BorderNodes, SpheresOfACutLatticeEndNearTheSurface) {
  const double radius = 1.0, a = 0.1;
  MeshCubicLatticeOptions options;
  options.lattice.spacing = a;
  const Model model = BuildCubicLatticeInSolid(Material::FromYoungsPoisson(1e5, 0.3, 1000.0),
                                               SolidMesh(MakeIcosphereMesh(radius, 4)), options);
  const BorderNodes border = FindBorderNodes(model);
  ASSERT_GT(border.nodes.size(), 100u);
  double farthest = -1.0;
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    ASSERT_GT(border.radii[k], 0.0);
    const double past = model.rest_positions().col(border.nodes[k]).norm() + border.radii[k];
    farthest = std::max(farthest, past - radius);
  }
  std::printf("  farthest sphere past the surface: %.3f a\n", farthest / a);
  EXPECT_LT(farthest, (0.5 * std::sqrt(2.0) - 0.05) * a);
  EXPECT_GT(farthest, 0.0);
  // Whole cells keep their radii: an aligned box has no insets.
  CubicLatticeOptions box;
  box.size = Eigen::Vector3d::Constant(0.4);
  box.lattice.spacing = 0.1;
  EXPECT_EQ(BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.25, 1000.0), box)
                .surface_insets()
                .maxCoeff(),
            0.0);
}

// A sphere lowered onto a hand-made border touches the collision sphere it meets first.
TEST(BorderNodes, SphereTouchdownHeightIsWhereTheSphereFirstTouches) {
  Eigen::Matrix3Xd x(3, 2);
  x << 0.0, 0.3, 0.0, 0.0, 1.0, 1.1;  // two nodes: (0, 0, 1) and (0.3, 0, 1.1)
  BorderNodes border;
  border.nodes = {0, 1};
  border.radii = {0.1, 0.1};
  // Right above node 0, radius 0.5: reaches node 1 (0.3 aside) at 1.1 + sqrt(0.6^2 - 0.3^2).
  EXPECT_NEAR(SphereTouchdownHeight(x, border, Eigen::Vector2d(0, 0), 0.5),
              1.1 + std::sqrt(0.36 - 0.09), 1e-12);
  // A small sphere above node 0 misses node 1: touches node 0's sphere at 1 + 0.1 + 0.05.
  EXPECT_NEAR(SphereTouchdownHeight(x, border, Eigen::Vector2d(0, 0), 0.05), 1.15, 1e-12);
  EXPECT_EQ(SphereTouchdownHeight(x, border, Eigen::Vector2d(5, 0), 0.5),
            -std::numeric_limits<double>::infinity());
}

std::shared_ptr<const Model> Block() {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(0.2);
  lattice_options.lattice.spacing = 0.04;
  return std::make_shared<Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), lattice_options));
}

// The largest |E / E0 - 1| of a free, undamped 20 cm block (nu = 1/4: no dispersion, so the
// forces have a potential for every law) released from a 20 % stretch along x, over 0.3 s of
// explicit steps without gravity.
double FreeVibrationEnergyDeviation(const Model& block) {
  WorldOptions options;
  options.gravity.setZero();
  World world(options);
  const int body = world.AddBody("block", std::make_shared<Model>(block), BodyOptions{});
  State state = world.state(body);
  const Eigen::Vector3d centre = state.positions.rowwise().mean();
  state.positions.row(0) = (state.positions.row(0).array() - centre.x()) * 1.2 + centre.x();
  world.SetState(body, state);
  const double initial = world.ComputeEnergies(body).total();
  double deviation = 0.0;
  for (int k = 0; k < 300; ++k) {
    const StepReport report = world.Step(1e-3);
    EXPECT_TRUE(report.accepted) << report.reason;
    deviation = std::max(deviation, std::abs(world.ComputeEnergies(body).total() / initial - 1.0));
  }
  return deviation;
}

// The fitted law (Ecoflex 00-30, docs/physics.md §4.1) keeps the explicit integrator's energy
// at least as well as the linear law (measured: largest deviation 1.4 % against 1.9 %; its
// substeps are shorter by the stable step's stiffening), and both within 2.5 % at every step.
TEST(World, PowerLawBlockVibratesWithoutDriftingEnergy) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(0.2);
  lattice_options.lattice.spacing = 0.04;
  const Model linear =
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.25, 1000.0), lattice_options);
  ASSERT_EQ(linear.dispersion_fraction(), 0.0);
  const double linear_deviation = FreeVibrationEnergyDeviation(linear);
  const double power_deviation = FreeVibrationEnergyDeviation(
      WithSpringLaw(linear, SpringLaw::kPower, PowerSpringLaw{-4.54, 0.116}));
  std::printf(
      "  free vibration from 20 %% stretch: largest energy deviation linear %.4f %%, "
      "power law %.4f %%\n",
      100 * linear_deviation, 100 * power_deviation);
  EXPECT_LT(linear_deviation, 0.025);
  EXPECT_LE(power_deviation, linear_deviation);
}

// The clamp's reaction balances a static push and the weight (Newton's third law).
// Pushes the 20 cm block near its top with (3, 0, -20) N for 10 s, lets it settle for 1.5 s,
// and expects the last kinematic group's reaction, averaged over 0.2 s, to balance the push and
// the weight within 2 %.
void PushAndExpectTheClampToBalanceIt(World* world, int body, const Model& block) {
  const Eigen::Vector3d push(3.0, 0.0, -20.0);
  world->ApplyForce(body, Eigen::Vector3d(0.1, 0.1, 0.18), push, 0.03, 10.0);
  for (int step = 0; step < 1500; ++step) ASSERT_TRUE(world->Step(1e-3).accepted);
  Eigen::Vector3d on_clamp = Eigen::Vector3d::Zero();
  for (int step = 0; step < 200; ++step) {
    ASSERT_TRUE(world->Step(1e-3).accepted);
    on_clamp += world->wrenches(body).back().force / 200;
  }
  const Eigen::Vector3d expected = push + block.masses().sum() * Eigen::Vector3d(0, 0, -9.81);
  EXPECT_LT((on_clamp - expected).norm(), 0.02 * expected.norm())
      << on_clamp.transpose() << " vs " << expected.transpose();
}

TEST(World, ClampReactionBalancesAStaticPush) {
  World world;
  BodyOptions options;
  options.damping_beta = 0.01;
  const auto block = Block();
  const int body = world.AddBody("block", block, options);
  // The bottom layer: the half-space below z = 3 cm (nodes at 2, 6, ... cm).
  const KinematicGroup clamp{
      "base", NodesInHalfSpace(*block, Eigen::Vector3d(0, 0, 0.03), Eigen::Vector3d::UnitZ()), {}};
  ASSERT_EQ(clamp.nodes,
            NodesInBox(*block, Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 0.03)));
  ASSERT_EQ(clamp.nodes.size(), 25u);
  world.AddKinematicGroup(body, clamp);
  PushAndExpectTheClampToBalanceIt(&world, body, *block);
  // Every clamped node carries reaction in every substep.
  const int events = world.wrenches(body).back().microcollisions;
  EXPECT_GT(events, 0);
  EXPECT_EQ(events % static_cast<int>(clamp.nodes.size()), 0);
}

// A block clamped at its base face (face anchors, AnchoredPlane) rather than at its bottom node
// layer: the anchors' token masses leave the stable step once the clamp holds them, the
// reaction balances a static push and the weight, and the anchors stay on the face.
TEST(World, FaceAnchoredClampBalancesAStaticPush) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.2, 0.2, 0.2);
  lattice_options.lattice.spacing = 0.04;
  lattice_options.surface.anchored_planes = {
      AnchoredPlane{Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitZ()}};
  const auto block = std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(5e4, 0.3, 1000.0), lattice_options));
  const std::vector<NodeIndex> anchors =
      AnchorNodes(*block, lattice_options.surface.anchored_planes[0]);
  ASSERT_EQ(anchors.size(), 25u + 2u * 5u * 6u);
  World world;
  BodyOptions options;
  options.damping_beta = 0.01;
  const int body = world.AddBody("block", block, options);
  const double counting_anchors = world.stable_time_step();
  world.AddKinematicGroup(body, KinematicGroup{"base", anchors, {}});
  StableTimeStepOptions step;
  step.damping_beta = options.damping_beta;
  step.safety = WorldOptions{}.time_step_safety;
  step.fixed_nodes = anchors;
  EXPECT_DOUBLE_EQ(world.stable_time_step(), StableTimeStep(*block, step));
  EXPECT_GT(world.stable_time_step(), 300.0 * counting_anchors);

  PushAndExpectTheClampToBalanceIt(&world, body, *block);
  for (const NodeIndex anchor : anchors) {
    EXPECT_EQ(world.state(body).positions.col(anchor), block->rest_positions().col(anchor));
  }
}

TEST(World, KinematicGroupsFollowTheirFrame) {
  World world(WorldOptions{Eigen::Vector3d::Zero()});
  const auto block = Block();
  const int body = world.AddBody("block", block);
  KinematicGroup grip{"grip", {0, 1, 2}, [](double t) {
                        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
                        pose.translation() = Eigen::Vector3d(0.1 * t, 0.0, 0.0);
                        pose.linear() =
                            Eigen::AngleAxisd(0.5 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
                        return pose;
                      }};
  world.AddKinematicGroup(body, grip);
  for (int step = 0; step < 100; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
  const Eigen::Isometry3d pose = grip.pose(world.time());
  for (const NodeIndex node : grip.nodes) {
    EXPECT_LT((world.state(body).positions.col(node) -
               pose * Eigen::Vector3d(block->rest_positions().col(node)))
                  .norm(),
              1e-12);
  }
}

TEST(World, PushesSpreadOverNearbyNodesByMass) {
  World world(WorldOptions{Eigen::Vector3d::Zero()});
  const auto block = Block();
  const int body = world.AddBody("block", block);
  // Far from every node within the radius: the nearest node takes it all.
  world.ApplyForce(body, Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(0, 0, 1), 0.01, 0.0);
  ASSERT_TRUE(world.Step(1e-3).accepted);
  const Eigen::Vector3d momentum =
      world.state(body).velocities * block->masses();  // = impulse of the push
  EXPECT_LT((momentum - Eigen::Vector3d(0, 0, 1e-3)).norm(), 1e-12);
  EXPECT_THROW(world.ApplyForce(body, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), -1.0, 0.0),
               std::invalid_argument);
  EXPECT_THROW(world.ApplyForce(7, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.1, 0.0),
               std::invalid_argument);
}

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
// kick) run on each node share's thread (ForceEvaluator::NodeStages). Two threads repeat
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

TEST(World, ResetRestoresTheRestState) {
  World world;
  const auto block = Block();
  const int body = world.AddBody("block", block);
  for (int step = 0; step < 50; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
  EXPECT_GT((world.state(body).positions - block->rest_positions()).norm(), 1e-3);
  world.Reset();
  EXPECT_EQ(world.state(body).positions, block->rest_positions());
  EXPECT_EQ(world.time(), 0.0);
}

// A state that fails by itself (a node already faster than max_speed, no push to drop) stops the
// bodies instead of failing every later step; the soak got stuck this way for 579k steps.
TEST(World, AStateThatFailsByItselfIsStopped) {
  World world(WorldOptions{Eigen::Vector3d::Zero()});
  const auto block = Block();
  const int body = world.AddBody("block", block);
  State state = world.state(body);
  state.velocities.col(0) = Eigen::Vector3d(150.0, 0.0, 0.0);  // above max_speed 100 m/s
  world.SetState(body, state);
  const StepReport failed = world.Step(1e-3);
  ASSERT_FALSE(failed.accepted);
  EXPECT_NE(failed.reason.find("stopped where they are"), std::string::npos) << failed.reason;
  // Finer substeps were tried (no push to drop) and did not help: not kept.
  EXPECT_FALSE(failed.refined_because.empty());
  EXPECT_EQ(world.substep_refinement(), 1);
  EXPECT_EQ(world.state(body).positions, state.positions);
  EXPECT_EQ(world.state(body).velocities.norm(), 0.0);
  EXPECT_EQ(world.time(), 0.0);
  for (int step = 0; step < 10; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
}

// A shape that diverges by itself even at rest (here: every node moved 100 times its rest
// distance from the centre, springs stretched a hundredfold) goes back to its rest shape after
// stopping has not helped.
TEST(World, AShapeThatDivergesAtRestGoesBackToItsRestShape) {
  World world(WorldOptions{Eigen::Vector3d::Zero()});
  const auto block = Block();
  const int body = world.AddBody("block", block);
  State state = world.state(body);
  const Eigen::Vector3d centre = block->rest_positions().rowwise().mean();
  state.positions = (100.0 * (block->rest_positions().colwise() - centre)).colwise() + centre;
  world.SetState(body, state);
  const StepReport stopped = world.Step(1e-3);
  ASSERT_FALSE(stopped.accepted);
  EXPECT_NE(stopped.reason.find("stopped where they are"), std::string::npos) << stopped.reason;
  const StepReport restored = world.Step(1e-3);
  ASSERT_FALSE(restored.accepted);
  EXPECT_NE(restored.reason.find("rest shape"), std::string::npos) << restored.reason;
  EXPECT_EQ(world.state(body).positions, block->rest_positions());
  for (int step = 0; step < 10; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
}

// A block held stretched by 30 % along z between two clamped layers (kinematic groups), without
// dampers, stepped at exactly its stable step (safety 1): the stretched springs' tension adds a
// stiffness T / L across each of them, which lifts the highest frequency above the rest shape's,
// and at safety 1 any lift diverges (rejected within a few dozen steps when refinement is off).
// With refinement the diverging step is taken again with twice the substeps and every step is
// accepted; Reset restores the rest shape's substep.
World StretchedBlockAtTheStableStep(int max_substep_refinement, int* body) {
  WorldOptions options{Eigen::Vector3d::Zero()};
  options.time_step_safety = 1.0;
  options.max_substep_refinement = max_substep_refinement;
  World world(options);
  const auto block = Block();
  *body = world.AddBody("block", block);
  const double stretch = 1.3, lift = (stretch - 1.0) * 0.16;  // layers at z = 2 ... 18 cm
  world.AddKinematicGroup(
      *body, KinematicGroup{
                 "base",
                 NodesInHalfSpace(*block, Eigen::Vector3d(0, 0, 0.03), Eigen::Vector3d::UnitZ()),
                 {}});
  world.AddKinematicGroup(
      *body,
      KinematicGroup{
          "top", NodesInHalfSpace(*block, Eigen::Vector3d(0, 0, 0.17), -Eigen::Vector3d::UnitZ()),
          [lift](double) {
            Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
            pose.translation().z() = lift;
            return pose;
          }});
  State state = world.state(*body);
  state.positions.row(2) =
      ((block->rest_positions().row(2).array() - 0.02) * stretch + 0.02).matrix();
  world.SetState(*body, state);
  return world;
}

TEST(World, ADivergingStepIsTakenAgainWithFinerSubsteps) {
  int body = 0;
  World without = StretchedBlockAtTheStableStep(1, &body);
  const double dt = without.stable_time_step();
  bool rejected = false;
  for (int step = 0; step < 100 && !rejected; ++step) rejected = !without.Step(dt).accepted;
  ASSERT_TRUE(rejected) << "the stretched block must diverge at the rest shape's stable step";

  World world = StretchedBlockAtTheStableStep(WorldOptions{}.max_substep_refinement, &body);
  ASSERT_EQ(world.stable_time_step(), dt);
  int refined_steps = 0;
  for (int step = 0; step < 300; ++step) {
    const StepReport report = world.Step(dt);
    ASSERT_TRUE(report.accepted) << "step " << step << ": " << report.reason;
    EXPECT_EQ(report.substeps, report.substep_refinement);  // dt is one stable step
    if (!report.refined_because.empty()) {
      ++refined_steps;
      EXPECT_NE(report.refined_because.find("m/s"), std::string::npos) << report.refined_because;
    }
  }
  EXPECT_GE(refined_steps, 1);
  EXPECT_GE(world.substep_refinement(), 2);
  EXPECT_LE(world.substep_refinement(), WorldOptions{}.max_substep_refinement);
  EXPECT_TRUE(world.state(body).positions.allFinite());
  world.Reset();
  EXPECT_EQ(world.substep_refinement(), 1);
}

}  // namespace
}  // namespace msm_sim::core
