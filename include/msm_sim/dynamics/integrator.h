#pragma once

#include <string>

namespace msm_sim::core {

/// How the World's substep turns forces into velocities (docs/physics.md §7 and §7.1).
enum class Integrator {
  /// Position Verlet in substeps no longer than the stable step (conditionally stable).
  kExplicit,
  /// The linearly implicit substep (world.h's class comment): unconditionally stable for linear
  /// springs, so substeps of up to implicit_max_substep, each a conjugate-gradient solve.
  kImplicit,
};

/// "explicit" or "implicit" (for reports).
inline const char* IntegratorName(Integrator integrator) {
  return integrator == Integrator::kImplicit ? "implicit" : "explicit";
}

/// The integrator IntegratorName calls `name`; false (and *integrator unchanged) for any other.
inline bool ParseIntegrator(const std::string& name, Integrator* integrator) {
  for (const Integrator candidate : {Integrator::kExplicit, Integrator::kImplicit}) {
    if (name == IntegratorName(candidate)) {
      *integrator = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace msm_sim::core
