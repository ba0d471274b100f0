#pragma once
// Shared by the calibration tests: the compression experiment with default options (or another
// imposed strain), asserting that the static solve converged.

#include <gtest/gtest.h>

#include "msm_sim/experiments/compression_experiment.h"

namespace msm_sim::core::testing {

inline CompressionExperimentResult Compress(const Model& model, const Eigen::Vector3d& size,
                                            double strain = CompressionExperimentOptions{}.strain) {
  CompressionExperimentOptions options;
  options.body_size = size;
  options.strain = strain;
  const CompressionExperimentResult result = RunCompressionExperiment(model, options);
  EXPECT_TRUE(result.solver.converged) << result.solver.message;
  return result;
}

}  // namespace msm_sim::core::testing
