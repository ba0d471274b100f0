#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "expect_stiffness.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/material/extended_msm.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model_builder.h"
#include "msm_sim/model/model_transform.h"

namespace msm_sim::core {
namespace {

Model RandomModel(double poisson, SpringLaw law) {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.3);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = law;
  return BuildRandomLattice(Material::FromYoungsPoisson(1e4, poisson, 1000.0), options);
}

Eigen::Matrix3Xd Perturbed(const Model& model, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, amplitude);
  Eigen::Matrix3Xd x = model.rest_positions();
  for (int i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  return x;
}

Eigen::Matrix3Xd Forces(const Model& model, const Eigen::Matrix3Xd& x, double* energy = nullptr) {
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  evaluator.AccumulateForces(x, &f);
  if (energy) *energy = evaluator.ElasticEnergy(x);
  return f;
}

// Checks ApplyStiffness and StiffnessDiagonal at x against central differences of the forces at
// the given DOFs.
void ExpectExactLinearisation(const Model& model, const Eigen::Matrix3Xd& x,
                              const std::vector<int>& dofs) {
  ForceEvaluator evaluator(model);
  ExpectStiffnessIsTheForcesDerivative(
      &evaluator, [&](const Eigen::Matrix3Xd& at) { return Forces(model, at); }, x, dofs);
}

// Checks the forces at x against central differences of ElasticEnergy at the given DOFs.
void ExpectForcesAreMinusEnergyGradient(const Model& model, const Eigen::Matrix3Xd& x,
                                        const std::vector<int>& dofs) {
  const Eigen::Matrix3Xd f = Forces(model, x);
  const double h = 1e-7;
  for (const int dof : dofs) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[dof] += h;
    xm.data()[dof] -= h;
    double ep = 0.0, em = 0.0;
    Forces(model, xp, &ep);
    Forces(model, xm, &em);
    EXPECT_NEAR(-(ep - em) / (2 * h), f.data()[dof], 1e-5 * (1.0 + std::abs(f.data()[dof])))
        << "dof " << dof;
  }
}

std::vector<int> EveryNthDof(const Model& model, int stride) {
  std::vector<int> dofs;
  for (int dof = 0; dof < 3 * model.num_nodes(); dof += stride) dofs.push_back(dof);
  return dofs;
}

TEST(ForceEvaluator, LinearSpringObeysHookesLaw) {
  ModelBuilder builder(Material::FromYoungsPoisson(1e4, 0.25, 1000.0));
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({2, 0, 0}, 1.0);
  builder.AddSpring(0, 1, 50.0);
  const Model model = builder.Build(1.0, 1.0);
  Eigen::Matrix3Xd x = model.rest_positions();
  x(0, 1) = 2.1;  // stretched by 0.1
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 2);
  evaluator.AccumulateForces(x, &f);
  EXPECT_NEAR(evaluator.ElasticEnergy(x), 0.5 * 50.0 * 0.01, 1e-12);
  EXPECT_NEAR(f(0, 0), 5.0, 1e-12);  // node 0 pulled towards node 1
  EXPECT_NEAR(f(0, 1), -5.0, 1e-12);
  EXPECT_NEAR(evaluator.total_tensions()[0], 5.0, 1e-12);
}

TEST(ForceEvaluator, NonlinearSpringMatchesTheCarrierLaw) {
  const double k = 50.0, l0 = 2.0;
  for (const double l : {0.1, 1.0, 1.9, 2.0, 2.5, 6.0}) {
    EXPECT_NEAR(CarrierSpringLaw::Tension(k, l0, l), k * l0 * (l - l0) / l, 1e-12);
    const double h = 1e-6;
    EXPECT_NEAR(
        (CarrierSpringLaw::Energy(k, l0, l + h) - CarrierSpringLaw::Energy(k, l0, l - h)) / (2 * h),
        CarrierSpringLaw::Tension(k, l0, l), 1e-5);
  }
  // Same small-strain stiffness as the linear law; unbounded compressive force as L -> 0.
  EXPECT_DOUBLE_EQ(CarrierSpringLaw::TangentStiffness(k, l0, l0), k);
  EXPECT_LT(CarrierSpringLaw::Tension(k, l0, 1e-6), -1e6);
  EXPECT_GT(LinearSpringLaw::Tension(k, l0, 1e-6), -k * l0 - 1e-9);
}

