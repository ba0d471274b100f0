// OrientationBarrier (docs/physics.md §4 "Orientation barrier"): which corners a lattice has,
// their volume ratios, and forces, energy and stiffness that agree with each other, alone and
// inside ForceEvaluator's loops.
#include <atomic>
#include <cmath>
#include <memory>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "expect_stiffness.h"
#include "mechanics/node_shares.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/orientation_barrier.h"
#include "perturbed_positions.h"

namespace msm_sim::core {
namespace {

constexpr double kSpacing = 0.1;  // m

Model Block(int cells_per_side, double poisson = 0.3) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d::Constant(cells_per_side * kSpacing);
  options.lattice.spacing = kSpacing;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e4, poisson, 1000.0), options);
}

// The block with its top node layer pushed 30 % of a spacing below the layer under it (the
// fold a squeeze leaves), plus seeded noise so that no two corners are alike.
Eigen::Matrix3Xd Folded(const Model& model, unsigned seed) {
  Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 0.03 * kSpacing, seed);
  const double top = model.rest_positions().row(2).maxCoeff();
  for (int i = 0; i < x.cols(); ++i) {
    if (model.rest_positions()(2, i) > top - 0.5 * kSpacing) x(2, i) -= 1.3 * kSpacing;
  }
  return x;
}

TEST(OrientationBarrier, EveryCellHasEightCornersAndRandomLatticesNone) {
  // 3 x 3 x 3 nodes: 8 cells. 4 x 3 x 2 nodes: 6 cells.
  EXPECT_EQ(OrientationBarrier(Block(3), 1e4, 0.2).num_corners(), 8 * 8);
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(4, 3, 2) * kSpacing;
  options.lattice.spacing = kSpacing;
  const Model box = BuildCubicLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), options);
  EXPECT_EQ(OrientationBarrier(box, 1e4, 0.2).num_corners(), 6 * 8);
  options.construction = CubicConstruction::kElementCorner;  // 5 x 4 x 3 corner nodes
  const Model corners = BuildCubicLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), options);
  EXPECT_EQ(OrientationBarrier(corners, 1e4, 0.2).num_corners(), 4 * 3 * 2 * 8);
  RandomLatticeOptions random;
  random.size = Eigen::Vector3d(0.5, 0.4, 0.3);
  random.lattice.spacing = kSpacing;
  const Model irregular = BuildRandomLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), random);
  EXPECT_EQ(OrientationBarrier(irregular, 1e4, 0.2).num_corners(), 0);
}

TEST(OrientationBarrier, VolumeRatiosFollowTheDeformation) {
  const Model model = Block(3);
  const OrientationBarrier barrier(model, 1e4, 0.2);
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 0.9, -0.4).normalized()).toRotationMatrix();
  const Eigen::Vector3d stretch(1.1, 0.8, 0.5);
  const Eigen::Matrix3Xd rotated = rotation * rest;
  const Eigen::Matrix3Xd stretched = stretch.asDiagonal() * rest;
  Eigen::Matrix3Xd mirrored = rest;
  mirrored.row(2) *= -1.0;
  for (int c = 0; c < barrier.num_corners(); ++c) {
    EXPECT_NEAR(barrier.VolumeRatios(rest)[c], 1.0, 1e-12);
    EXPECT_NEAR(barrier.VolumeRatios(rotated)[c], 1.0, 1e-12);
    EXPECT_NEAR(barrier.VolumeRatios(stretched)[c], stretch.prod(), 1e-12);
    EXPECT_NEAR(barrier.VolumeRatios(mirrored)[c], -1.0, 1e-12);  // turned inside out
  }
  // Nothing above the threshold: a squeeze to J = 0.44 neither stores energy nor pushes.
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  barrier.AccumulateForces(stretched, &forces);
  EXPECT_EQ(forces.norm(), 0.0);
  EXPECT_EQ(barrier.Energy(stretched), 0.0);
  EXPECT_TRUE(barrier.ActiveCorners(stretched).empty());
  EXPECT_EQ(barrier.ActiveCorners(mirrored).size(), static_cast<std::size_t>(64));
}

