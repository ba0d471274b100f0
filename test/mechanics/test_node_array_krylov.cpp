// The node-array Krylov solver (masked CG of the implicit substep and of the static solver)
// against dense solves.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "mechanics/node_array_krylov.h"

namespace msm_sim::core {
namespace {

// A 12 x 12 symmetric positive definite matrix (4 nodes), with couplings between every DOF.
Eigen::MatrixXd TinySpdMatrix() {
  Eigen::MatrixXd g(12, 12);
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) g(i, j) = std::sin(1.0 + 3.0 * i + 7.0 * j);
  }
  return g * g.transpose() + 0.5 * Eigen::MatrixXd::Identity(12, 12);
}

NodeArrayOperator DenseOperator(const Eigen::MatrixXd& a) {
  return [a](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    const Eigen::VectorXd product = a * Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
    *out = Eigen::Map<const Eigen::Matrix3Xd>(product.data(), 3, v.cols());
  };
}

// A's blocks on the free DOFs (free entries != 0) and the fixed ones, in DOF order, and b's free
// part: the dense reference systems the solves are checked against.
struct SplitSystem {
  std::vector<int> free, fixed;
  Eigen::MatrixXd a_ff, a_fc;
  Eigen::VectorXd b_f;
};
SplitSystem SplitByFree(const Eigen::MatrixXd& a, const Eigen::Matrix3Xd& b,
                        const Eigen::Matrix3Xd& free) {
  SplitSystem s;
  for (int k = 0; k < a.rows(); ++k) (free.data()[k] != 0.0 ? s.free : s.fixed).push_back(k);
  const auto& f = s.free;
  const auto& c = s.fixed;
  s.a_ff.resize(f.size(), f.size());
  s.a_fc.resize(f.size(), c.size());
  s.b_f.resize(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    s.b_f[i] = b.data()[f[i]];
    for (std::size_t j = 0; j < f.size(); ++j) s.a_ff(i, j) = a(f[i], f[j]);
    for (std::size_t j = 0; j < c.size(); ++j) s.a_fc(i, j) = a(f[i], c[j]);
  }
  return s;
}

// 1 / diag(A) as node arrays.
Eigen::Matrix3Xd InverseDiagonal(const Eigen::MatrixXd& a) {
  Eigen::Matrix3Xd inverse(3, a.rows() / 3);
  for (int k = 0; k < a.rows(); ++k) inverse.data()[k] = 1.0 / a(k, k);
  return inverse;
}

TEST(MaskedPcg, MatchesADenseSolveWithFixedDofsMovedToTheRightHandSide) {
  const Eigen::MatrixXd a = TinySpdMatrix();
  Eigen::Matrix3Xd b(3, 4);
  b << 1.0, -2.0, 0.5, 3.0, 0.0, 1.5, -1.0, 2.0, 4.0, -0.5, 1.0, 0.25;
  // Node 1 is held (all three DOFs), and DOF (2, 3) too, at non-zero values.
  Eigen::Matrix3Xd free = Eigen::Matrix3Xd::Ones(3, 4);
  free.col(1).setZero();
  free(2, 3) = 0.0;
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 4);
  x.col(1) = Eigen::Vector3d(0.3, -0.2, 0.1);
  x(2, 3) = -0.4;
  const Eigen::Matrix3Xd held = x;

  // Dense reference: A_ff x_f = b_f - A_fc x_c.
  const SplitSystem split = SplitByFree(a, b, free);
  const std::vector<int>& f = split.free;
  const std::vector<int>& c = split.fixed;
  Eigen::VectorXd x_c(c.size());
  for (std::size_t j = 0; j < c.size(); ++j) x_c[j] = x.data()[c[j]];
  const Eigen::VectorXd expected = split.a_ff.ldlt().solve(split.b_f - split.a_fc * x_c);

  const Eigen::Matrix3Xd inverse_diagonal = InverseDiagonal(a);
  MaskedPcgOptions options;
  options.relative_tolerance = 1e-12;
  options.max_iterations = 100;
  Eigen::Matrix3Xd residual;
  const MaskedPcgReport report =
      SolveMaskedPcg(DenseOperator(a), b, free, inverse_diagonal, options, &x, &residual);
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.iterations, 40);
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_NEAR(x.data()[f[i]], expected[i], 1e-9);
  for (std::size_t j = 0; j < c.size(); ++j) EXPECT_EQ(x.data()[c[j]], held.data()[c[j]]);
  // The residual on every DOF, the fixed ones too (there, minus the constraint's force).
  const Eigen::VectorXd full = Eigen::Map<const Eigen::VectorXd>(b.data(), 12) -
                               a * Eigen::Map<const Eigen::VectorXd>(x.data(), 12);
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(residual.data()[k], full[k], 1e-9);
}

