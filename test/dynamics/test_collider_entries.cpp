// ColliderEntries (src/dynamics/collider_entries.h): a collider that appears with node centres
// inside a body is moved out along the way out of the body, to where no collision sphere
// touches it, and pressed back in at the recovery speed (docs/physics.md §7.2).
#include <algorithm>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "dynamics/collider_entries.h"
#include "internal_world.h"

namespace msm_sim::core::internal {
namespace {

// A 10 cm block whose lowest nodes are at z = 0 and a 4 cm box collider whose lower face is
// 0.5 cm below the block's top node layer.
struct BoxInsideABlock : ::testing::Test {
  void SetUp() override {
    AddBody(&world, "block", SmallBlock(Eigen::Vector3d(0, 0, 0)));
    Collider box;
    box.shape = ColliderShape::Box(Eigen::Vector3d::Constant(0.04));
    box.pose.translation() = Eigen::Vector3d(0.05, 0.05, 0.09);
    world.colliders.push_back(box);
  }
  WorldState world{WorldOptions{}};
  ColliderEntries entries{&world};
};

TEST_F(BoxInsideABlock, TheWayOutIsUp) {
  const Collider& box = world.colliders.front();
  EXPECT_GT(entries.DeepestBorderOverlap(box, box.pose, true), 0.0);
  const Eigen::Vector3d out = entries.WayOutOfBodies(box, box.pose);
  EXPECT_GT(out.z(), 0.99) << out.transpose();
}

TEST_F(BoxInsideABlock, TheEntryStartsClearAndShrinksAtTheRecoverySpeed) {
  const double dt = 1e-3;
  const std::vector<Eigen::Isometry3d> poses{world.colliders.front().pose};
  const std::vector<Eigen::Isometry3d> entered = entries.Begin(dt, poses);
  const ColliderEntry& entry = entries.entry(0);
  const double depth = (entered[0].translation() - poses[0].translation()).norm();
  EXPECT_GT(depth, 0.0);
  // No collision sphere touches the collider where the substeps start.
  EXPECT_LE(entries.DeepestBorderOverlap(world.colliders.front(), entered[0], false), 0.0);
  // Pressed back in over the step at min(max speed, depth / recovery time).
  const double speed = std::min(world.options.penetration_max_speed,
                                depth / world.options.penetration_recovery_time);
  EXPECT_NEAR(entry.depth_after, depth - dt * speed, 1e-12);
  EXPECT_NEAR(world.colliders.front().linear_velocity.z(), -speed, 1e-9);
  entries.End(true);
  EXPECT_EQ(world.colliders.front().linear_velocity, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(entries.entry(0).depth, depth - dt * speed);
}

TEST_F(BoxInsideABlock, ARejectedStepLeavesTheEntryWhereItWas) {
  entries.Begin(1e-3, {world.colliders.front().pose});
  entries.End(false);
  EXPECT_EQ(entries.entry(0).depth, 0.0);
  EXPECT_EQ(world.colliders.front().linear_velocity, Eigen::Vector3d::Zero());
}

TEST_F(BoxInsideABlock, AColliderOutsideNeedsNoEntry) {
  world.colliders.front().pose.translation().z() = 0.2;
  const std::vector<Eigen::Isometry3d> poses{world.colliders.front().pose};
  const std::vector<Eigen::Isometry3d> entered = entries.Begin(1e-3, poses);
  EXPECT_TRUE(entered[0].isApprox(poses[0]));
  EXPECT_EQ(entries.entry(0).depth_after, 0.0);
  EXPECT_LT(entries.DeepestBorderOverlap(world.colliders.front(), poses[0], false), 0.0);
}

}  // namespace
}  // namespace msm_sim::core::internal
