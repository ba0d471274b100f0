#pragma once

namespace msm_sim::core {

/// How a force evaluation computes the eMSM momentum dispersion (docs/physics.md §3).
enum class DispersionPasses {
  /// Exact: a second loop over the springs redistributes this evaluation's accumulators.
  kTwoPass,
  /// One loop: redistributes the accumulators of the previous evaluation (the first evaluation
  /// is two-pass). About half the cost of the second pass, one evaluation of lag.
  kOnePass,
};

}  // namespace msm_sim::core
