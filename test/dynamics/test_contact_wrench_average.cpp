// Averaging contact wrenches over a publication interval (the ROS contact report), against
// values worked out by hand.
#include <gtest/gtest.h>
#include <Eigen/Core>

#include "msm_sim/dynamics/contact_point_average.h"
#include "msm_sim/dynamics/contact_wrench_average.h"

namespace msm_sim::core {
namespace {

ContactWrench Wrench(const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                     const Eigen::Vector3d& centroid, int microcollisions) {
  ContactWrench wrench;
  wrench.force = force;
  wrench.torque = torque;
  wrench.centroid = centroid;
  wrench.microcollisions = microcollisions;
  return wrench;
}

void ExpectNear(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected) {
  EXPECT_LT((actual - expected).norm(), 1e-12)
      << actual.transpose() << " instead of " << expected.transpose();
}

// Force and torque: the time-weighted mean; centroid: weighted by impulse |force| dt.
TEST(ContactWrenchAverage, IsTheTimeWeightedMean) {
  ContactWrenchAverage average;
  average.Add(Wrench({1, 0, 0}, {0, 0, 2}, {0, 0, 0}, 3), 0.1);
  average.Add(Wrench({0, 0, 3}, {0, 1, 0}, {1, 1, 0}, 5), 0.3);
  EXPECT_NEAR(average.seconds(), 0.4, 1e-15);
  EXPECT_EQ(average.microcollisions(), 8);
  const ContactWrench mean = average.Average();
  ExpectNear(mean.force, Eigen::Vector3d(0.1 * 1, 0, 0.3 * 3) / 0.4);   // (0.25, 0, 2.25)
  ExpectNear(mean.torque, Eigen::Vector3d(0, 0.3 * 1, 0.1 * 2) / 0.4);  // (0, 0.75, 0.5)
  ExpectNear(mean.centroid, (0.1 * Eigen::Vector3d(0, 0, 0) + 0.9 * Eigen::Vector3d(1, 1, 0)));
  EXPECT_EQ(mean.microcollisions, 8);
}

// A contact during half of the interval averages to half its force; its centroid is where it
// pressed.
TEST(ContactWrenchAverage, CountsStepsWithoutContact) {
  ContactWrenchAverage average;
  average.Add(Wrench({0, 0, 4}, {0, 0, 0}, {0.5, 0, 0}, 2), 0.01);
  average.Add(ContactWrench{}, 0.01);
  const ContactWrench mean = average.Average();
  ExpectNear(mean.force, Eigen::Vector3d(0, 0, 2));
  ExpectNear(mean.centroid, Eigen::Vector3d(0.5, 0, 0));
  EXPECT_EQ(mean.microcollisions, 2);
}

TEST(ContactWrenchAverage, WithoutImpulseTheCentroidIsZero) {
  ContactWrenchAverage average;
  average.Add(Wrench({0, 0, 0}, {0, 0, 0}, {1, 2, 3}, 0), 0.01);
  ExpectNear(average.Average().centroid, Eigen::Vector3d::Zero());
}

TEST(ContactWrenchAverage, ResetStartsANewInterval) {
  ContactWrenchAverage average;
  average.Add(Wrench({1, 2, 3}, {4, 5, 6}, {1, 1, 1}, 7), 0.5);
  average.Reset();
  EXPECT_EQ(average.seconds(), 0.0);
  EXPECT_EQ(average.microcollisions(), 0);
  average.Add(Wrench({0, 0, 1}, {0, 0, 0}, {2, 0, 0}, 1), 0.25);
  const ContactWrench mean = average.Average();
  ExpectNear(mean.force, Eigen::Vector3d(0, 0, 1));
  ExpectNear(mean.torque, Eigen::Vector3d::Zero());
  ExpectNear(mean.centroid, Eigen::Vector3d(2, 0, 0));
  EXPECT_EQ(mean.microcollisions, 1);
}

// A force (0, 0, 1) through the old origin has no torque there; about a new origin 1 m along x
// (offset = old - new = (-1, 0, 0)) its torque is r x F = (-1, 0, 0) x (0, 0, 1) = (0, 1, 0).
TEST(ContactWrenchAverage, MoveTorqueAddsTheLeverArm) {
  ExpectNear(MoveTorque({0, 0, 0}, {0, 0, 1}, {-1, 0, 0}), Eigen::Vector3d(0, 1, 0));
  ExpectNear(MoveTorque({0.5, 0, 0}, {0, 0, 1}, {0, 0, 0}), Eigen::Vector3d(0.5, 0, 0));
  ExpectNear(MoveTorque({0, 0, 0}, {0, 0, 1}, {0, 0, 2}), Eigen::Vector3d::Zero());  // along F
}

// Two collision elements of one link, 1 m either side of the link origin along x, pushed up by
// 1 N and 3 N over the same two steps: the link gets 4 N and the torque of the lever arms,
// (1, 0, 0) x (0, 0, 1) + (-1, 0, 0) x (0, 0, 3) = (0, -1, 0) + (0, 3, 0) = (0, 2, 0).
TEST(ContactWrenchAverage, AddMovedSumsPartsAboutANewOrigin) {
  ContactWrenchAverage a, b, link;
  for (int step = 0; step < 2; ++step) {
    a.Add(Wrench({0, 0, 1}, {0, 0, 0}, {1, 0, 0}, 1), 0.1);
    b.Add(Wrench({0, 0, 3}, {0, 0, 0}, {-1, 0, 0}, 2), 0.1);
  }
  link.AddMoved(a, Eigen::Vector3d(1, 0, 0));
  link.AddMoved(b, Eigen::Vector3d(-1, 0, 0));
  EXPECT_NEAR(link.seconds(), 0.2, 1e-15);  // the same interval, not the parts' sum
  EXPECT_EQ(link.microcollisions(), 6);
  const ContactWrench mean = link.Average();
  ExpectNear(mean.force, Eigen::Vector3d(0, 0, 4));
  ExpectNear(mean.torque, Eigen::Vector3d(0, 2, 0));
  ExpectNear(mean.centroid, Eigen::Vector3d((1.0 * 1 + 3.0 * -1) / 4.0, 0, 0));
}

// The patch: the normal weighted by normal force and time, force and area by time, the pressure
// their ratio: 0.1 s of 2 N on 0.01 m^2 along z, 0.3 s of 1 N on 0.03 m^2 along x.
TEST(ContactWrenchAverage, PatchIsTheTimeWeightedMean) {
  ContactWrench up, side;
  up.normal = Eigen::Vector3d::UnitZ();
  up.normal_force = 2.0;
  up.area = 0.01;
  side.normal = Eigen::Vector3d::UnitX();
  side.normal_force = 1.0;
  side.area = 0.03;
  ContactWrenchAverage average;
  average.Add(up, 0.1);
  average.Add(side, 0.3);
  average.Add(ContactWrench{}, 0.1);  // a step without contact
  const ContactWrench mean = average.Average();
  ExpectNear(mean.normal, Eigen::Vector3d(0.3, 0, 0.2).normalized());
  EXPECT_NEAR(mean.normal_force, 0.5 / 0.5, 1e-12);
  EXPECT_NEAR(mean.area, 0.01 / 0.5, 1e-12);
  EXPECT_NEAR(mean.mean_pressure, 0.5 / 0.01, 1e-9);  // N s / (m^2 s)
}

ContactPoint Point(int collider, NodeIndex node, const Eigen::Vector3d& point,
                   double normal_impulse, const Eigen::Vector3d& tangential) {
  ContactPoint contact;
  contact.collider = collider;
  contact.node = node;
  contact.point = point;
  contact.normal = Eigen::Vector3d::UnitZ();
  contact.normal_impulse = normal_impulse;
  contact.tangential_impulse = tangential;
  return contact;
}

// Points merge per (body, collider, node): impulses summed over the interval's seconds, the
// position weighted by |impulse|; a reset empties the average and the same node starts afresh.
TEST(ContactPointAverage, MergesPerBodyColliderAndNode) {
  ContactPointAverage average;
  for (int pass = 0; pass < 2; ++pass) {
    average.AddStep(0.1);
    average.Add(0, 5,
                {Point(0, 3, {0, 0, 0}, 1.0, {0, 0, 0}), Point(1, 3, {1, 0, 0}, 2.0, {0, 0, 0})});
    average.Add(1, 4, {Point(0, 3, {2, 0, 0}, 4.0, {0, 0, 0})});
    average.AddStep(0.1);
    average.Add(0, 5, {Point(0, 3, {0, 3, 0}, 3.0, {0, 0, 0})});
    ASSERT_EQ(average.size(), 3u);
    EXPECT_NEAR(average.seconds(), 0.2, 1e-15);
    const ContactPointAverage::Point first = average.Average(0);
    EXPECT_EQ(first.body, 0);
    EXPECT_EQ(first.collider, 0);
    EXPECT_EQ(first.node, 3);
    ExpectNear(first.force, Eigen::Vector3d(0, 0, -4.0 / 0.2));
    ExpectNear(first.position, Eigen::Vector3d(0, 3.0 * 3 / 4.0, 0));
    ExpectNear(first.normal, Eigen::Vector3d::UnitZ());
    EXPECT_EQ(average.Average(1).collider, 1);
    EXPECT_EQ(average.Average(2).body, 1);
    average.Reset();
    EXPECT_EQ(average.size(), 0u);
  }
  // Friction: the tangential impulse counts in the force, not in the normal.
  average.AddStep(0.5);
  average.Add(0, 5, {Point(0, 1, {0, 0, 0}, 1.0, {0.5, 0, 0})});
  ExpectNear(average.Average(0).force, Eigen::Vector3d(1.0, 0, -2.0));
  ExpectNear(average.Average(0).normal, Eigen::Vector3d::UnitZ());
}

}  // namespace
}  // namespace msm_sim::core
