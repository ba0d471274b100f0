// ForceEvaluator::StiffnessMatrix against ApplyStiffness's products, on every kind of lattice
// and stiffness term (springs, dispersion, Baudet correction, geometric stiffness).
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "perturbed_positions.h"

namespace msm_sim::core {
namespace {

// Checks K v == StiffnessMatrix() vec(v) for a few seeded random v, to rounding: the matrix of
// the per-spring linearisation against the products of the default evaluator (the run kernels
// where the model suits them).
void ExpectMatrixMatchesProducts(const Model& model, const Eigen::Matrix3Xd& x,
                                 GeometricStiffness geometric) {
  ForceEvaluator per_spring(model, DispersionPasses::kTwoPass, SpringKernels::kPerSpring);
  per_spring.Linearize(x, geometric);
  const Eigen::SparseMatrix<double> k = per_spring.StiffnessMatrix();
  ForceEvaluator evaluator(model);
  evaluator.Linearize(x, geometric);
  ASSERT_EQ(k.rows(), 3 * model.num_nodes());
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::Matrix3Xd v(3, model.num_nodes());
    for (int i = 0; i < v.size(); ++i) v.data()[i] = normal(rng);
    Eigen::Matrix3Xd product;
    evaluator.ApplyStiffness(v, &product);
    const Eigen::VectorXd assembled = k * Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
    const Eigen::Map<const Eigen::VectorXd> expected(product.data(), product.size());
    EXPECT_LE((assembled - expected).norm(), 1e-10 * expected.norm()) << "trial " << trial;
  }
  // Diagonal as StiffnessDiagonal reports it.
  const Eigen::Matrix3Xd diagonal = evaluator.StiffnessDiagonal();
  const Eigen::VectorXd assembled_diagonal = k.diagonal();
  const Eigen::Map<const Eigen::VectorXd> expected_diagonal(diagonal.data(), diagonal.size());
  EXPECT_LE((assembled_diagonal - expected_diagonal).norm(), 1e-10 * expected_diagonal.norm());
}

TEST(StiffnessMatrix, MatchesProductsOfANearlyIncompressibleCubicLattice) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.05, 0.04, 0.03);
  options.lattice.spacing = 0.01;
  options.surface.surface_dispersion = 0.25;  // non-uniform dispersion weights
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.49, 1100.0), options);
  ASSERT_GT(model.dispersion_fraction(), 0.0);
  ExpectMatrixMatchesProducts(model, model.rest_positions(), GeometricStiffness::kExact);
  const Eigen::Matrix3Xd deformed = Perturbed(model.rest_positions(), 1e-3, 7);
  ExpectMatrixMatchesProducts(model, deformed, GeometricStiffness::kExact);
  ExpectMatrixMatchesProducts(model, deformed, GeometricStiffness::kDropCompression);
}

TEST(StiffnessMatrix, MatchesProductsOfARandomLattice) {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.3);
  options.lattice.spacing = 0.1;
  const Model model = BuildRandomLattice(Material::FromYoungsPoisson(1e4, 0.45, 1000.0), options);
  ExpectMatrixMatchesProducts(model, Perturbed(model.rest_positions(), 0.01, 5),
                              GeometricStiffness::kExact);
}

TEST(StiffnessMatrix, MatchesProductsWithTheBaudetCorrection) {
  BaudetLatticeOptions options;
  options.size = Eigen::Vector3d(0.3, 0.2, 0.2);
  options.lattice.spacing = 0.1;
  const Model model = BuildBaudetLattice(Material::FromYoungsPoisson(1e4, 0.4, 1000.0), options);
  ASSERT_FALSE(model.correction_edges().empty());
  ExpectMatrixMatchesProducts(model, Perturbed(model.rest_positions(), 0.004, 11),
                              GeometricStiffness::kExact);
}

TEST(StiffnessMatrix, IsSymmetricForLinearSprings) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.04, 0.04, 0.04);
  options.lattice.spacing = 0.01;
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.45, 1100.0), options);
  ForceEvaluator evaluator(model, DispersionPasses::kTwoPass, SpringKernels::kPerSpring);
  evaluator.Linearize(Perturbed(model.rest_positions(), 1e-3, 2), GeometricStiffness::kExact);
  const Eigen::SparseMatrix<double> k = evaluator.StiffnessMatrix();
  const Eigen::SparseMatrix<double> asymmetry = k - Eigen::SparseMatrix<double>(k.transpose());
  EXPECT_LE(asymmetry.norm(), 1e-12 * k.norm());
}

TEST(StiffnessMatrix, RefusesALinearisationThroughTheRunKernels) {
  CubicLatticeOptions options;
  options.lattice.spacing = 0.01;
  options.size = Eigen::Vector3d(0.04, 0.04, 0.04);
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.45, 1100.0), options);
  ForceEvaluator evaluator(model);
  evaluator.Linearize(model.rest_positions(), GeometricStiffness::kExact);
  EXPECT_THROW(evaluator.StiffnessMatrix(), std::logic_error);
}

}  // namespace
}  // namespace msm_sim::core
