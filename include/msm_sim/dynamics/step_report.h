#pragma once

#include <string>

namespace msm_sim::core {

/// What a Step did.
struct StepReport {
  bool accepted = true;
  std::string reason;  ///< why a step was rejected; empty when accepted
  int substeps = 0;
  double substep = 0.0;  ///< s
  int microcollisions = 0;
  /// Implicit integrator: conjugate-gradient iterations summed over the step's substeps (each
  /// costs one stiffness product); 0 for the explicit one.
  int solver_iterations = 0;
};

}  // namespace msm_sim::core
