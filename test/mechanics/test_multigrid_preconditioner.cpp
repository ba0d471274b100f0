// The implicit step's multigrid V-cycle: its grids interpolate linear fields exactly, it is a
// symmetric preconditioner, and conjugate gradient with it needs few iterations, not growing as
// the lattice is refined, on a nearly incompressible block (docs/physics.md §7.1).
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "mechanics/masked_pcg.h"
#include "mechanics/multigrid_preconditioner.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core::internal {
namespace {

constexpr double kStep = 1e-3;
constexpr double kStepFactor = 0.5 * kStep * kStep;  // c = h^2 / 2, no dampers

Model Block(double spacing, double poisson) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.06, 0.06, 0.03);
  options.lattice.spacing = spacing;
  return BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), options);
}

Eigen::SparseMatrix<double> RestStiffness(const Model& model) {
  ForceEvaluator evaluator(model, DispersionPasses::kTwoPass, SpringKernels::kPerSpring);
  evaluator.Linearize(model.rest_positions(), GeometricStiffness::kDropCompression);
  return evaluator.StiffnessMatrix();
}

// M + c K at rest as a node-array operator, its inverse diagonal, and the bottom layer held.
struct RestSystem {
  std::shared_ptr<const Eigen::SparseMatrix<double>> matrix;
  NodeArrayOperator apply;
  Eigen::Matrix3Xd inverse_diagonal;
  DofProjection projection;
};

RestSystem SystemOf(const Model& model,
                    const Eigen::SparseMatrix<double>& stiffness = Eigen::SparseMatrix<double>()) {
  RestSystem system;
  Eigen::VectorXd masses(3 * model.num_nodes());
  for (int i = 0; i < model.num_nodes(); ++i) {
    masses.segment<3>(3 * i).setConstant(model.masses()[i]);
  }
  Eigen::SparseMatrix<double> a =
      kStepFactor * (stiffness.rows() > 0 ? stiffness : RestStiffness(model));
  a += Eigen::SparseMatrix<double>(masses.asDiagonal());
  system.matrix = std::make_shared<const Eigen::SparseMatrix<double>>(std::move(a));
  system.apply = [matrix = system.matrix](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    const Eigen::VectorXd product = *matrix * Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
    *out = Eigen::Map<const Eigen::Matrix3Xd>(product.data(), 3, v.cols());
  };
  const Eigen::VectorXd diagonal = system.matrix->diagonal();
  system.inverse_diagonal =
      Eigen::Map<const Eigen::Matrix3Xd>(diagonal.data(), 3, model.num_nodes()).cwiseInverse();
  system.projection.free = Eigen::Matrix3Xd::Ones(3, model.num_nodes());
  const double bottom = model.rest_positions().row(2).minCoeff();
  for (int i = 0; i < model.num_nodes(); ++i) {
    if (model.rest_positions()(2, i) < bottom + 1e-9) system.projection.free.col(i).setZero();
  }
  return system;
}

// The nodes the system holds (all three DOFs), as the World hands its kinematic nodes over.
std::vector<char> HeldNodes(const RestSystem& system) {
  std::vector<char> held(static_cast<std::size_t>(system.projection.free.cols()));
  for (Eigen::Index i = 0; i < system.projection.free.cols(); ++i) {
    held[static_cast<std::size_t>(i)] = system.projection.free.col(i).isZero() ? 1 : 0;
  }
  return held;
}

// Iterations of conjugate gradient on the gravity impulse, from rest, to the integrator's
// default tolerance.
int Iterations(const RestSystem& system, const Model& model,
               const MultigridPreconditioner* multigrid,
               const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  Eigen::Matrix3Xd b = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  b.row(2) = -9.81 * kStep * model.masses().transpose();
  system.projection.Apply(&b);
  MaskedPcgOptions options;
  options.relative_tolerance = 1e-4;
  options.max_iterations = 1000;
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, model.num_nodes()), residual;
  MaskedPcgReport report;
  if (multigrid) {
    const NodeArrayPreconditioner v_cycle = [&](const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd* z) {
      multigrid->Apply(system.apply, system.inverse_diagonal, system.projection, rotation, r, z);
    };
    report = SolveMaskedPcg(system.apply, b, system.projection, v_cycle, options, &x, &residual);
  } else {
    report = SolveMaskedPcg(system.apply, b, system.projection, system.inverse_diagonal, options,
                            &x, &residual);
  }
  EXPECT_TRUE(report.converged);
  return report.iterations;
}

