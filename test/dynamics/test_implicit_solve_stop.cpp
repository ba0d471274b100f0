// The implicit solve's early stop (docs/physics.md §7.1, "Stopping the solve"): a body in motion
// stops the solve once its residual can no longer change the kinetic energy by more than 2 eta
// of it, and a body at rest solves to the full tolerance as before.
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

// A 4 x 4 x 2 cm rubber-like block (E 200 kPa, nu 0.49, rho 1100) at 5 mm.
std::shared_ptr<const Model> RubberBlock() {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.04, 0.04, 0.02);
  options.lattice.spacing = 0.005;
  return std::make_shared<Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.49, 1100.0), options));
}

struct OneStep {
  double kinetic_energy = 0.0;  // J, after the step
  int iterations = 0;
};

// One 1 ms implicit step of the block, free and without gravity, from `velocities`.
OneStep StepFrom(const std::shared_ptr<const Model>& model, const Eigen::Matrix3Xd& velocities,
                 double energy_tolerance) {
  WorldOptions options;
  options.integrator = Integrator::kImplicit;
  options.gravity = Eigen::Vector3d::Zero();
  options.implicit_energy_tolerance = energy_tolerance;
  World world(options);
  const int body = world.AddBody("block", model);
  State state = world.state(body);
  state.velocities = velocities;
  world.SetState(body, state);
  const StepReport report = world.Step(1e-3);
  EXPECT_TRUE(report.accepted) << report.reason;
  return {world.ComputeEnergies(body).kinetic, report.solver_iterations};
}

TEST(ImplicitSolveStop, AMovingBodyStopsEarlyWithinTheKineticEnergyBound) {
  const auto model = RubberBlock();
  const Eigen::Matrix3Xd& x = model->rest_positions();
  // A body carried at 0.5 m/s with a shear wave of 2 cm/s in it: the step loads its springs,
  // and the residual that is left matters little to its kinetic energy.
  Eigen::Matrix3Xd v(3, model->num_nodes());
  for (int i = 0; i < model->num_nodes(); ++i) {
    v.col(i) = Eigen::Vector3d(0.5 + 0.02 * std::sin(150.0 * x(2, i)),
                               0.02 * std::cos(90.0 * x(0, i)), 0.0);
  }
  const double eta = WorldOptions{}.implicit_energy_tolerance;
  const OneStep full = StepFrom(model, v, 0.0);
  const OneStep early = StepFrom(model, v, eta);
  std::printf(
      "  full solve: %d iterations, KE %.6g J; early stop: %d iterations, KE %.6g J (%+.2e)\n",
      full.iterations, full.kinetic_energy, early.iterations, early.kinetic_energy,
      early.kinetic_energy / full.kinetic_energy - 1.0);
  EXPECT_LT(early.iterations, full.iterations);
  EXPECT_LE(std::abs(early.kinetic_energy - full.kinetic_energy), 2.0 * eta * full.kinetic_energy);
}

TEST(ImplicitSolveStop, ABodyAtRestSolvesToTheFullTolerance) {
  const auto model = RubberBlock();
  const Eigen::Matrix3Xd rest = Eigen::Matrix3Xd::Zero(3, model->num_nodes());
  // At rest, without gravity, but squeezed: its springs drive the step, its momentum is zero.
  WorldOptions options;
  options.integrator = Integrator::kImplicit;
  options.gravity = Eigen::Vector3d::Zero();
  int iterations[2] = {0, 0};
  for (const double eta : {0.0, WorldOptions{}.implicit_energy_tolerance}) {
    options.implicit_energy_tolerance = eta;
    World world(options);
    const int body = world.AddBody("block", model);
    State state = world.state(body);
    state.positions.row(2) *= 0.99;
    world.SetState(body, state);
    iterations[eta > 0.0] = world.Step(1e-3).solver_iterations;
  }
  EXPECT_GT(iterations[0], 0);
  EXPECT_EQ(iterations[1], iterations[0]);
}

}  // namespace
}  // namespace msm_sim::core
