#include "lab_material_command.h"

#include <iomanip>
#include <stdexcept>
#include <string>

#include "lab_report.h"
#include "msm_sim/material/material.h"
#include "msm_sim/material/shore_hardness.h"

namespace msm_sim::lab {
namespace {

// The conversion the arguments ask for; throws std::out_of_range outside its range.
core::ShoreConversion Convert(const HardnessArguments& hardness) {
  return hardness.from_shore_00 ? core::YoungsFromShore00(hardness.shore_00)
                                : core::YoungsFromShoreA(hardness.shore_a);
}

}  // namespace

int RunMaterial(const LabArguments& arguments, std::ostream& out) {
  const HardnessArguments& hardness = arguments.hardness;
  const core::ShoreConversion result = Convert(hardness);
  const char* scale = hardness.from_shore_00 ? "00" : "A";
  double shear_modulus = 0.0;
  if (hardness.has_poisson) {
    // Validates nu the way every model does; the density plays no part here.
    shear_modulus =
        core::Material::FromYoungsPoisson(result.youngs, hardness.poisson, 1000.0).shear_modulus();
  }
  if (arguments.json) {
    Json json{
        {"command", "material"},
        {"shore_a", result.shore_a >= 0.0 ? Json(result.shore_a) : Json(nullptr)},
        {"shore_00", hardness.from_shore_00 ? Json(result.shore_00) : Json(nullptr)},
        {"youngs", result.youngs},
        {"poisson", hardness.has_poisson ? Json(hardness.poisson) : Json(nullptr)},
        {"shear_modulus", hardness.has_poisson ? Json(shear_modulus) : Json(nullptr)},
        {"conversion", result.conversion},
        {"valid_range",
         {{"scale", scale}, {"min", result.valid_range.min}, {"max", result.valid_range.max}}},
        {"uncertainty", result.uncertainty}};
    out << json.dump() << "\n";
    return 0;
  }
  out << std::setprecision(4);
  if (hardness.from_shore_00 && result.shore_a >= 0.0) {
    out << "Shore 00 " << result.shore_00 << " = Shore A " << result.shore_a << "\n";
  }
  // A 00 reading below the comparison table (00 45) has no Shore A equivalent.
  if (result.shore_a >= 0.0) {
    out << "Shore A " << result.shore_a;
  } else {
    out << "Shore 00 " << result.shore_00;
  }
  out << ": E = " << result.youngs << " Pa\n";
  if (hardness.has_poisson) {
    out << "nu = " << hardness.poisson << ": G = " << shear_modulus << " Pa\n";
  }
  out << "conversion: " << result.conversion << "\n"
      << "valid range: Shore " << scale << " " << result.valid_range.min << " to "
      << result.valid_range.max << "\n"
      << "uncertainty: " << result.uncertainty << "\n";
  return 0;
}

}  // namespace msm_sim::lab
