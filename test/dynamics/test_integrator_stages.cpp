// The substep's per-node stages (src/dynamics/node_stages.h) and the implicit kick's contact
// holds (src/dynamics/implicit_integrator.h), each on its own.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "dynamics/collider_contacts.h"
#include "dynamics/implicit_integrator.h"
#include "dynamics/node_stages.h"
#include "internal_world.h"

namespace msm_sim::core::internal {
namespace {

struct OneBlock : ::testing::Test {
  void SetUp() override {
    Body& body = AddBody(&world, "block", SmallBlock(Eigen::Vector3d::Zero()));
    body.state.velocities = Eigen::Matrix3Xd::Random(3, body.model->num_nodes());
  }
  Body& block() { return world.bodies.front(); }
  WorldState world{WorldOptions{}};
};

TEST_F(OneBlock, AHalfDriftMovesByHalfTheStepAndSavesWhenAsked) {
  const Eigen::Matrix3Xd x = block().state.positions, v = block().state.velocities;
  block().saved_positions.resize(3, x.cols());
  block().saved_velocities.resize(3, x.cols());
  DriftHalf(&block(), 0.2, {}, 0, block().model->num_nodes(), true);
  EXPECT_EQ(block().saved_positions, x);
  EXPECT_EQ(block().saved_velocities, v);
  EXPECT_LT((block().state.positions - (x + 0.1 * v)).cwiseAbs().maxCoeff(), 1e-15);
}

TEST_F(OneBlock, PendingRestitutionAppliesOnceToItsNodes) {
  const Eigen::Matrix3Xd v = block().state.velocities;
  block().pending = {{3, Eigen::Vector3d(0, 0, 1)}, {7, Eigen::Vector3d(1, 0, 0)}};
  ApplyPendingRestitution(&block(), block().pending, 0, 5);  // node 3 only
  EXPECT_EQ(block().state.velocities.col(3), Eigen::Vector3d(v.col(3) + Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(block().state.velocities.col(7), v.col(7));
  EXPECT_EQ(block().pending.size(), 2u);
  ApplyPendingRestitution(&block());
  EXPECT_TRUE(block().pending.empty());
}

TEST_F(OneBlock, TheDriftNotesANodeFasterThanTheLimitOrNotFinite) {
  block().state.velocities.setZero();
  block().state.velocities(1, 11) = 30.0;
  DriftHalfNotingFastest(&block(), 1e-4, 0.0, 10.0);
  EXPECT_EQ(block().fastest_node, 11);
  EXPECT_DOUBLE_EQ(block().fastest_speed_sq, 900.0);
  block().state.velocities(0, 5) = std::numeric_limits<double>::quiet_NaN();
  DriftHalfNotingFastest(&block(), 1e-4, 0.0, 10.0);
  EXPECT_EQ(block().fastest_node, 5);
  EXPECT_EQ(block().fastest_speed_sq, std::numeric_limits<double>::infinity());
}

TEST_F(OneBlock, PushesAddToTheirNodesOnly) {
  block().forces.setZero();
  block().pushes.push_back({{2, 9}, {Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0, 0, -1)}, 0.0});
  AddPushes(&block(), 0, 5);
  EXPECT_EQ(block().forces.col(2), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(block().forces.col(9), Eigen::Vector3d::Zero());
}

ContactNormal Held(NodeIndex node, double friction) {
  return {node,
          Eigen::Vector3d::UnitZ(),
          Eigen::Vector3d::Zero(),
          Eigen::Vector3d::Zero(),
          0,
          0.0,
          friction,
          0.0,
          0.0,
          FrictionHold::kStuck,
          Eigen::Vector3d::Zero()};
}

TEST(ImplicitContactHolds, AStickLeavesTheConeWithItsCoulombImpulse) {
  const ContactNormal contact = Held(0, 0.5);
  // Normal 2 N s, tangential 0.8 N s: within mu 2 = 1, it holds.
  EXPECT_EQ(ImplicitIntegrator::SlidingImpulseOfStick(contact, Eigen::Vector3d(0.8, 0, 2)),
            Eigen::Vector3d::Zero());
  // Tangential 3 N s: slides with 1 N s along it.
  EXPECT_LT((ImplicitIntegrator::SlidingImpulseOfStick(contact, Eigen::Vector3d(0, 3, 2)) -
             Eigen::Vector3d(0, 1, 0))
                .norm(),
            1e-15);
}

TEST(ImplicitContactHolds, AStickSlidesOnlyOnceItLeavesTheConeByMoreThanTheSlidesTolerance) {
  // A stick at the cone's edge must not flip to sliding in a pass (and back in the next, a solve
  // each): the passes let it leave the cone by the tolerance a slide's limit keeps (2 %).
  std::vector<ContactNormal> held{Held(0, 0.5), Held(1, 0.5)};
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 2), dv = Eigen::Matrix3Xd::Zero(3, 2);
  Eigen::Matrix3Xd residual(3, 2);  // the holds' impulses are -residual: normal 2 N s each
  residual.col(0) = -Eigen::Vector3d(1.01, 0, 2);  // 1 % past mu 2 = 1 N s
  residual.col(1) = -Eigen::Vector3d(0, 1.03, 2);  // 3 % past it
  EXPECT_TRUE(ImplicitIntegrator::UpdateFrictionHolds(v, dv, residual, &held));
  EXPECT_EQ(held[0].friction_hold, FrictionHold::kStuck);
  EXPECT_EQ(held[1].friction_hold, FrictionHold::kSliding);
  EXPECT_LT((held[1].sliding_impulse - Eigen::Vector3d(0, 1, 0)).norm(), 1e-15);
  // Once the kick is done, a stick past the exact cone starts the next kick sliding.
  EXPECT_GT(ImplicitIntegrator::SlidingImpulseOfStick(held[0], -residual.col(0)).norm(), 0.0);
}

TEST(ImplicitContactHolds, ASphereOnTheSurfaceToRoundingTouchesAndOneAboveItIsSpeculative) {
  // A held node ends its kick on the surface only to rounding; had that left it speculative, a
  // second solve would hold it again in every kick.
  WorldState world{WorldOptions{}};
  world.colliders.push_back(Collider{});  // the plane z = 0
  Body& body = AddBody(&world, "block", SmallBlock(Eigen::Vector3d::Zero()));
  const double h = 1e-3;
  const NodeIndex low = body.border.nodes.front(), raised = body.border.nodes.back();
  const double radius = body.border.radii.front(), raised_radius = body.border.radii.back();
  for (NodeIndex node = 0; node < body.model->num_nodes(); ++node)
    body.state.positions(2, node) += 1.0;
  body.state.positions(2, low) = std::nextafter(std::nextafter(radius, 1.0), 1.0);
  body.state.positions(2, raised) = 1.5 * raised_radius;
  ColliderContacts contacts(&world);
  const std::vector<ContactNormal> found =
      ImplicitIntegrator(&world, &contacts).DeepestColliderContacts(body, h);
  ASSERT_EQ(found.size(), 2u);
  for (const ContactNormal& contact : found) {
    if (contact.node == low) {
      EXPECT_EQ(contact.closing_speed, 0.0);
    } else {
      EXPECT_NEAR(contact.closing_speed, 0.5 * raised_radius / h, 1e-12);
    }
  }
}

TEST(ImplicitContactHolds, AHoldThatPullsIsReleased) {
  std::vector<ContactNormal> held{Held(0, 0.5), Held(1, 0.5)};
  Eigen::Matrix3Xd residual = Eigen::Matrix3Xd::Zero(3, 2);
  residual(2, 0) = -1.0;  // the hold pushed node 0 out (impulse = -residual)
  residual(2, 1) = 1.0;   // and pulled node 1 in
  EXPECT_TRUE(ImplicitIntegrator::ReleasePullingContacts(residual, &held));
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].node, 0);
  EXPECT_FALSE(ImplicitIntegrator::ReleasePullingContacts(residual, &held));
}

TEST(ImplicitContactHolds, ASpeculativeContactIsHeldOnceItsNodeWouldReachTheSurface) {
  ContactNormal near = Held(0, 0.0), far = Held(1, 0.0);
  near.holding_speed = far.holding_speed = 1.0;
  std::vector<ContactNormal> speculative{near, far}, held;
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, 2);
  Eigen::Matrix3Xd dv = Eigen::Matrix3Xd::Zero(3, 2);
  dv(2, 0) = -2.0;  // node 0 would approach at 2 m/s, node 1 not at all
  EXPECT_TRUE(ImplicitIntegrator::HoldReachingContacts(v, dv, &speculative, &held));
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].node, 0);
  ASSERT_EQ(speculative.size(), 1u);
  EXPECT_EQ(speculative[0].node, 1);
}

}  // namespace
}  // namespace msm_sim::core::internal
