#pragma once
// The single-precision spring loops' test blocks and forces, and the bound within which they must
// match the double loops (test_single_precision_kernels.cpp, test_single_precision_shares.cpp).
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {

inline Eigen::Matrix3Xd Forces(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& x,
                               const Eigen::Matrix3Xd& v, double beta) {
  // Added to a non-zero start, as a step does.
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Ones(3, x.cols());
  evaluator->AccumulateForces(x, v, beta, &forces);
  return forces;
}

inline Eigen::Matrix3Xd Forces(const Model& model, SpringPrecision precision,
                               const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double beta,
                               int threads = 1) {
  const SpringKernels kernels =
      precision == SpringPrecision::kSingle ? SpringKernels::kAuto : SpringKernels::kPerSpring;
  ForceEvaluator evaluator(model, kernels, threads);
  evaluator.set_precision(precision);
  return Forces(&evaluator, x, v, beta);
}

// The largest difference single precision may make to a node's force: every spring's length is
// resolved to about 2^-24 of the body's extent (positions relative to node 0), so its tension to
// k 2^-24 extent, its dispersed tension to (1 + 2|q|) times that. The errors of a node's springs
// add like random numbers: measured 0.8-1.2 of that unit on these blocks, so 4 units bound them.
// A kernel error shows far above it: a 1e-4 relative error in the b ends' dispersed tension
// fails the eMSM cases, a swapped end weight fails them by orders of magnitude.
inline double SingleBound(const Model& model) {
  const Eigen::Vector3d extent =
      model.rest_positions().rowwise().maxCoeff() - model.rest_positions().rowwise().minCoeff();
  const double k_max =
      *std::max_element(model.spring_stiffness().begin(), model.spring_stiffness().end());
  const double q = std::abs(model.dispersion_fraction());
  return 4.0 * (1.0 + 2.0 * q) * k_max * std::ldexp(extent.maxCoeff(), -24);
}

inline void ExpectClose(const Model& model, const Eigen::Matrix3Xd& single,
                        const Eigen::Matrix3Xd& reference) {
  ASSERT_EQ(single.cols(), reference.cols());
  ASSERT_TRUE(single.allFinite());
  const double bound = SingleBound(model);
  const double scale = (reference.array() - 1.0).abs().maxCoeff();  // the start was 1
  ASSERT_GT(scale, 1e3 * bound) << "the perturbation must load the springs well above the bound";
  EXPECT_LE((single - reference).cwiseAbs().maxCoeff(), bound) << "force scale " << scale;
}

// Node-centred block: surface springs of unequal end weights, rows that end at the surface
// (phantoms bridge them).
inline Model Block(double poisson, double spacing = 0.01) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.1, 0.06, 0.05);
  options.lattice.spacing = spacing;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1000.0), options);
}

}  // namespace msm_sim::core
