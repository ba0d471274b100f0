#pragma once

#include <string>

namespace msm_sim::core {

/// Isotropic linear-elastic material in SI units (Pa, -, kg/m^3).
///
/// Immutable once created; the factory validates its input so that every
/// Material in the program is physically admissible (docs/physics.md §1):
/// E > 0, -1 < nu < 1/2, rho > 0, all finite.
class Material {
 public:
  /// Throws std::invalid_argument naming the offending value and the valid range.
  static Material FromYoungsPoisson(double youngs_modulus, double poisson_ratio, double density);

  double youngs_modulus() const { return youngs_; }
  double poisson_ratio() const { return poisson_; }
  double density() const { return density_; }

  /// K = E / (3(1 - 2 nu)).
  double bulk_modulus() const;
  /// mu = G = E / (2(1 + nu)).
  double shear_modulus() const;
  /// lambda = E nu / ((1 + nu)(1 - 2 nu)).
  double lame_lambda() const;

  /// One-line human-readable description, e.g. for logs.
  std::string Describe() const;

 private:
  Material(double youngs, double poisson, double density)
      : youngs_(youngs), poisson_(poisson), density_(density) {}

  double youngs_;
  double poisson_;
  double density_;
};

}  // namespace msm_sim::core
