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
constexpr double kMinShoreA = 10.0;

// The ASTM D2240 type 00 durometer (docs/materials.md): a sphere of radius 1.19 mm (2.38 mm
// diameter), 2.54 mm of travel from a reading of 100 to 0, and a spring force rising linearly
// from 0.203 N at 0 to 1.111 N at 100. Lengths in mm and forces in N give E in MPa.
constexpr double kType00RadiusMm = 1.19;
constexpr double kType00FullDepthMm = 2.54;
constexpr double kType00ForceOffsetN = 0.203;
constexpr double kType00ForcePerPointN = 0.00908;
constexpr double kIncompressible = 0.75;  // 1 - nu^2 at nu = 0.5

constexpr double kSphereMinShore00 = 10.0;
constexpr double kSphereMaxShore00 = 70.0;  // = Shore A 20, where Gent's relation takes over
constexpr double kMaxShore00 = 98.0;        // the comparison table's last row

constexpr const char* kGentUncertainty =
    "tens of percent (hardness-to-modulus correlations scatter; see docs/materials.md)";
constexpr const char* kSphereUncertainty =
    "up to a factor of 2 (soft silicones' datasheet moduli lie within 0.5 to 2 times it; see "
    "docs/materials.md)";
constexpr const char* kSphereConversion =
    "Sneddon (1965) sphere indentation by the ASTM D2240 type 00 durometer";

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

// Linear interpolation in the comparison table, from the 00 column to the A column or back.
// Precondition: value within the table's span on its column.
double InterpolateTable(double value, bool from_shore_00) {
  const auto column = [from_shore_00](const std::pair<double, double>& row, bool input) {
    return input == from_shore_00 ? row.first : row.second;
  };
  for (std::size_t i = 1; i < kShore00ToA.size(); ++i) {
    const double x1 = column(kShore00ToA[i], true);
    if (value > x1) continue;
    const double x0 = column(kShore00ToA[i - 1], true);
    const double y0 = column(kShore00ToA[i - 1], false);
    const double y1 = column(kShore00ToA[i], false);
    return y0 + (y1 - y0) * (value - x0) / (x1 - x0);
  }
  return column(kShore00ToA.back(), false);
}

// Sneddon's sphere: the contact radius a in (0, radius) at which the depth
// (a/2) ln((R+a)/(R-a)) equals `depth` (increasing in a, so bisection).
double SneddonContactRadius(double depth, double radius) {
  double low = 0.0;
  double high = radius;
  for (int i = 0; i < 200 && high - low > 1e-15 * radius; ++i) {
    const double a = 0.5 * (low + high);
    const double depth_at_a = 0.5 * a * std::log((radius + a) / (radius - a));
    (depth_at_a < depth ? low : high) = a;
  }
  return 0.5 * (low + high);
}

}  // namespace

ShoreRange ShoreARange() { return {kMinShoreA, kGentMaxShoreA}; }

ShoreRange GentShoreARange() { return {kGentMinShoreA, kGentMaxShoreA}; }

ShoreRange Shore00Range() { return {kSphereMinShore00, kMaxShore00}; }

ShoreRange SphereShore00Range() { return {kSphereMinShore00, kSphereMaxShore00}; }

double GentYoungsFromShoreA(double shore_a) {
  RequireWithin(shore_a, GentShoreARange(), "A",
                "where Gent's relation is used (ASTM D2240's reliable readings; outside it no "
                "hardness relation here applies: give youngs)");
  const double force = kGentMegapascalScale * (kGentForceOffset + kGentForcePerPoint * shore_a);
  const double depth = kGentGeometry * (kGentFullDepth - kGentDepthPerPoint * shore_a);
  return force / depth * 1e6;  // MPa to Pa
}

double SphereYoungsFromShore00(double shore_00) {
  RequireWithin(shore_00, SphereShore00Range(), "00", "where the type 00 sphere relation is used");
  const double radius = kType00RadiusMm;
  const double depth = kType00FullDepthMm * (1.0 - shore_00 / 100.0);
  const double force = kType00ForceOffsetN + kType00ForcePerPointN * shore_00;
  const double a = SneddonContactRadius(depth, radius);
  const double log_term = std::log((radius + a) / (radius - a));
  const double shape = 0.5 * (a * a + radius * radius) * log_term - a * radius;  // mm^2
  return kIncompressible * force / shape * 1e6;                                  // MPa to Pa
}

double ShoreAFromShore00(double shore_00) {
  RequireWithin(shore_00, {kShore00ToA.front().first, kShore00ToA.back().first}, "00",
                "the Shore 00 / Shore A comparison table's span");
  return InterpolateTable(shore_00, true);
}

ShoreConversion YoungsFromShoreA(double shore_a) {
  RequireWithin(shore_a, ShoreARange(), "A",
                "the readings converted here (Gent's relation from 20, the Shore 00 sphere "
                "relation below; softer materials: read the 00 scale, or give youngs)");
  ShoreConversion result;
  result.shore_a = shore_a;
  result.valid_range = ShoreARange();
  if (shore_a >= kGentMinShoreA) {
    result.youngs = GentYoungsFromShoreA(shore_a);
    result.conversion = "Gent (1958) relation for Shore A";
    result.uncertainty = kGentUncertainty;
    return result;
  }
  const double shore_00 = InterpolateTable(shore_a, false);
  result.youngs = SphereYoungsFromShore00(shore_00);
  result.conversion = "Shore A to Shore 00 " + Number(shore_00) +
                      " by the durometer comparison table, then " + kSphereConversion;
  result.uncertainty = kSphereUncertainty;
  return result;
}

ShoreConversion YoungsFromShore00(double shore_00) {
  RequireWithin(shore_00, Shore00Range(), "00",
                "the readings converted here (the type 00 sphere relation to 70, the Shore 00 / "
                "Shore A table and Gent's relation above; otherwise give youngs)");
  ShoreConversion result;
  result.shore_00 = shore_00;
  result.valid_range = Shore00Range();
  if (shore_00 < kSphereMaxShore00) {
    result.youngs = SphereYoungsFromShore00(shore_00);
    if (shore_00 >= kShore00ToA.front().first) result.shore_a = ShoreAFromShore00(shore_00);
    result.conversion = kSphereConversion;
    result.uncertainty = kSphereUncertainty;
    return result;
  }
  result.shore_a = ShoreAFromShore00(shore_00);
  result.youngs = GentYoungsFromShoreA(result.shore_a);
  result.conversion =
      "Shore 00 to Shore A by the durometer comparison table, then Gent (1958) relation";
  result.uncertainty = kGentUncertainty;
  return result;
}

}  // namespace msm_sim::core