class ForceEvaluatorLaws : public ::testing::TestWithParam<SpringLaw> {};

TEST_P(ForceEvaluatorLaws, ForcesAreMinusEnergyGradient) {
  // Without dispersion and with it (w = v k L0^2, the dispersed tension weighted by t' / k).
  for (const double poisson : {0.25, 0.45}) {
    SCOPED_TRACE(poisson);
    const Model model = RandomModel(poisson, GetParam());
    const Eigen::Matrix3Xd x = Perturbed(model, 0.01, 3);
    ExpectForcesAreMinusEnergyGradient(model, x, {0, 7, 31, 3 * model.num_nodes() - 1});
    const Eigen::Matrix3Xd f = Forces(model, x);
    EXPECT_LT(f.rowwise().sum().norm(), 1e-9);  // Newton's third law
  }
}

// The stiffness is the energy's Hessian: u . K v = v . K u, for every law with dispersion.
TEST_P(ForceEvaluatorLaws, StiffnessIsSymmetricWithDispersion) {
  const Model model = RandomModel(0.45, GetParam());
  ForceEvaluator evaluator(model);
  evaluator.Linearize(Perturbed(model, 0.01, 4));
  const Eigen::Matrix3Xd u = Perturbed(model, 1.0, 5) - model.rest_positions();
  const Eigen::Matrix3Xd v = Perturbed(model, 1.0, 6) - model.rest_positions();
  Eigen::Matrix3Xd ku(3, model.num_nodes()), kv(3, model.num_nodes());
  evaluator.ApplyStiffness(u, &ku);
  evaluator.ApplyStiffness(v, &kv);
  const double uv = u.cwiseProduct(kv).sum(), vu = v.cwiseProduct(ku).sum();
  EXPECT_NEAR(uv, vu, 1e-10 * (ku.norm() * v.norm()));
}

TEST_P(ForceEvaluatorLaws, StiffnessIsMinusForceJacobianWithDispersion) {
  for (const double poisson : {-0.5, 0.25, 0.45}) {
    SCOPED_TRACE(poisson);
    const Model model = RandomModel(poisson, GetParam());
    ExpectExactLinearisation(model, Perturbed(model, 0.01, 5), {2, 40, 3 * model.num_nodes() - 2});
  }
}

TEST_P(ForceEvaluatorLaws, StiffnessIsExactWithNonUnitDispersionWeights) {
  // Compensated node-centred and element-corner lattices carry dispersion weights != 1.
  for (const auto construction :
       {CubicConstruction::kNodeCentred, CubicConstruction::kElementCorner}) {
    CubicLatticeOptions options;
    options.size = Eigen::Vector3d(0.4, 0.3, 0.3);
    options.lattice.spacing = 0.1;
    options.construction = construction;
    options.lattice.spring_law = GetParam();
    const Model model = BuildCubicLattice(Material::FromYoungsPoisson(1e4, -0.5, 1000.0), options);
    ExpectExactLinearisation(model, Perturbed(model, 0.005, 9), EveryNthDof(model, 7));
  }
}

TEST_P(ForceEvaluatorLaws, BaudetCorrectionIsExactlyLinearisedAndConservative) {
  BaudetLatticeOptions options;
  options.size = Eigen::Vector3d(0.3, 0.2, 0.2);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = GetParam();
  const Model model = BuildBaudetLattice(Material::FromYoungsPoisson(1e4, 0.4, 1000.0), options);
  ASSERT_EQ(model.correction_edges().size(), 12u);
  const Eigen::Matrix3Xd x = Perturbed(model, 0.004, 11);
  ExpectExactLinearisation(model, x, EveryNthDof(model, 5));
  ExpectForcesAreMinusEnergyGradient(model, x, EveryNthDof(model, 5));
}