// A row longer than the screen's chunk of 256 corners: every corner is screened once.
TEST(OrientationBarrier, ScreensLongRowsWhole) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(300, 2, 2) * kSpacing;
  options.lattice.spacing = kSpacing;
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), options);
  const OrientationBarrier barrier(model, 1e4, 0.2);
  ASSERT_EQ(barrier.num_corners(), 299 * 8);
  Eigen::Matrix3Xd mirrored = model.rest_positions();
  mirrored.row(1) *= -1.0;
  const std::vector<int> active = barrier.ActiveCorners(mirrored);
  ASSERT_EQ(active.size(), static_cast<std::size_t>(barrier.num_corners()));
  for (int c = 0; c < barrier.num_corners(); ++c) EXPECT_EQ(active[c], c);
  EXPECT_TRUE(barrier.ActiveCorners(model.rest_positions()).empty());
}

// The screen (float, over padded runs) selects exactly the corners whose double J is below the
// threshold, on a rotated lattice whose rows start and end irregularly.
TEST(OrientationBarrier, ScreenAgreesWithTheVolumeRatios) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(1.0, 0.8, 0.6);
  options.lattice.spacing = kSpacing;
  options.lattice.rotation_axis = Eigen::Vector3d(0.2, 0.9, -0.4);
  options.lattice.rotation_angle = 0.6;
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), options);
  const OrientationBarrier barrier(model, 1e4, 0.6);
  ASSERT_GT(barrier.num_corners(), 1000);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Eigen::Matrix3Xd x = Perturbed(model.rest_positions(), 0.25 * kSpacing, seed);
    const Eigen::VectorXd ratios = barrier.VolumeRatios(x);
    std::vector<int> expected;
    for (int c = 0; c < barrier.num_corners(); ++c) {
      if (ratios[c] < 0.6) expected.push_back(c);
    }
    ASSERT_GT(expected.size(), 100u);
    ASSERT_LT(expected.size(), static_cast<std::size_t>(barrier.num_corners()));
    EXPECT_EQ(barrier.ActiveCorners(x), expected);
  }
}

TEST(OrientationBarrier, ForcesAreMinusTheEnergyGradient) {
  const Model model = Block(3);
  const double modulus = 2e4;
  const OrientationBarrier barrier(model, modulus, 0.3);
  const Eigen::Matrix3Xd x = Folded(model, 7);
  ASSERT_GE(barrier.ActiveCorners(x).size(), static_cast<std::size_t>(8));
  // One fully inverted corner (J = -1) stores 1/2 E (a^3 / 8) (0.3 + 1)^2.
  Eigen::Matrix3Xd mirrored = model.rest_positions();
  mirrored.row(2) *= -1.0;
  EXPECT_NEAR(barrier.Energy(mirrored), 64 * 0.5 * modulus * std::pow(kSpacing, 3) / 8 * 1.69,
              1e-12);
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  barrier.AccumulateForces(x, &forces);
  const double h = 1e-7;
  for (int dof = 0; dof < x.size(); ++dof) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[dof] += h;
    xm.data()[dof] -= h;
    const double gradient = (barrier.Energy(xp) - barrier.Energy(xm)) / (2 * h);
    ASSERT_NEAR(forces.data()[dof], -gradient, 1e-6 * (1.0 + std::abs(gradient))) << dof;
  }
  // Internal forces: no net force, no net moment.
  EXPECT_LT(forces.rowwise().sum().norm(), 1e-9 * forces.norm());
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (int i = 0; i < x.cols(); ++i) moment += x.col(i).cross(forces.col(i));
  EXPECT_LT(moment.norm(), 1e-9 * forces.norm());
}

