// The vectorised run kernels (ForceEvaluator with SpringKernels::kAuto on a lattice in rows)
// against the per-spring loops, which the rest of the suite checks against theory.
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_builder.h"
#include "perturbed_positions.h"

namespace msm_sim::core {
namespace {

struct Evaluation {
  Eigen::Matrix3Xd forces;
  Eigen::VectorXd tensions;
};

// Forces (added to a non-zero start, as a step does) and total tensions of one evaluation.
Evaluation Evaluate(const Model& model, SpringKernels kernels, const Eigen::Matrix3Xd& x,
                    const Eigen::Matrix3Xd& v, double beta) {
  ForceEvaluator evaluator(model, kernels);
  Evaluation result;
  result.forces = Eigen::Matrix3Xd::Ones(3, model.num_nodes());
  evaluator.AccumulateForces(x, v, beta, &result.forces);
  result.tensions = evaluator.total_tensions();
  return result;
}

void ExpectSame(const Evaluation& runs, const Evaluation& reference) {
  const double force_scale = reference.forces.cwiseAbs().maxCoeff();
  const double tension_scale = reference.tensions.cwiseAbs().maxCoeff();
  ASSERT_GT(force_scale, 1.0);
  EXPECT_LE((runs.forces - reference.forces).cwiseAbs().maxCoeff(), 1e-12 * force_scale);
  EXPECT_LE((runs.tensions - reference.tensions).cwiseAbs().maxCoeff(), 1e-12 * tension_scale);
}

// Node-centred block: its surface springs carry unequal end weights (v = 4/3 and 2/3).
Model Block(double poisson) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.1, 0.06, 0.05);
  options.lattice.spacing = 0.01;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1000.0), options);
}

class ForceKernels : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(ForceKernels, RunKernelsMatchThePerSpringLoops) {
  const auto [poisson, beta] = GetParam();
  const Model model = Block(poisson);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 5e-4, 1);
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 2);
  ExpectSame(Evaluate(model, SpringKernels::kAuto, x, v, beta),
             Evaluate(model, SpringKernels::kPerSpring, x, v, beta));
}

// Plain MSM (nu = 1/4) and eMSM (nu = 0.45, -0.5), without and with dampers.
INSTANTIATE_TEST_SUITE_P(PlainAndDispersed, ForceKernels,
                         ::testing::Values(std::make_pair(0.25, 0.0), std::make_pair(0.25, 1e-3),
                                           std::make_pair(0.45, 0.0), std::make_pair(0.45, 1e-3),
                                           std::make_pair(-0.5, 1e-3)));

TEST(ForceKernelsChain, ReversedSpringsKeepTheirEndWeights) {
  // Springs from the higher index to the lower, unequal end weights: the schedule swaps the
  // ends, and the dispersion must still read each end's own weight.
  ModelBuilder builder(Material::FromYoungsPoisson(1e4, 0.45, 1000.0));
  for (int i = 0; i < 12; ++i) builder.AddNode(Eigen::Vector3d(0.01 * i, 0.0, 0.0), 0.1);
  for (int i = 0; i < 11; ++i) {
    const SpringIndex s = builder.AddSpring(i + 1, i, 100.0 + i);
    builder.SetDispersionWeight(s, i + 1, 1.5);
    builder.SetDispersionWeight(s, i, 0.5);
  }
  builder.SetDispersionFraction(2.0);
  const Model model = builder.Build(1e-6, 0.01);
  const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 1e-3, 3);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  ExpectSame(Evaluate(model, SpringKernels::kAuto, x, v, 0.0),
             Evaluate(model, SpringKernels::kPerSpring, x, v, 0.0));
}

TEST(ForceKernelsLinearize, StiffnessProductMatchesThePerSpringLoops) {
  for (const double poisson : {0.25, 0.45}) {
    const Model model = Block(poisson);
    // Perturbed enough that some springs are compressed and some stretched.
    const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 5e-4, 5);
    const Eigen::Matrix3Xd probe = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 1.0, 6);
    for (const auto geometric :
         {GeometricStiffness::kExact, GeometricStiffness::kDropCompression}) {
      Eigen::Matrix3Xd product[2];
      const SpringKernels kernels[2] = {SpringKernels::kAuto, SpringKernels::kPerSpring};
      for (int k = 0; k < 2; ++k) {
        ForceEvaluator evaluator(model, kernels[k]);
        evaluator.Linearize(x, geometric);
        evaluator.ApplyStiffness(probe, &product[k]);
        ASSERT_EQ(product[k].cols(), model.num_nodes());
      }
      EXPECT_LE((product[0] - product[1]).cwiseAbs().maxCoeff(),
                1e-12 * product[1].cwiseAbs().maxCoeff())
          << "nu " << poisson << " geometric " << static_cast<int>(geometric);
    }
  }
}

TEST(ForceKernelsLinearize, DiagonalAndTensionsMatchThePerSpringLoops) {
  for (const double poisson : {0.25, 0.45}) {
    const Model model = Block(poisson);
    const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 5e-4, 5);
    for (const auto geometric :
         {GeometricStiffness::kExact, GeometricStiffness::kDropCompression}) {
      Eigen::Matrix3Xd diagonal[2];
      Eigen::VectorXd tensions[2];
      const SpringKernels kernels[2] = {SpringKernels::kAuto, SpringKernels::kPerSpring};
      for (int k = 0; k < 2; ++k) {
        // Forces evaluated before in float, as the implicit kick does: Linearize evaluates anew.
        ForceEvaluator evaluator(model, kernels[k]);
        evaluator.set_precision(SpringPrecision::kSingle);
        Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
        evaluator.AccumulateForces(model.rest_positions(), &forces);
        evaluator.Linearize(x, geometric);
        diagonal[k] = evaluator.StiffnessDiagonal();
        tensions[k] = evaluator.total_tensions();
      }
      const std::string what = "nu " + std::to_string(poisson) + " geometric " +
                               std::to_string(static_cast<int>(geometric));
      EXPECT_LE((diagonal[0] - diagonal[1]).cwiseAbs().maxCoeff(),
                1e-12 * diagonal[1].cwiseAbs().maxCoeff())
          << what;
      EXPECT_LE((tensions[0] - tensions[1]).cwiseAbs().maxCoeff(),
                1e-12 * tensions[1].cwiseAbs().maxCoeff())
          << what;
    }
  }
}

}  // namespace
}  // namespace msm_sim::core
