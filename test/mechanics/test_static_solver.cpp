#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e4, 0.25, 1000.0);

TEST(StaticSolver, ChainUnderEndLoadStretchesLikeSeriesSprings) {
  // Four springs in series along x, node 0 fixed, a 2 N pull at the free end.
  ModelBuilder builder(kMaterial);
  for (int i = 0; i < 5; ++i) builder.AddNode({0.1 * i, 0, 0}, 1.0);
  for (int i = 0; i < 4; ++i) builder.AddSpring(i, i + 1, 100.0);
  const Model model = builder.Build(1.0, 0.1);
  DofConstraints constraints(model.num_nodes());
  constraints.FixNode(0);
  for (int i = 1; i < 5; ++i) {  // keep the chain on its axis
    constraints.FixDof(i, 1);
    constraints.FixDof(i, 2);
  }
  Eigen::Matrix3Xd external = Eigen::Matrix3Xd::Zero(3, 5);
  external(0, 4) = 2.0;
  Eigen::Matrix3Xd x = model.rest_positions();
  StaticSolverOptions options;
  options.force_tolerance = 1e-10;
  const StaticSolverReport report =
      SolveStaticEquilibrium(model, constraints, external, options, &x);
  ASSERT_TRUE(report.converged) << report.message;
  EXPECT_LE(report.max_residual_force, 1e-10);
  for (int i = 1; i < 5; ++i) EXPECT_NEAR(x(0, i) - 0.1 * i, i * 2.0 / 100.0, 1e-10);
  EXPECT_EQ(x(0, 0), 0.0);
}

TEST(StaticSolver, PrescribedDisplacementReachesToleranceOnALattice) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(1.0, 0.5, 0.5);
  lattice_options.lattice.spacing = 0.1;
  const Model model = BuildCubicLattice(kMaterial, lattice_options);
  DofConstraints constraints(model.num_nodes());
  Eigen::Matrix3Xd x = model.rest_positions();
  for (int i = 0; i < model.num_nodes(); ++i) {
    if (x(0, i) < 0.1) constraints.FixNode(i);
    if (x(0, i) > 0.9) {  // twist-and-pull the far end: a genuinely non-linear problem
      constraints.FixNode(i);
      x(0, i) += 0.05;
      x(1, i) += 0.2 * (x(2, i) - 0.25);
    }
  }
  StaticSolverOptions options;
  options.force_tolerance = 1e-8;
  const StaticSolverReport report = SolveStaticEquilibrium(
      model, constraints, Eigen::Matrix3Xd::Zero(3, model.num_nodes()), options, &x);
  ASSERT_TRUE(report.converged) << report.message;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  ForceEvaluator(model).AccumulateForces(x, &f);
  for (int i = 0; i < model.num_nodes(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!constraints.is_fixed(3 * i + axis)) {
        EXPECT_LE(std::abs(f(axis, i)), 1e-8);
      }
    }
  }
}

TEST(StaticSolver, ReportsNonConvergenceInsteadOfPretending) {
  ModelBuilder builder(kMaterial);
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({1, 0, 0}, 1.0);
  builder.AddSpring(0, 1, 1.0);
  const Model model = builder.Build(1.0, 1.0);
  DofConstraints constraints(2);
  constraints.FixNode(0);
  Eigen::Matrix3Xd x = model.rest_positions();
  x(0, 1) = 1.5;
  StaticSolverOptions options;
  options.max_newton_iterations = 0;
  const StaticSolverReport report =
      SolveStaticEquilibrium(model, constraints, Eigen::Matrix3Xd::Zero(3, 2), options, &x);
  EXPECT_FALSE(report.converged);
  EXPECT_NEAR(report.max_residual_force, 0.5, 1e-12);
  EXPECT_NE(report.message.find("did not converge"), std::string::npos);
}

}  // namespace
}  // namespace msm_sim::core