// K v and diag K of the barrier inside ForceEvaluator against central differences of its forces.
TEST(OrientationBarrier, StiffnessIsTheDerivativeOfTheForces) {
  const Model model = Block(3);
  const auto barrier = std::make_shared<const OrientationBarrier>(model, 2e4, 0.3);
  const Eigen::Matrix3Xd x = Folded(model, 11);
  ForceEvaluator evaluator(model);
  evaluator.set_orientation_barrier(barrier);
  const auto forces = [&](const Eigen::Matrix3Xd& at) {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    ForceEvaluator fresh(model);
    fresh.set_orientation_barrier(barrier);
    fresh.AccumulateForces(at, &f);
    return f;
  };
  std::vector<int> dofs(x.size());
  std::iota(dofs.begin(), dofs.end(), 0);
  ExpectStiffnessIsTheForcesDerivative(&evaluator, forces, x, dofs);
  // Without the curvature the barrier's part of K is c grad J grad J^T: v^T K v >= that of the
  // springs alone for any v.
  ForceEvaluator springs_only(model);
  springs_only.Linearize(x, GeometricStiffness::kDropCompression);
  evaluator.Linearize(x, GeometricStiffness::kDropCompression);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 1.0, seed);
    Eigen::Matrix3Xd with_barrier, without;
    evaluator.ApplyStiffness(v, &with_barrier);
    springs_only.ApplyStiffness(v, &without);
    EXPECT_GT((v.array() * with_barrier.array()).sum(), (v.array() * without.array()).sum());
  }
}

// The barrier's forces and energy are added on every loop: per-spring, vectorised double and
// the single-precision node shares with their stages.
TEST(OrientationBarrier, AddedByEveryForceLoop) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(12, 10, 10) * kSpacing;  // 1,200 nodes: threaded shares
  options.lattice.spacing = kSpacing;
  const Model model = BuildCubicLattice(Material::FromYoungsPoisson(1e4, 0.45, 1000.0), options);
  const auto barrier = std::make_shared<const OrientationBarrier>(model, 1e4, 0.2);
  const Eigen::Matrix3Xd x = Folded(model, 3);
  const Eigen::Matrix3Xd v = Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.1, 4);
  Eigen::Matrix3Xd barrier_forces = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  barrier->AccumulateForces(x, &barrier_forces);
  ASSERT_GT(barrier_forces.norm(), 0.0);
  for (const SpringKernels kernels : {SpringKernels::kPerSpring, SpringKernels::kAuto}) {
    for (const SpringPrecision precision : {SpringPrecision::kDouble, SpringPrecision::kSingle}) {
      ForceEvaluator plain(model, kernels, 2);
      ForceEvaluator guarded(model, kernels, 2);
      plain.set_precision(precision);
      guarded.set_precision(precision);
      guarded.set_orientation_barrier(barrier);
      Eigen::Matrix3Xd without, with;
      plain.SetForces(x, v, 1e-3, &without);
      std::atomic<int> staged{0};  // the stages run on the shares' threads
      internal::NodeStages stages{[](int, int, int) {},
                                  [&](int, int begin, int end) {
                                    staged += end - begin;
                                    // The barrier is in the forces the stage sees.
                                    EXPECT_GT(with.middleCols(begin, end - begin).norm(), 0.0);
                                  },
                                  {}};
      internal::NodeShares::SetForces(&guarded, x, v, 1e-3, &with, stages);
      EXPECT_EQ(staged.load(), model.num_nodes());
      const double scale = without.norm();
      EXPECT_LT((with - without - barrier_forces).norm(), 1e-6 * scale)
          << static_cast<int>(kernels) << " " << static_cast<int>(precision);
      EXPECT_NEAR(guarded.ElasticEnergy(x) - plain.ElasticEnergy(x), barrier->Energy(x),
                  1e-9 * guarded.ElasticEnergy(x));
    }
  }
}

TEST(OrientationBarrier, RejectsBadParameters) {
  const Model model = Block(2);
  EXPECT_THROW(OrientationBarrier(model, -1.0, 0.2), std::invalid_argument);
  EXPECT_THROW(OrientationBarrier(model, std::nan(""), 0.2), std::invalid_argument);
  EXPECT_THROW(OrientationBarrier(model, 1e4, 0.0), std::invalid_argument);
  EXPECT_THROW(OrientationBarrier(model, 1e4, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
