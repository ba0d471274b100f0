#pragma once
// The rejected-step check both integrators' tests share (test_dynamics.cpp,
// test_implicit_contacts.cpp).
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {

// Pushes `body` with an absurd force (1e12 N along x, at `point` within `radius`) and expects the
// 1 ms step refused for the speed it would give, with the state and the time kept; the next step
// goes on from the kept state.
inline void ExpectAbsurdForceRejectedAndStateKept(World* world, int body,
                                                  const Eigen::Vector3d& point, double radius) {
  const State before = world->state(body);
  const double time = world->time();
  world->ApplyForce(body, point, Eigen::Vector3d(1e12, 0.0, 0.0), radius, 0.0);
  const StepReport report = world->Step(1e-3);
  EXPECT_FALSE(report.accepted);
  EXPECT_NE(report.reason.find("m/s"), std::string::npos) << report.reason;
  EXPECT_EQ(world->state(body).positions, before.positions);
  EXPECT_EQ(world->state(body).velocities, before.velocities);
  EXPECT_EQ(world->time(), time);
  EXPECT_TRUE(world->Step(1e-3).accepted);
}

}  // namespace msm_sim::core