// A contact's projection (a node's velocity change along a unit normal held) solves A x = b on
// the range of S, against a dense solve in a basis of that range; the held normal's residual (the
// contact's force) does not enter the convergence test.
TEST(MaskedPcg, ContactNormalsHoldTheirComponentAndMatchADenseSolve) {
  const Eigen::MatrixXd a = TinySpdMatrix();
  Eigen::Matrix3Xd b(3, 4);
  b << 1.0, -2.0, 0.5, 3.0, 0.0, 1.5, -1.0, 2.0, 4.0, -0.5, 1.0, 0.25;
  DofProjection projection;
  projection.free = Eigen::Matrix3Xd::Ones(3, 4);
  projection.free.col(3).setZero();
  const Eigen::Vector3d normal = Eigen::Vector3d(1.0, 2.0, -2.0) / 3.0;
  projection.normals.push_back({2, normal});
  Eigen::Matrix3Xd start = Eigen::Matrix3Xd::Zero(3, 4);
  start.col(2) = 0.7 * normal;
  start.col(3) = Eigen::Vector3d(0.2, -0.1, 0.3);
  // A basis of the range of S (node 2's plane, nodes 0 and 1 whole), then the dense solve of
  // B^T A B y = B^T (b - A x0).
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(12, 8);
  for (int k = 0; k < 6; ++k) basis(k, k) = 1.0;
  const Eigen::Vector3d t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
  basis.block<3, 1>(6, 6) = t1;
  basis.block<3, 1>(6, 7) = t2;
  const Eigen::VectorXd x0 = Eigen::Map<const Eigen::VectorXd>(start.data(), 12);
  const Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(b.data(), 12) - a * x0;
  const Eigen::VectorXd y = (basis.transpose() * a * basis).ldlt().solve(basis.transpose() * rhs);
  const Eigen::VectorXd expected = x0 + basis * y;

  const Eigen::Matrix3Xd inverse_diagonal = InverseDiagonal(a);
  MaskedPcgOptions options;
  options.relative_tolerance = 1e-12;
  options.max_iterations = 100;
  Eigen::Matrix3Xd x = start, residual;
  ASSERT_TRUE(
      SolveMaskedPcg(DenseOperator(a), b, projection, inverse_diagonal, options, &x, &residual)
          .converged);
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(x.data()[k], expected[k], 1e-9) << k;
  EXPECT_NEAR(x.col(2).dot(normal), 0.7, 1e-12);
}

TEST(MaskedPcg, WarmStartAtTheSolutionTakesNoIteration) {
  const Eigen::MatrixXd a = TinySpdMatrix();
  const Eigen::VectorXd solution = Eigen::VectorXd::LinSpaced(12, -1.0, 2.0);
  const Eigen::VectorXd b_vector = a * solution;
  const Eigen::Matrix3Xd b = Eigen::Map<const Eigen::Matrix3Xd>(b_vector.data(), 3, 4);
  Eigen::Matrix3Xd x = Eigen::Map<const Eigen::Matrix3Xd>(solution.data(), 3, 4);
  Eigen::Matrix3Xd residual;
  const MaskedPcgReport report =
      SolveMaskedPcg(DenseOperator(a), b, Eigen::Matrix3Xd::Ones(3, 4),
                     Eigen::Matrix3Xd::Ones(3, 4), MaskedPcgOptions{}, &x, &residual);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.iterations, 0);
}

TEST(MaskedPcg, StopsAtMaxIterationsUnconverged) {
  const Eigen::MatrixXd a = TinySpdMatrix();
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 4), residual;
  MaskedPcgOptions options;
  options.relative_tolerance = 1e-14;
  options.max_iterations = 2;
  const MaskedPcgReport report =
      SolveMaskedPcg(DenseOperator(a), Eigen::Matrix3Xd::Ones(3, 4), Eigen::Matrix3Xd::Ones(3, 4),
                     Eigen::Matrix3Xd::Ones(3, 4), options, &x, &residual);
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(report.iterations, 2);
  EXPECT_GT(report.relative_residual, 1e-14);
}

// The early stop: taken at the first iteration whose residual is within the early tolerance and
// that the caller accepts, never before; a caller that accepts nothing gets the full solve.
TEST(MaskedPcg, EarlyStopNeedsBothTheEarlyToleranceAndTheCallersAcceptance) {
  // A chain of 30 nodes (90 DOFs, tridiagonal 2.01 / -1): many iterations between 1e-2 and 1e-12.
  const int nodes = 30;
  Eigen::MatrixXd a = 2.01 * Eigen::MatrixXd::Identity(3 * nodes, 3 * nodes);
  for (int k = 0; k + 1 < 3 * nodes; ++k) a(k, k + 1) = a(k + 1, k) = -1.0;
  const Eigen::Matrix3Xd b = Eigen::Matrix3Xd::Ones(3, nodes);
  const Eigen::Matrix3Xd ones = Eigen::Matrix3Xd::Ones(3, nodes);
  const auto solve = [&](const MaskedPcgOptions& options, std::vector<double>* seen) {
    MaskedPcgOptions counted = options;
    if (options.accept_early) {
      counted.accept_early = [&](const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& r) {
        seen->push_back(r.norm() / b.norm());
        return options.accept_early(x, r);
      };
    }
    Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, nodes), residual;
    const MaskedPcgReport report =
        SolveMaskedPcg(DenseOperator(a), b, ones, ones, counted, &x, &residual);
    return report;
  };
  MaskedPcgOptions tight;
  tight.relative_tolerance = 1e-12;
  tight.max_iterations = 500;
  std::vector<double> seen;
  const MaskedPcgReport full = solve(tight, &seen);
  ASSERT_TRUE(full.converged);

  MaskedPcgOptions early = tight;
  early.early_relative_tolerance = 1e-2;
  early.accept_early = [](const Eigen::Matrix3Xd&, const Eigen::Matrix3Xd&) { return true; };
  const MaskedPcgReport stopped = solve(early, &seen);
  EXPECT_TRUE(stopped.converged);
  EXPECT_LT(stopped.iterations, full.iterations);
  EXPECT_LE(stopped.relative_residual, 1e-2);
  ASSERT_EQ(seen.size(), 1u);  // asked once: at the first residual within the early tolerance
  EXPECT_LE(seen[0], 1e-2);

  seen.clear();
  early.accept_early = [](const Eigen::Matrix3Xd&, const Eigen::Matrix3Xd&) { return false; };
  const MaskedPcgReport refused = solve(early, &seen);
  EXPECT_EQ(refused.iterations, full.iterations);
  EXPECT_LE(refused.relative_residual, 1e-12);
  for (const double residual : seen) EXPECT_LE(residual, 1e-2);
}

}  // namespace
}  // namespace msm_sim::core
