#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/material/material.h"

namespace msm_sim::core {
namespace {

TEST(Material, DerivesModuliFromYoungsAndPoisson) {
  const Material steel = Material::FromYoungsPoisson(210e9, 0.3, 7850.0);
  EXPECT_NEAR(steel.bulk_modulus(), 210e9 / (3.0 * 0.4), 1.0);
  EXPECT_NEAR(steel.shear_modulus(), 210e9 / 2.6, 1.0);
  EXPECT_NEAR(steel.lame_lambda(), 210e9 * 0.3 / (1.3 * 0.4), 1.0);
  // Round trip through the Lame constants (docs/physics.md §1).
  const double mu = steel.shear_modulus();
  const double lambda = steel.lame_lambda();
  EXPECT_NEAR(mu * (3 * lambda + 2 * mu) / (lambda + mu), 210e9, 1e-3);
  EXPECT_NEAR(lambda / (2 * (lambda + mu)), 0.3, 1e-12);
}

TEST(Material, CauchySolidHasEqualLameConstants) {
  const Material m = Material::FromYoungsPoisson(1.0, 0.25, 1.0);
  EXPECT_NEAR(m.lame_lambda(), m.shear_modulus(), 1e-15);
}

TEST(Material, RejectsInvalidValuesWithAMessageNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double e : {0.0, -1.0, nan, inf}) {
    EXPECT_THROW(Material::FromYoungsPoisson(e, 0.25, 1.0), std::invalid_argument) << e;
  }
  for (const double nu : {-1.0, -1.5, 0.5, 0.7, nan}) {
    EXPECT_THROW(Material::FromYoungsPoisson(1.0, nu, 1.0), std::invalid_argument) << nu;
  }
  for (const double rho : {0.0, -5.0, nan}) {
    EXPECT_THROW(Material::FromYoungsPoisson(1.0, 0.25, rho), std::invalid_argument) << rho;
  }
  try {
    Material::FromYoungsPoisson(1.0, 0.5, 1.0);
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("Poisson"), std::string::npos);
  }
  EXPECT_NO_THROW(Material::FromYoungsPoisson(1.0, -0.99, 1.0));
  EXPECT_NO_THROW(Material::FromYoungsPoisson(1.0, 0.499, 1.0));
}

}  // namespace
}  // namespace msm_sim::core
