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
  /// The fitted two-parameter law of docs/physics.md §4.1 (PowerSpringLaw, whose model-wide
  /// alpha and beta the Model carries); alpha = 1, beta = 0 is kLinear, alpha = -1 kNonlinear.
  kPower,
};

/// Parses "linear" / "nonlinear" / "power"; returns false for anything else. kPower needs its
/// (alpha, beta) from elsewhere (a scene's tensile_law, msm_lab --alpha / --beta).
bool ParseSpringLaw(const std::string& name, SpringLaw* law);

/// The laws as types with Tension (N, > 0 stretched), TangentStiffness (dt/dL, N/m), Curvature
/// (d^2t/dL^2, N/m^2) and Energy (J) of a spring of stiffness k, rest length l0 and length l: the
/// force loops are templated on them (PowerSpringLaw, power_spring_law.h, is the third), so the
/// law is chosen once per loop.
struct LinearSpringLaw {
  static double Tension(double k, double l0, double l) { return k * (l - l0); }
  static double TangentStiffness(double k, double, double) { return k; }
  static double Curvature(double, double, double) { return 0.0; }
  static double Energy(double k, double l0, double l) {
    const double stretch = l - l0;
    return 0.5 * k * stretch * stretch;
  }
};

struct CarrierSpringLaw {
  static double Tension(double k, double l0, double l) { return k * l0 * (l - l0) / l; }
  static double TangentStiffness(double k, double l0, double l) { return k * l0 * l0 / (l * l); }
  static double Curvature(double k, double l0, double l) {
    return -2.0 * k * l0 * l0 / (l * l * l);
  }
  static double Energy(double k, double l0, double l) {
    const double stretch = l - l0;
    return k * l0 * l0 * (stretch / l0 - std::log1p(stretch / l0));
  }
};

}  // namespace msm_sim::core
