#pragma once

#include <cmath>
#include <string>

namespace msm_sim::core {

/// How a spring's tension depends on its length (docs/physics.md §4). Both laws have the same
/// small-strain stiffness k, so calibration does not depend on the choice.
enum class SpringLaw {
  /// Hooke: t = k (L - L0). Finite force at L = 0, so a strongly compressed network can invert.
  kLinear,
  /// Carrier model: t = k L0 (L - L0) / L, W = k L0^2 (dL/L0 - ln(1 + dL/L0)). The compressive
  /// force diverges as L -> 0, so a spring cannot collapse.
  kNonlinear,
};

/// Parses "linear" / "nonlinear"; returns false for anything else.
bool ParseSpringLaw(const std::string& name, SpringLaw* law);

/// Tension (N, > 0 stretched) of a spring of stiffness k, rest length l0 and length l.
template <SpringLaw Law>
inline double SpringTension(double k, double l0, double l) {
  if constexpr (Law == SpringLaw::kLinear) {
    return k * (l - l0);
  } else {
    return k * l0 * (l - l0) / l;
  }
}

/// dt/dL (N/m).
template <SpringLaw Law>
inline double SpringTangentStiffness(double k, double l0, double l) {
  if constexpr (Law == SpringLaw::kLinear) {
    return k;
  } else {
    return k * l0 * l0 / (l * l);
  }
}

/// Stored energy (J).
template <SpringLaw Law>
inline double SpringEnergy(double k, double l0, double l) {
  const double stretch = l - l0;
  if constexpr (Law == SpringLaw::kLinear) {
    return 0.5 * k * stretch * stretch;
  } else {
    return k * l0 * l0 * (stretch / l0 - std::log1p(stretch / l0));
  }
}

}  // namespace msm_sim::core
