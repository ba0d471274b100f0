#include "msm_sim/material/material.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace msm_sim::core {

Material Material::FromYoungsPoisson(double youngs_modulus, double poisson_ratio, double density) {
  std::ostringstream error;
  if (!std::isfinite(youngs_modulus) || youngs_modulus <= 0.0) {
    error << "Young's modulus must be a finite value > 0 Pa, got " << youngs_modulus;
  } else if (!std::isfinite(poisson_ratio) || poisson_ratio <= -1.0 || poisson_ratio >= 0.5) {
    error << "Poisson's ratio must lie in the open interval (-1, 0.5), got " << poisson_ratio;
  } else if (!std::isfinite(density) || density <= 0.0) {
    error << "density must be a finite value > 0 kg/m^3, got " << density;
  }
  if (!error.str().empty()) throw std::invalid_argument(error.str());
  return Material(youngs_modulus, poisson_ratio, density);
}

double Material::bulk_modulus() const { return youngs_ / (3.0 * (1.0 - 2.0 * poisson_)); }

double Material::shear_modulus() const { return youngs_ / (2.0 * (1.0 + poisson_)); }

double Material::lame_lambda() const {
  return youngs_ * poisson_ / ((1.0 + poisson_) * (1.0 - 2.0 * poisson_));
}

std::string Material::Describe() const {
  std::ostringstream out;
  out << "E = " << youngs_ << " Pa, nu = " << poisson_ << ", rho = " << density_ << " kg/m^3";
  return out.str();
}

}  // namespace msm_sim::core
