// The masked conjugate gradient of the implicit substep against a dense solve.
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "mechanics/masked_pcg.h"

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
  std::vector<int> f, c;
  for (int k = 0; k < 12; ++k) (free.data()[k] != 0.0 ? f : c).push_back(k);
  Eigen::MatrixXd a_ff(f.size(), f.size()), a_fc(f.size(), c.size());
  Eigen::VectorXd rhs(f.size()), x_c(c.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    rhs[i] = b.data()[f[i]];
    for (std::size_t j = 0; j < f.size(); ++j) a_ff(i, j) = a(f[i], f[j]);
    for (std::size_t j = 0; j < c.size(); ++j) a_fc(i, j) = a(f[i], c[j]);
  }
  for (std::size_t j = 0; j < c.size(); ++j) x_c[j] = x.data()[c[j]];
  const Eigen::VectorXd expected = a_ff.ldlt().solve(rhs - a_fc * x_c);

  Eigen::Matrix3Xd inverse_diagonal(3, 4);
  for (int k = 0; k < 12; ++k) inverse_diagonal.data()[k] = 1.0 / a(k, k);
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

}  // namespace
}  // namespace msm_sim::core