TEST(MultigridPreconditioner, GridsInterpolateLinearFieldsOfARandomLattice) {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.3, 0.2, 0.2);
  options.lattice.spacing = 0.02;
  const Model model = BuildRandomLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), options);
  const MultigridPreconditioner multigrid(model, RestStiffness(model), {}, {2, 50});
  ASSERT_GE(multigrid.coarse_levels().size(), 2u);
  // Trilinear interpolation is exact on linear fields: each level's vertex positions (x, y and z
  // are linear fields), prolongated, are the positions of the level above, down to the nodes'.
  const auto& levels = multigrid.coarse_levels();
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const Eigen::Matrix3Xd& above = l == 0 ? model.rest_positions() : levels[l - 1].vertices;
    const Eigen::VectorXd prolongated =
        levels[l].prolongation *
        Eigen::Map<const Eigen::VectorXd>(levels[l].vertices.data(), levels[l].vertices.size());
    const Eigen::Map<const Eigen::VectorXd> expected(above.data(), above.size());
    EXPECT_LE((prolongated - expected).cwiseAbs().maxCoeff(), 1e-12) << "level " << l;
  }
}

TEST(MultigridPreconditioner, IsSymmetricAndPositiveForATurnedBody) {
  const Eigen::Matrix3d kTurn =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Model model = Block(0.006, 0.49);
  const RestSystem system = SystemOf(model);
  MultigridPreconditioner multigrid(model, RestStiffness(model), HeldNodes(system), {2, 50});
  multigrid.SetStepFactor(kStepFactor);
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  Eigen::Matrix3Xd y(3, model.num_nodes()), w(3, model.num_nodes()), by, bw;
  for (int i = 0; i < y.size(); ++i) y.data()[i] = normal(rng), w.data()[i] = normal(rng);
  system.projection.Apply(&y);
  system.projection.Apply(&w);
  multigrid.Apply(system.apply, system.inverse_diagonal, system.projection, kTurn, y, &by);
  multigrid.Apply(system.apply, system.inverse_diagonal, system.projection, kTurn, w, &bw);
  const double wby = w.cwiseProduct(by).sum();
  EXPECT_NEAR(wby, y.cwiseProduct(bw).sum(), 1e-10 * std::abs(wby));
  EXPECT_GT(y.cwiseProduct(by).sum(), 0.0);
}

TEST(MultigridPreconditioner, IterationsDoNotGrowWithRefinementAtNuNearOneHalf) {
  // Jacobi's count grows as 1 / spacing; the V-cycle's stays (docs/design/implicit-solver.md).
  int jacobi[2], multigrid_iterations[2];
  const double spacings[2] = {0.006, 0.003};
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(spacings[k]);
    const Model model = Block(spacings[k], 0.49);
    const RestSystem system = SystemOf(model);
    MultigridPreconditioner multigrid(model, RestStiffness(model), HeldNodes(system));
    multigrid.SetStepFactor(kStepFactor);
    jacobi[k] = Iterations(system, model, nullptr);
    multigrid_iterations[k] = Iterations(system, model, &multigrid);
  }
  std::printf("  CG iterations, 6 mm / 3 mm: Jacobi %d / %d, multigrid %d / %d\n", jacobi[0],
              jacobi[1], multigrid_iterations[0], multigrid_iterations[1]);
  EXPECT_GT(jacobi[1], 1.5 * jacobi[0]);
  EXPECT_LE(multigrid_iterations[1], 1.25 * multigrid_iterations[0] + 1);
  EXPECT_LT(4 * multigrid_iterations[1], jacobi[1]);
}

TEST(MultigridPreconditioner, ABodyTurnedAsAWholeKeepsItsIterations) {
  // The system of the block turned a quarter turn (K at the turned positions) against the
  // multigrid built at rest: told the turn, it needs the iterations it needs at rest.
  const Model model = Block(0.006, 0.49);
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  ForceEvaluator evaluator(model, DispersionPasses::kTwoPass, SpringKernels::kPerSpring);
  evaluator.Linearize(turn * model.rest_positions(), GeometricStiffness::kDropCompression);
  const RestSystem turned = SystemOf(model, evaluator.StiffnessMatrix());
  const RestSystem at_rest_system = SystemOf(model);
  MultigridPreconditioner multigrid(model, RestStiffness(model), HeldNodes(at_rest_system));
  multigrid.SetStepFactor(kStepFactor);
  const int at_rest = Iterations(at_rest_system, model, &multigrid);
  const int told = Iterations(turned, model, &multigrid, turn);
  const int not_told = Iterations(turned, model, &multigrid);
  EXPECT_LE(told, at_rest + 1);
  EXPECT_GT(not_told, told);
}

}  // namespace
}  // namespace msm_sim::core::internal
