#include <random>

#include <gtest/gtest.h>
#include <Eigen/SparseCore>

#include "msm_sim/core/model_builder.h"
#include "msm_sim/core/random_lattice_builder.h"
#include "msm_sim/core/spring_forces.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e4, 0.25, 1000.0);

Model SmallRandomModel() {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.3);
  options.spacing = 0.1;
  return BuildRandomLattice(kMaterial, options);
}

Eigen::Matrix3Xd Perturbed(const Model& model, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, amplitude);
  Eigen::Matrix3Xd x = model.rest_positions();
  for (int i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  return x;
}

TEST(SpringForces, SingleSpringObeysHookesLaw) {
  ModelBuilder builder(kMaterial);
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({2, 0, 0}, 1.0);
  builder.AddSpring(0, 1, 50.0);
  const Model model = builder.Build(1.0, 1.0);
  Eigen::Matrix3Xd x = model.rest_positions();
  x(0, 1) = 2.1;  // stretched by 0.1
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 2);
  const double energy = AccumulateSpringForces(model, x, &f);
  EXPECT_NEAR(energy, 0.5 * 50.0 * 0.01, 1e-12);
  EXPECT_NEAR(f(0, 0), 5.0, 1e-12);  // node 0 pulled towards node 1
  EXPECT_NEAR(f(0, 1), -5.0, 1e-12);
  Eigen::VectorXd t;
  ComputeSpringTensions(model, x, &t);
  EXPECT_NEAR(t[0], 5.0, 1e-12);
}

TEST(SpringForces, ForcesAreMinusEnergyGradient) {
  const Model model = SmallRandomModel();
  const Eigen::Matrix3Xd x = Perturbed(model, 0.01, 3);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  AccumulateSpringForces(model, x, &f);
  const double h = 1e-7;
  for (int dof : {0, 7, 31, 3 * model.num_nodes() - 1}) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[dof] += h;
    xm.data()[dof] -= h;
    Eigen::Matrix3Xd scratch = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    const double ep = AccumulateSpringForces(model, xp, &scratch);
    scratch.setZero();
    const double em = AccumulateSpringForces(model, xm, &scratch);
    EXPECT_NEAR(-(ep - em) / (2 * h), f.data()[dof], 1e-5 * (1.0 + std::abs(f.data()[dof])));
  }
  // Internal forces are balanced (Newton's third law).
  EXPECT_LT(f.rowwise().sum().norm(), 1e-9);
}

TEST(SpringForces, TangentIsMinusForceJacobian) {
  const Model model = SmallRandomModel();
  const Eigen::Matrix3Xd x = Perturbed(model, 0.01, 5);
  const int dofs = 3 * model.num_nodes();
  std::vector<int> numbering(dofs);
  for (int i = 0; i < dofs; ++i) numbering[i] = i;
  std::vector<Eigen::Triplet<double>> triplets;
  AppendTangentStiffness(model, x, numbering, &triplets);
  Eigen::SparseMatrix<double> k(dofs, dofs);
  k.setFromTriplets(triplets.begin(), triplets.end());
  EXPECT_NEAR((Eigen::MatrixXd(k) - Eigen::MatrixXd(k).transpose()).norm(), 0.0, 1e-9);
  const double h = 1e-7;
  for (int dof : {2, 40, dofs - 2}) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[dof] += h;
    xm.data()[dof] -= h;
    Eigen::Matrix3Xd fp = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    Eigen::Matrix3Xd fm = fp;
    AccumulateSpringForces(model, xp, &fp);
    AccumulateSpringForces(model, xm, &fm);
    const Eigen::VectorXd column = -(Eigen::Map<Eigen::VectorXd>(fp.data(), dofs) -
                                     Eigen::Map<Eigen::VectorXd>(fm.data(), dofs)) /
                                   (2 * h);
    const Eigen::VectorXd analytic = Eigen::MatrixXd(k).col(dof);
    EXPECT_LT((column - analytic).norm(), 1e-5 * (1.0 + analytic.norm()));
  }
}

}  // namespace
}  // namespace msm_sim::core
