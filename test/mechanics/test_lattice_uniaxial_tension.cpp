// The reduction of a cubic lattice's uniaxial tension to one cell (LatticeUniaxialTension,
// docs/physics.md §4.1) against the lattice itself stretched to large strain by the static
// solver, for the linear (alpha = 1) and carrier (alpha = -1) laws and a fitted (alpha, beta),
// all three run by the simulator's force loops.

#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/dof_constraints.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/lattice_uniaxial_tension.h"
#include "msm_sim/mechanics/momentum_flow.h"
#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model_transform.h"

namespace msm_sim::core {
namespace {

constexpr double kYoungs = 1e5;
constexpr double kSpacing = 0.05;  // 20 x 10 x 10 cells

struct LatticeReading {
  bool converged = false;
  double nominal_stress = 0.0;   // Pa: force through the middle plane over Ly Lz
  double lateral_stretch = 0.0;  // the middle node's distance to the axis, over its rest one
};

// A node-centred block stretched along x: the end node layers moved affinely, free in y and z,
// the rest in static equilibrium, reached in strain steps of 0.05, each started from the last
// equilibrium stretched on by the reduction's increment (so that the fitted law reaches 100 %).
// `power` is the (alpha, beta) of SpringLaw::kPower.
LatticeReading StretchLattice(SpringLaw spring_law, double poisson, double strain,
                              const PowerSpringLaw& power) {
  const Eigen::Vector3d size(1.0, 0.5, 0.5);
  CubicLatticeOptions options;
  options.size = size;
  options.lattice.spacing = kSpacing;
  const Model model = WithSpringLaw(
      BuildCubicLattice(Material::FromYoungsPoisson(kYoungs, poisson, 1000.0), options), spring_law,
      power);
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const Eigen::Vector3d centre = 0.5 * size;
  const PowerSpringLaw law = model.power_spring_law();
  DofConstraints constraints(model.num_nodes());
  for (int i = 0; i < model.num_nodes(); ++i) {
    if (rest(0, i) < kSpacing || rest(0, i) > size.x() - kSpacing) constraints.FixDof(i, 0);
  }
  Eigen::Matrix3Xd positions = rest;
  LatticeReading reading;
  StaticSolverOptions solver;
  solver.force_tolerance = 1e-9 * kYoungs * kSpacing * kSpacing;
  const int steps = static_cast<int>(std::ceil(strain / 0.05 - 1e-9));
  Eigen::Vector3d previous(1.0, 1.0, 1.0);  // the stretches of the last step's start
  for (int step = 1; step <= steps; ++step) {
    const double e = strain * step / steps;
    const double lateral = LatticeUniaxialTension(e, kYoungs, poisson, law).lateral_stretch;
    const Eigen::Vector3d stretches(1.0 + e, lateral, lateral);
    // Each step starts from the last equilibrium stretched on by the reduction's increment.
    for (int i = 0; i < model.num_nodes(); ++i) {
      const Eigen::Vector3d d = positions.col(i) - centre;
      positions.col(i) = centre + stretches.cwiseQuotient(previous).cwiseProduct(d);
    }
    previous = stretches;
    const StaticSolverReport report = SolveStaticEquilibrium(
        model, constraints, Eigen::Matrix3Xd::Zero(3, model.num_nodes()), solver, &positions);
    reading.converged = report.converged;
    if (!reading.converged) {
      std::cout << "static solver stopped at strain " << e << ": " << report.message << " ("
                << report.newton_iterations << " Newton iterations, residual "
                << report.max_residual_force << " N)\n";
      return reading;
    }
  }
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  evaluator.AccumulateForces(positions, &forces);
  const Eigen::Vector3d flow =
      MomentumFlowThroughPlane(model, positions, evaluator.total_tensions(),
                               MaterialPlane{centre, Eigen::Vector3d::UnitX()});
  reading.nominal_stress = flow.x() / (size.y() * size.z());
  // The lateral stretch of the middle cross-section: the spread of its nodes in y.
  double rest_spread = 0.0, spread = 0.0;
  for (int i = 0; i < model.num_nodes(); ++i) {
    if (std::abs(rest(0, i) - centre.x()) > 0.6 * kSpacing) continue;
    rest_spread += std::abs(rest(1, i) - centre.y());
    spread += std::abs(positions(1, i) - positions.row(1).mean());
  }
  reading.lateral_stretch = spread / rest_spread;
  return reading;
}

// The block's force is its small-strain reading times the reduction's non-linear response: the
// finite block (10 cells across, its end layers held along x) reads a few per cent stiff
// already at 1 % strain, a finite-size effect that shrinks as the block grows; beyond it the
// reduction must follow the lattice within 1.5 %, and the middle section's lateral stretch too.
void ExpectReductionFollowsLattice(SpringLaw spring_law, double poisson, double strain,
                                   const PowerSpringLaw& power = {}) {
  const LatticeReading small = StretchLattice(spring_law, poisson, 0.01, power);
  const LatticeReading lattice = StretchLattice(spring_law, poisson, strain, power);
  ASSERT_TRUE(small.converged);
  ASSERT_TRUE(lattice.converged);
  PowerSpringLaw law{spring_law == SpringLaw::kLinear ? 1.0 : -1.0, 0.0};
  if (spring_law == SpringLaw::kPower) law = power;
  const LatticeTensionState cell_small = LatticeUniaxialTension(0.01, kYoungs, poisson, law);
  const LatticeTensionState cell = LatticeUniaxialTension(strain, kYoungs, poisson, law);
  const double small_ratio = small.nominal_stress / cell_small.nominal_stress;
  EXPECT_NEAR(small_ratio, 1.0, 0.05);
  EXPECT_NEAR(lattice.nominal_stress / cell.nominal_stress / small_ratio, 1.0, 0.015)
      << "strain " << strain << ", nu " << poisson;
  EXPECT_NEAR(lattice.lateral_stretch / cell.lateral_stretch, 1.0, 0.015);
  std::cout << "strain " << strain << " nu " << poisson << ": lattice / reduction "
            << lattice.nominal_stress / cell.nominal_stress << " (at 1 %: " << small_ratio
            << "), lateral " << lattice.lateral_stretch / cell.lateral_stretch << "\n";
}

TEST(LatticeUniaxialTension, SmallStrainGivesTheCalibratedModulus) {
  for (const double nu : {0.25, 0.45, 0.49}) {
    for (const double alpha : {1.0, -1.0, -4.0}) {
      const LatticeTensionState state =
          LatticeUniaxialTension(1e-5, kYoungs, nu, PowerSpringLaw{alpha, 0.3});
      EXPECT_NEAR(state.nominal_stress / (kYoungs * 1e-5), 1.0, 1e-3) << nu << " " << alpha;
      EXPECT_NEAR((1.0 - state.lateral_stretch) / 1e-5, nu, 1e-3);
    }
  }
}

TEST(LatticeUniaxialTension, FollowsTheLatticeWithCarrierSprings) {
  ExpectReductionFollowsLattice(SpringLaw::kNonlinear, 0.45, 0.5);
}

// The fit's law for Ecoflex 00-30 (docs/materials.md) run by the force loops on the block.
TEST(LatticeUniaxialTension, FollowsTheLatticeWithAFittedPowerLaw) {
  const PowerSpringLaw fitted{-4.54, 0.116};
  ExpectReductionFollowsLattice(SpringLaw::kPower, 0.45, 0.3, fitted);
  ExpectReductionFollowsLattice(SpringLaw::kPower, 0.45, 1.0, fitted);
}

TEST(LatticeUniaxialTension, FollowsTheLatticeWithLinearSprings) {
  ExpectReductionFollowsLattice(SpringLaw::kLinear, 0.45, 0.5);
  ExpectReductionFollowsLattice(SpringLaw::kLinear, 0.25, 1.0);
}

}  // namespace
}  // namespace msm_sim::core
