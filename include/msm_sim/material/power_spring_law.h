#pragma once

#include <cmath>

namespace msm_sim::core {

/// The two-parameter spring law of docs/physics.md §4.1, fitted to tensile curves
/// (`msm_lab fit --tensile`). With s = L / L0 the spring's stretch,
///
///     t(L) = k L0 [ (s^alpha - 1) / alpha  +  beta (s - 1)^3 ]
///
/// Its slope at rest is k for every (alpha, beta), so the calibration of §2-§3 is unchanged.
/// alpha = 1, beta = 0 is the linear law and alpha = -1, beta = 0 the carrier law of §4;
/// alpha < -1 softens more in tension (the first term saturates at -k L0 / alpha) and still
/// diverges as L -> 0 (for alpha < 0); beta >= 0 stiffens at large stretch.
struct PowerSpringLaw {
  double alpha = 1.0;  ///< softening exponent (alpha = 0: t = k L0 ln s)
  double beta = 0.0;   ///< stiffening coefficient, >= 0

  /// The stretch term (s^alpha - 1) / alpha, its limit ln s at alpha = 0.
  double PowerTerm(double stretch) const {
    if (std::abs(alpha) < 1e-12) return std::log(stretch);
    return std::expm1(alpha * std::log(stretch)) / alpha;
  }

  /// Tension (N, > 0 stretched) of a spring of stiffness k, rest length l0 and length l > 0.
  double Tension(double k, double l0, double l) const {
    const double s = l / l0;
    const double d = s - 1.0;
    return k * l0 * (PowerTerm(s) + beta * d * d * d);
  }

  /// dt/dL (N/m).
  double TangentStiffness(double k, double l0, double l) const {
    const double s = l / l0;
    const double d = s - 1.0;
    return k * (std::pow(s, alpha - 1.0) + 3.0 * beta * d * d);
  }
};

}  // namespace msm_sim::core
