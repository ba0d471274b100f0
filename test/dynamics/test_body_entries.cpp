// BodyEntries (src/dynamics/body_entries.h): a body found with border node centres inside
// another is seen by the pair contacts moved out of it, to where no collision spheres touch, and
// pressed back in at the recovery speed (docs/physics.md §7.2, "A body found inside another").
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "dynamics/body_entries.h"
#include "dynamics/pair_contacts.h"
#include "internal_world.h"

namespace msm_sim::core::internal {
namespace {

// Two 10 cm blocks (2.5 cm spacing, 4 x 4 x 4 nodes), the second's lowest node at `corner`.
struct TwoSmallBlocks : ::testing::Test {
  void Place(const Eigen::Vector3d& corner) {
    world.bodies.clear();
    world.bodies.reserve(2);
    AddBody(&world, "first", SmallBlock(Eigen::Vector3d(0, 0, 0)));
    AddBody(&world, "second", SmallBlock(corner));
  }
  // The least distance between a border node of the first block and one of the second, seen
  // where the pair contacts see them, less their reach (m): < 0 where spheres overlap.
  double LeastClearance() const {
    const Body& a = world.bodies[0];
    const Body& b = world.bodies[1];
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < a.border.nodes.size(); ++i) {
      for (std::size_t j = 0; j < b.border.nodes.size(); ++j) {
        const Eigen::Vector3d d = a.state.positions.col(a.border.nodes[i]) + a.contact_offset -
                                  b.state.positions.col(b.border.nodes[j]) - b.contact_offset;
        least = std::min(least, d.norm() - a.border.radii[i] - b.border.radii[j]);
      }
    }
    return least;
  }
  double Reach() const { return 2.0 * world.bodies[0].border.radii[0]; }
  WorldState world{WorldOptions{}};
  BodyEntries entries{&world};
};

TEST_F(TwoSmallBlocks, TheFreeBodyEntersTheClampedOneElseTheLighterElseTheLater) {
  Place(Eigen::Vector3d(0, 0, 0.05));
  EXPECT_EQ(entries.Entering(0, 1), 1);
  world.bodies[1].constrained[0] = 1;
  EXPECT_EQ(entries.Entering(0, 1), 0);
  EXPECT_EQ(entries.Entering(1, 0), 0);
}

TEST_F(TwoSmallBlocks, BlocksRestingFaceToFaceDoNotOverlap) {
  // The second on the first, their spheres overlapping by 2 % of the reach as a resting pair.
  Place(Eigen::Vector3d(0, 0, 0.075));
  const double reach = Reach();
  Place(Eigen::Vector3d(0, 0, 0.075 + 0.98 * reach));
  EXPECT_FALSE(entries.Overlapping(1, Eigen::Vector3d::Zero(), 0));
  Place(Eigen::Vector3d(0.075 + 0.98 * reach, 0, 0));
  EXPECT_FALSE(entries.Overlapping(1, Eigen::Vector3d::Zero(), 0));
}

TEST_F(TwoSmallBlocks, CoincidentOrSunkBlocksOverlap) {
  Place(Eigen::Vector3d(0, 0, 0));
  EXPECT_TRUE(entries.Overlapping(1, Eigen::Vector3d::Zero(), 0));
  // The second's bottom layer on the first's second layer from the top: interior nodes.
  Place(Eigen::Vector3d(0.0125, 0.0125, 0.05));
  EXPECT_TRUE(entries.Overlapping(1, Eigen::Vector3d::Zero(), 0));
  // Seen moved up out of it, no longer.
  EXPECT_FALSE(entries.Overlapping(1, Eigen::Vector3d(0, 0, 0.06), 0));
}

TEST_F(TwoSmallBlocks, TheWayOutIsTheLeastTravelAndAgainstGravityOnATie) {
  Place(Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(entries.WayOut(1, 0), Eigen::Vector3d::UnitZ());
  // Overlapping by a quarter of its length along x: out along +x.
  Place(Eigen::Vector3d(0.05, 0.0, 0.0));
  EXPECT_EQ(entries.WayOut(1, 0), Eigen::Vector3d::UnitX());
  Place(Eigen::Vector3d(0.0, -0.06, 0.0));
  EXPECT_EQ(entries.WayOut(1, 0), -Eigen::Vector3d::UnitY());
}

TEST_F(TwoSmallBlocks, TheEntryStartsJustClearAndShrinksAtTheRecoverySpeed) {
  Place(Eigen::Vector3d(0, 0, 0.04));
  const double dt = 1e-3;
  entries.Begin(dt);
  const BodyEntry& entry = entries.entry(1);
  ASSERT_EQ(entry.other, 0);
  EXPECT_EQ(entry.direction, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(entries.entry(0).step_depth, 0.0);
  // Where the substeps start no collision spheres overlap, and one pair just touches.
  EXPECT_NEAR(LeastClearance(), 0.0, 1e-12);
  const double depth = entry.step_depth;
  const double speed = std::min(world.options.penetration_max_speed,
                                depth / world.options.penetration_recovery_time);
  EXPECT_NEAR(entry.depth_after, depth - dt * speed, 1e-12);
  EXPECT_NEAR(world.bodies[1].contact_offset_velocity.z(), -speed, 1e-9);
  entries.Place(0.5 * dt);
  EXPECT_NEAR(world.bodies[1].contact_offset.z(), depth - 0.5 * dt * speed, 1e-12);
  entries.End(true);
  EXPECT_EQ(world.bodies[1].contact_offset, Eigen::Vector3d::Zero());
  EXPECT_EQ(world.bodies[1].contact_offset_velocity, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(entries.entry(1).depth, depth - dt * speed);
}

TEST_F(TwoSmallBlocks, ARejectedStepLeavesTheEntryWhereItWas) {
  Place(Eigen::Vector3d(0, 0, 0.04));
  entries.Begin(1e-3);
  entries.End(false);
  EXPECT_EQ(entries.entry(1).depth, 0.0);
  EXPECT_EQ(world.bodies[1].contact_offset, Eigen::Vector3d::Zero());
}

TEST_F(TwoSmallBlocks, WithoutRecoveryThereIsNoEntry) {
  world.options.penetration_max_speed = 0.0;
  Place(Eigen::Vector3d(0, 0, 0.04));
  entries.Begin(1e-3);
  EXPECT_EQ(entries.entry(1).step_depth, 0.0);
  EXPECT_EQ(world.bodies[1].contact_offset, Eigen::Vector3d::Zero());
}

// Coincident border nodes have no line between them: their pair faces the way out of both
// bodies (their stars' difference), a unit vector, its overlap the whole reach. Sunk by two
// layers, the side faces' nodes coincide, the upper's bottom edge on the lower's mid-face.
TEST_F(TwoSmallBlocks, CoincidentNodesFaceTheWayOutOfBothBodies) {
  Place(Eigen::Vector3d(0, 0, 0.05));
  PairContacts pairs{&world};
  int coincident = 0;
  for (const PairContact& pair : pairs.FindTouchingPairs()) {
    ASSERT_TRUE(pair.normal.allFinite());
    EXPECT_NEAR(pair.normal.norm(), 1.0, 1e-12);
    if (pair.body_i->state.positions.col(pair.i) != pair.body_j->state.positions.col(pair.j)) {
      continue;
    }
    ++coincident;
    EXPECT_DOUBLE_EQ(pair.overlap, pair.reach);
    const Eigen::Vector3d out = NodeStar(*pair.body_i, pair.i) - NodeStar(*pair.body_j, pair.j);
    EXPECT_NEAR(pair.normal.dot(out.normalized()), 1.0, 1e-12);
  }
  EXPECT_GT(coincident, 0);
}

}  // namespace
}  // namespace msm_sim::core::internal
