#pragma once

#include <random>

#include <Eigen/Core>

namespace msm_sim::core {

/// x0 plus seeded Gaussian noise of standard deviation `amplitude` on every coordinate.
inline Eigen::Matrix3Xd Perturbed(const Eigen::Matrix3Xd& x0, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, amplitude);
  Eigen::Matrix3Xd x = x0;
  for (int i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  return x;
}

}  // namespace msm_sim::core
