// PairContacts (src/dynamics/pair_contacts.h): touching border nodes of two bodies stop
// approaching each other, their momentum kept, and bodies apart are not searched at all.
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "dynamics/pair_contacts.h"
#include "internal_world.h"

namespace msm_sim::core::internal {
namespace {

Eigen::Vector3d Momentum(const Body& body) { return body.state.velocities * body.model->masses(); }

// Two blocks side by side along x, `gap` (m) between their outer node layers, closing at 2 m/s.
struct TwoBlocks : ::testing::Test {
  void Place(double gap) {
    world.bodies.clear();
    world.bodies.reserve(2);
    BodyOptions options;
    options.restitution = 0.0;
    options.friction = 0.0;
    Body& left = AddBody(&world, "left", SmallBlock(Eigen::Vector3d(0, 0, 0)), options);
    Body& right = AddBody(&world, "right", SmallBlock(Eigen::Vector3d(0.075 + gap, 0, 0)), options);
    left.state.velocities.row(0).setConstant(1.0);
    right.state.velocities.row(0).setConstant(-1.0);
    world.substep = 1e-4;
  }
  WorldState world{WorldOptions{}};
  PairContacts pairs{&world};
};

TEST_F(TwoBlocks, BlocksApartHaveNoPairs) {
  Place(0.05);
  EXPECT_FALSE(pairs.MayHaveTouchingPairs());
  EXPECT_TRUE(pairs.FindTouchingPairs().empty());
}

TEST_F(TwoBlocks, TouchingFacesStopApproachingAndKeepTheMomentum) {
  Place(0.01);  // within the two collision spheres (about 1.3 cm each)
  ASSERT_TRUE(pairs.MayHaveTouchingPairs());
  const std::vector<PairContact> found = pairs.FindTouchingPairs();
  ASSERT_FALSE(found.empty());
  for (const PairContact& pair : found) EXPECT_NE(pair.body_i, pair.body_j);
  const Eigen::Vector3d momentum = Momentum(world.bodies[0]) + Momentum(world.bodies[1]);
  int microcollisions = 0;
  pairs.CollideNodes(&microcollisions);
  EXPECT_GT(microcollisions, 0);
  const Eigen::Vector3d after = Momentum(world.bodies[0]) + Momentum(world.bodies[1]);
  EXPECT_LT((after - momentum).norm(), 1e-12);
  // No touching pair approaches any more (e = 0: nothing pending either).
  for (const PairContact& pair : pairs.FindTouchingPairs()) {
    const Eigen::Vector3d vi = pair.body_i->state.velocities.col(pair.i);
    const Eigen::Vector3d vj = pair.body_j->state.velocities.col(pair.j);
    EXPECT_GE((vi - vj).dot(pair.normal), -1e-9);
  }
  EXPECT_TRUE(world.bodies[0].pending.empty());
}

TEST_F(TwoBlocks, ABodyTouchesItselfOnlyWhereItFolds) {
  Place(0.05);
  world.bodies.pop_back();
  world.bodies[0].options.self_collision = true;
  EXPECT_TRUE(pairs.MayHaveTouchingPairs());
  // At rest every node is near its neighbours: no pair of a body that has not folded.
  EXPECT_TRUE(pairs.FindTouchingPairs().empty());
}

}  // namespace
}  // namespace msm_sim::core::internal
