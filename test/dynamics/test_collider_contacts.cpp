// ColliderContacts (src/dynamics/collider_contacts.h): a node's approach to a collider stops,
// its rebound waits for the next substep, Coulomb friction never reverses the sliding, and the
// impulses reach the collider's sum.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "dynamics/collider_contacts.h"
#include "internal_world.h"

namespace msm_sim::core::internal {
namespace {

TEST(CoulombFriction, StopsASlowSlideAndSlowsAFastOneAlongItself) {
  const Eigen::Vector3d sliding(3.0, 4.0, 0.0);
  EXPECT_EQ(CoulombFriction(sliding, 10.0), -sliding);
  EXPECT_LT((CoulombFriction(sliding, 1.0) - Eigen::Vector3d(-0.6, -0.8, 0.0)).norm(), 1e-15);
  EXPECT_EQ(CoulombFriction(Eigen::Vector3d::Zero(), 0.0), Eigen::Vector3d::Zero());
}

// A block sunk a little into the ground and falling at 1 m/s: its base stops, rebounds by e.
struct FallingBlock : ::testing::Test {
  void SetUp() override {
    world.options.contact_iterations = 4;
    Collider ground;
    ground.restitution = 0.5;
    ground.friction = 0.5;
    world.colliders.push_back(ground);
    BodyOptions options;
    options.restitution = 1.0;
    options.friction = 0.5;
    Body& block = AddBody(&world, "block", SmallBlock(Eigen::Vector3d(0, 0, 0.0)), options);
    // Every base node's sphere overlaps the ground, none deeply enough to be recovering.
    const double smallest = *std::min_element(block.border.radii.begin(), block.border.radii.end());
    block.state.positions.row(2).array() += 0.97 * smallest;
    block.state.velocities.row(2).setConstant(-1.0);
    block.state.velocities.row(0).setConstant(0.1);  // sliding along x
    world.substep = 1e-4;
  }
  WorldState world{WorldOptions{}};
  ColliderContacts contacts{&world};
};

TEST_F(FallingBlock, TheBaseStopsAndItsReboundIsPending) {
  Body& block = world.bodies.front();
  int microcollisions = 0;
  contacts.CollideWithColliders(&block, &microcollisions);
  EXPECT_GT(microcollisions, 0);
  ASSERT_EQ(block.pending.size(), static_cast<std::size_t>(microcollisions));
  double impulse_z = 0.0;
  for (const PendingResponse& rebound : block.pending) {
    // e = min(0.5, 1): half the 1 m/s approach, along the ground's normal.
    EXPECT_LT((rebound.delta_v - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-12);
    EXPECT_EQ(block.state.velocities(2, rebound.node), 0.0);
    // Friction mu (1 + e) 1 m/s = 0.75 m/s exceeds the 0.1 m/s slide: the node sticks.
    EXPECT_EQ(block.state.velocities(0, rebound.node), 0.0);
    impulse_z -= block.model->masses()[rebound.node] * 1.5;
  }
  // The collider took every node's m (1 + e) v_n, downwards.
  EXPECT_NEAR(block.impulses[0].impulse.z(), impulse_z, 1e-12);
  EXPECT_EQ(block.impulses[0].count, microcollisions);
  // The nodes away from the ground still fall.
  EXPECT_EQ(block.state.velocities.row(2).minCoeff(), -1.0);
}

TEST_F(FallingBlock, APairsFrictionOverridesTheSurfaces) {
  Body& block = world.bodies.front();
  EXPECT_DOUBLE_EQ(contacts.Friction(block, 0), 0.5);
  block.pair_friction[0] = 0.0;
  EXPECT_EQ(contacts.Friction(block, 0), 0.0);
  int microcollisions = 0;
  contacts.CollideWithColliders(&block, &microcollisions);
  for (const PendingResponse& rebound : block.pending) {
    EXPECT_EQ(block.state.velocities(0, rebound.node), 0.1);  // frictionless: slides on
  }
}

TEST_F(FallingBlock, ADisabledColliderTouchesNothing) {
  world.colliders.front().enabled = false;
  Body& block = world.bodies.front();
  int microcollisions = 0;
  contacts.CollideWithColliders(&block, &microcollisions);
  EXPECT_EQ(microcollisions, 0);
  EXPECT_TRUE(block.pending.empty());
  EXPECT_EQ(block.state.velocities.row(2).maxCoeff(), -1.0);
}

TEST_F(FallingBlock, DetectionFindsTheGroundWithinAReach) {
  const std::vector<ColliderFrame> frames = contacts.FrameColliders();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_FALSE(frames[0].bounded);
  std::vector<NodeContact> found;
  contacts.DetectColliderContacts(frames, Eigen::Vector3d(0.3, 0.2, 0.01), 0.02, &found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_DOUBLE_EQ(found[0].distance, 0.01);
  EXPECT_EQ(found[0].point, Eigen::Vector3d(0.3, 0.2, 0.0));
  contacts.DetectColliderContacts(frames, Eigen::Vector3d(0.3, 0.2, 0.03), 0.02, &found);
  EXPECT_TRUE(found.empty());
}

// A node overlapping the ground deeper than its sphere allows is moved out by the part of the
// recovery speed its velocity lacks, times the substep (docs/physics.md §7.2).
TEST_F(FallingBlock, ADeepOverlapIsRecoveredAtTheRecoverySpeed) {
  Body& block = world.bodies.front();
  block.state.velocities.setZero();
  block.state.positions.row(2).array() -= 0.5 * LowestZ(block);
  const Eigen::Matrix3Xd before = block.state.positions;
  int microcollisions = 0;
  contacts.CollideWithColliders(&block, &microcollisions);
  EXPECT_EQ(microcollisions, 0);  // nothing approached
  int recovered = 0;
  for (std::size_t k = 0; k < block.border.nodes.size(); ++k) {
    const NodeIndex node = block.border.nodes[k];
    const double z = before(2, node), radius = block.border.radii[k];
    if (z >= radius) continue;
    const double speed = std::min(world.options.penetration_max_speed,
                                  (0.99 * radius - z) / world.options.penetration_recovery_time);
    EXPECT_NEAR(block.state.positions(2, node) - z, speed * world.substep, 1e-12);
    ++recovered;
  }
  EXPECT_EQ(recovered, 16);  // the 4 x 4 base
}

}  // namespace
}  // namespace msm_sim::core::internal
