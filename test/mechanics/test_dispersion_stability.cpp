// Stability of the eMSM dispersion in explicit dynamics (issue "Any Poisson's ratio").
//
// The two-pass algorithm has no lag, and its dispersion is conservative
// (Model::dispersion_weight_a), so undamped free vibrations keep their energy at any Poisson's
// ratio (a dispersion lagged by one step pumps energy in for nu > 1/4, docs/physics.md §3).
// These tests run free vibrations of a small block to show it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

Model Block(double poisson) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.2, 0.2);
  options.lattice.spacing = 0.05;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1000.0), options);
}

// Largest |eigenvalue| of M^-1 K at rest, by power iteration.
double MaxAngularFrequency(const Model& model) {
  ForceEvaluator evaluator(model);
  evaluator.Linearize(model.rest_positions());
  Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Random(3, model.num_nodes());  // not a rigid motion
  double lambda = 0.0;
  for (int i = 0; i < 300; ++i) {
    Eigen::Matrix3Xd kv;
    evaluator.ApplyStiffness(v, &kv);
    for (int n = 0; n < model.num_nodes(); ++n) kv.col(n) /= model.masses()[n];
    lambda = kv.norm() / v.norm();
    v = kv / kv.norm();
  }
  return std::sqrt(lambda);
}

// Kinetic energy peak over the last quarter of a free vibration, relative to the first quarter.
double KineticEnergyGrowth(const Model& model, int steps) {
  const double dt = 0.5 * 2.0 / MaxAngularFrequency(model);
  ForceEvaluator evaluator(model);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1e-4);
  Eigen::Matrix3Xd x = model.rest_positions();
  for (int i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  Eigen::Matrix3Xd f(3, model.num_nodes());
  const auto forces = [&] {
    f.setZero();
    evaluator.AccumulateForces(x, &f);
    for (int n = 0; n < model.num_nodes(); ++n) f.col(n) /= model.masses()[n];
  };
  forces();
  double early = 0.0, late = 0.0;
  for (int step = 0; step < steps; ++step) {
    v += 0.5 * dt * f;
    x += dt * v;
    forces();
    v += 0.5 * dt * f;
    double kinetic = 0.0;
    for (int n = 0; n < model.num_nodes(); ++n) {
      kinetic += 0.5 * model.masses()[n] * v.col(n).squaredNorm();
    }
    if (!std::isfinite(kinetic)) return std::numeric_limits<double>::infinity();
    if (step < steps / 4) early = std::max(early, kinetic);
    if (step >= 3 * steps / 4) late = std::max(late, kinetic);
  }
  return late / early;
}

TEST(DispersionStability, TwoPassIsStableForAnyPoissonRatio) {
  for (const double nu : {-0.5, 0.0, 0.45}) {
    EXPECT_LT(KineticEnergyGrowth(Block(nu), 4000), 2.0) << nu;
  }
}

TEST(DispersionStability, TwoPassConservesEnergyWithLeapfrog) {
  // Leapfrog keeps a shadow energy: the total energy oscillates but does not drift.
  for (const double nu : {-0.5, 0.45}) {
    const Model model = Block(nu);
    const double dt = 0.2 * 2.0 / MaxAngularFrequency(model);
    ForceEvaluator evaluator(model);
    Eigen::Matrix3Xd x = model.rest_positions();
    x.row(0) *= 1.002;  // a stretch along x, released
    Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    evaluator.AccumulateForces(x, &f);
    const auto energy = [&] {
      double kinetic = 0.0;
      for (int n = 0; n < model.num_nodes(); ++n) {
        kinetic += 0.5 * model.masses()[n] * v.col(n).squaredNorm();
      }
      return kinetic + evaluator.ElasticEnergy(x);
    };
    const double initial = energy();
    double worst = 0.0;
    for (int step = 0; step < 3000; ++step) {
      for (int n = 0; n < model.num_nodes(); ++n)
        v.col(n) += 0.5 * dt * f.col(n) / model.masses()[n];
      x += dt * v;
      f.setZero();
      evaluator.AccumulateForces(x, &f);
      for (int n = 0; n < model.num_nodes(); ++n)
        v.col(n) += 0.5 * dt * f.col(n) / model.masses()[n];
      worst = std::max(worst, std::abs(energy() / initial - 1.0));
    }
    EXPECT_LT(worst, 0.02) << nu;
  }
}

}  // namespace
}  // namespace msm_sim::core