INSTANTIATE_TEST_SUITE_P(Laws, ForceEvaluatorLaws,
                         ::testing::Values(SpringLaw::kLinear, SpringLaw::kNonlinear));

// The power law of docs/physics.md §4.1 on the per-spring path: alpha = 1, beta = 0 gives the
// linear springs' forces, energy and stiffness and alpha = -1, beta = 0 the carrier springs', in
// the plain and two-pass eMSM loops, to 1e-12 of the largest value.
void ExpectPowerLawReproduces(const Model& model, double alpha) {
  const Model power = WithSpringLaw(model, SpringLaw::kPower, PowerSpringLaw{alpha, 0.0});
  ForceEvaluator expected(model, SpringKernels::kPerSpring);
  ForceEvaluator actual(power);
  for (const unsigned seed : {21u, 22u}) {
    const Eigen::Matrix3Xd x = Perturbed(model, 0.01, seed);
    Eigen::Matrix3Xd f_expected = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    Eigen::Matrix3Xd f_actual = f_expected;
    expected.AccumulateForces(x, &f_expected);
    actual.AccumulateForces(x, &f_actual);
    const double scale = f_expected.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0.0);
    EXPECT_LE((f_actual - f_expected).cwiseAbs().maxCoeff(), 1e-12 * scale) << "alpha " << alpha;
    const double energy = expected.ElasticEnergy(x);
    EXPECT_NEAR(actual.ElasticEnergy(x), energy, 1e-12 * energy);
    expected.Linearize(x);
    actual.Linearize(x);
    Eigen::Matrix3Xd k_expected = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    Eigen::Matrix3Xd k_actual = k_expected;
    expected.ApplyStiffness(x, &k_expected);
    actual.ApplyStiffness(x, &k_actual);
    EXPECT_LE((k_actual - k_expected).cwiseAbs().maxCoeff(),
              1e-12 * k_expected.cwiseAbs().maxCoeff());
  }
}

TEST(ForceEvaluator, PowerLawContainsTheLinearAndCarrierLaws) {
  for (const double poisson : {0.25, 0.45}) {  // without and with dispersion
    ExpectPowerLawReproduces(RandomModel(poisson, SpringLaw::kLinear), 1.0);
    ExpectPowerLawReproduces(RandomModel(poisson, SpringLaw::kNonlinear), -1.0);
  }
}

TEST(ForceEvaluator, PowerLawIsExactlyLinearisedAndConservative) {
  // A fitted law (Ecoflex 00-30, docs/materials.md) and one with a strong upturn, at strains of
  // several per cent, without dispersion and with it.
  for (const PowerSpringLaw law : {PowerSpringLaw{-4.54, 0.116}, PowerSpringLaw{0.5, 2.0}}) {
    for (const double poisson : {0.25, 0.45}) {
      SCOPED_TRACE(poisson);
      const Model model =
          WithSpringLaw(RandomModel(poisson, SpringLaw::kLinear), SpringLaw::kPower, law);
      const Eigen::Matrix3Xd x = Perturbed(model, 0.01, 5);
      ExpectExactLinearisation(model, x, {2, 40, 3 * model.num_nodes() - 2});
      ExpectForcesAreMinusEnergyGradient(model, x, {0, 7, 31});
      EXPECT_LT(Forces(model, x).rowwise().sum().norm(), 1e-9);  // Newton's third law
    }
  }
}

