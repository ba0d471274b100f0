#pragma once
// Shared by the calibration tests: the compression experiment with default options, asserting
// that the static solve converged.

#include <gtest/gtest.h>

#include "msm_sim/core/compression_test.h"

namespace msm_sim::core::testing {

inline CompressionTestResult Compress(const Model& model, const Eigen::Vector3d& size) {
  CompressionTestOptions options;
  options.body_size = size;
  const CompressionTestResult result = RunCompressionTest(model, options);
  EXPECT_TRUE(result.solver.converged) << result.solver.message;
  return result;
}

}  // namespace msm_sim::core::testing
