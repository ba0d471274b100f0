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
  /// Explicit: the factor by which the World divides the stable substep (1, or a power of 2 once
  /// a step has diverged; WorldOptions::max_substep_refinement).
  int substep_refinement = 1;
  /// Why this step was taken again with finer substeps (the divergence CheckSane found at the
  /// coarser ones); empty if it was not.
  std::string refined_because;
};

}  // namespace msm_sim::core