TEST(ForceEvaluator, DispersionAddsQTimesTheDirectBulkResponse) {
  // docs/physics.md §3: under uniform dilatation eps, sum over springs of t*_n L0_n = 2 q sum k
  // L0^2 eps.
  const Model model = RandomModel(0.4, SpringLaw::kLinear);
  const double q = model.dispersion_fraction();
  EXPECT_NEAR(q, 0.5 * DispersionRatio(0.4), 1e-15);
  const double eps = 1e-6;
  const Eigen::Matrix3Xd x = model.rest_positions() * (1.0 + eps);
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  evaluator.AccumulateForces(x, &f);
  double dispersed = 0.0, direct = 0.0;
  for (int s = 0; s < model.num_springs(); ++s) {
    const double l0 = model.spring_rest_length()[s];
    const double t = model.spring_stiffness()[s] * l0 * eps;
    dispersed += (evaluator.total_tensions()[s] - t) * l0;
    direct += model.spring_stiffness()[s] * l0 * l0 * eps;
  }
  EXPECT_NEAR(dispersed / (2.0 * q * direct), 1.0, 1e-6);
}

TEST(ExtendedMsm, DispersionRatioRoundTripsAndMatchesLimits) {
  for (const double nu : {-0.9, -0.5, 0.0, 0.25, 0.33, 0.45, 0.49}) {
    EXPECT_NEAR(PoissonFromDispersionRatio(DispersionRatio(nu)), nu, 1e-12);
  }
  EXPECT_DOUBLE_EQ(DispersionRatio(0.25), 0.0);
  EXPECT_NEAR(DispersionRatio(-0.999999), -1.0, 1e-5);
  EXPECT_GT(DispersionRatio(0.4999), 1e3);
  // Q = B / K_direct with B = lambda - mu, K_direct = 5 mu / 3.
  const Material m = Material::FromYoungsPoisson(1.0, 0.4, 1.0);
  EXPECT_NEAR(DispersionRatio(0.4),
              (m.lame_lambda() - m.shear_modulus()) / (5.0 / 3.0 * m.shear_modulus()), 1e-12);
}

}  // namespace
}  // namespace msm_sim::core

namespace msm_sim::core {
namespace {

// Large models may evaluate their springs on two threads (the worker pool: one worker on a
// two-core machine), each scattering into its own buffer: the forces and tensions must equal the
// one-thread evaluation up to rounding, and repeat exactly; by default an evaluator uses one
// thread.
TEST(ForceEvaluatorThreads, TwoThreadsMatchOneAndRepeatExactly) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.2, 0.15);
  options.lattice.spacing = 0.01;  // 12,000 nodes, ~100k springs: above the parallel threshold
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1000.0), options);
  ASSERT_GE(model.num_springs(), 50'000);
  Eigen::Matrix3Xd x = model.rest_positions();
  for (int i = 0; i < x.cols(); ++i)
    x.col(i) += 1e-4 * Eigen::Vector3d(std::sin(i), std::cos(3.0 * i), std::sin(7.0 * i));
  const Eigen::Matrix3Xd v = 0.01 * x;
  auto evaluate = [&](int max_threads) {
    ForceEvaluator evaluator = max_threads > 0
                                   ? ForceEvaluator(model, SpringKernels::kAuto, max_threads)
                                   : ForceEvaluator(model);
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    evaluator.AccumulateForces(x, v, 1e-4, &f);
    return std::make_pair(f, Eigen::VectorXd(evaluator.total_tensions()));
  };
  const auto serial = evaluate(1);
  const auto parallel = evaluate(2);
  const auto again = evaluate(2);
  const auto by_default = evaluate(0);  // WorldOptions::threads' default: one thread
  EXPECT_LE((parallel.first - serial.first).cwiseAbs().maxCoeff(),
            1e-12 * serial.first.cwiseAbs().maxCoeff());
  // The dispersed part of a tension sums a node's accumulator in another order: rounding only.
  EXPECT_LE((parallel.second - serial.second).cwiseAbs().maxCoeff(),
            1e-12 * serial.second.cwiseAbs().maxCoeff());
  EXPECT_EQ(again.first, parallel.first);
  EXPECT_EQ(by_default.first, serial.first);  // the same order of sums, bit for bit
}

}  // namespace
}  // namespace msm_sim::core
