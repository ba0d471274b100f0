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

  /// d^2t/dL^2 (N/m^2).
  double Curvature(double k, double l0, double l) const {
    const double s = l / l0;
    return k / l0 * ((alpha - 1.0) * std::pow(s, alpha - 2.0) + 6.0 * beta * (s - 1.0));
  }

  /// Stored energy (J), the integral of Tension from l0 to l (docs/physics.md §4.1):
  /// W = k L0^2 [ ((s^(alpha+1) - 1) / (alpha+1) - (s - 1)) / alpha + beta (s - 1)^4 / 4 ].
  double Energy(double k, double l0, double l) const {
    const double d = (l - l0) / l0;
    const double d2 = d * d;
    return k * l0 * l0 * (PowerIntegral(d) + 0.25 * beta * d2 * d2);
  }

 private:
  /// The integral of PowerTerm from 1 to s = 1 + d. With u = ln s and phi(c) = (e^(c u) - 1) / c
  /// it is (phi(alpha + 1) - phi(1)) / alpha; near alpha = 0 that quotient cancels, so there
  /// it is phi'(1) + alpha phi''(1) / 2 (s ln s - s + 1 at alpha = 0, error O(alpha^2)).
  double PowerIntegral(double d) const {
    const double u = std::log1p(d);
    if (std::abs(alpha) < 1e-4) {
      const double s = 1.0 + d;
      return s * u - d + 0.5 * alpha * (s * u * u - 2.0 * s * u + 2.0 * d);
    }
    return (Phi(alpha + 1.0, u) - d) / alpha;
  }

  /// phi(c) = expm1(c u) / c, its limit u at c = 0 (alpha = -1: the carrier's s - 1 - ln s).
  static double Phi(double c, double u) {
    if (std::abs(c) < 1e-12) return u;
    return std::expm1(c * u) / c;
  }
};

}  // namespace msm_sim::core
