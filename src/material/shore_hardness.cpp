#include "msm_sim/material/shore_hardness.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace msm_sim::core {
namespace {

// Shore 00 against Shore A, the durometer comparison table of docs/materials.md (integer
// readings, both columns increasing).
constexpr std::array<std::pair<double, double>, 16> kShore00ToA = {{{45, 5},
                                                                    {55, 10},
                                                                    {62, 15},
                                                                    {70, 20},
                                                                    {76, 25},
                                                                    {80, 30},
                                                                    {83, 35},
                                                                    {86, 40},
                                                                    {88, 45},
                                                                    {90, 50},
                                                                    {91, 55},
                                                                    {93, 60},
                                                                    {94, 65},
                                                                    {95, 70},
                                                                    {97, 75},
                                                                    {98, 80}}};

// Gent's constants (docs/materials.md): E = F / (C h), the durometer's spring force F over its
// indentation h times a length C = 1.37505 mm set by the indenter's shape. F = 56 + 7.62336 S in
// gf, h = 254 - 2.54 S in 0.01 mm (2.54 mm at S = 0, none at S = 100): 0.0981 / 0.137505 is
// (0.00981 N/gf) / (1.37505 mm x 0.01 mm), so that E comes out in N/mm^2 = MPa.
constexpr double kGentForceOffset = 56.0;
constexpr double kGentForcePerPoint = 7.62336;
constexpr double kGentMegapascalScale = 0.0981;
constexpr double kGentGeometry = 0.137505;
constexpr double kGentFullDepth = 254.0;
constexpr double kGentDepthPerPoint = 2.54;

constexpr double kGentMinShoreA = 20.0;
constexpr double kGentMaxShoreA = 90.0;

std::string Number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

void RequireWithin(double value, const ShoreRange& range, const std::string& scale,
                   const std::string& why) {
  if (std::isfinite(value) && value >= range.min && value <= range.max) return;
  throw std::out_of_range("Shore " + scale + " " + Number(value) + " is outside [" +
                          Number(range.min) + ", " + Number(range.max) + "], " + why);
}

}  // namespace

ShoreRange GentShoreARange() { return {kGentMinShoreA, kGentMaxShoreA}; }

ShoreRange Shore00Range() {
  // The table's 00 reading at Shore A 20 (a table row) up to its last row.
  double min = kShore00ToA.back().first;
  for (const auto& [shore_00, shore_a] : kShore00ToA) {
    if (shore_a >= kGentMinShoreA) {
      min = shore_00;
      break;
    }
  }
  return {min, kShore00ToA.back().first};
}

double GentYoungsFromShoreA(double shore_a) {
  RequireWithin(shore_a, GentShoreARange(), "A",
                "where Gent's relation is used (ASTM D2240's reliable readings; outside it no "
                "hardness relation here applies: give youngs)");
  const double force = kGentMegapascalScale * (kGentForceOffset + kGentForcePerPoint * shore_a);
  const double depth = kGentGeometry * (kGentFullDepth - kGentDepthPerPoint * shore_a);
  return force / depth * 1e6;  // MPa to Pa
}

double ShoreAFromShore00(double shore_00) {
  RequireWithin(shore_00, {kShore00ToA.front().first, kShore00ToA.back().first}, "00",
                "the Shore 00 / Shore A comparison table's span");
  for (std::size_t i = 1; i < kShore00ToA.size(); ++i) {
    const auto& [x1, y1] = kShore00ToA[i];
    if (shore_00 > x1) continue;
    const auto& [x0, y0] = kShore00ToA[i - 1];
    return y0 + (y1 - y0) * (shore_00 - x0) / (x1 - x0);
  }
  return kShore00ToA.back().second;
}

ShoreConversion YoungsFromShoreA(double shore_a) {
  ShoreConversion result;
  result.youngs = GentYoungsFromShoreA(shore_a);
  result.shore_a = shore_a;
  result.conversion = "Gent (1958) relation for Shore A";
  result.valid_range = GentShoreARange();
  return result;
}

ShoreConversion YoungsFromShore00(double shore_00) {
  RequireWithin(shore_00, Shore00Range(), "00",
                "the readings the Shore 00 / Shore A comparison table maps to Shore A 20 to 80, "
                "where Gent's relation is used (softer materials: measure E, e.g. a tensile test)");
  ShoreConversion result;
  result.shore_a = ShoreAFromShore00(shore_00);
  result.youngs = GentYoungsFromShoreA(result.shore_a);
  result.shore_00 = shore_00;
  result.conversion =
      "Shore 00 to Shore A by the durometer comparison table, then Gent (1958) relation";
  result.valid_range = Shore00Range();
  return result;
}

}  // namespace msm_sim::core
