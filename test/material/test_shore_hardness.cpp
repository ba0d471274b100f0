// Hardness to modulus (docs/materials.md): Gent's relation and the type 00 sphere relation against
// the hand-evaluated tables of docs/materials.md, the Shore 00 path against the comparison table's
// rows, soft silicones' datasheet moduli within the stated uncertainty, and the ranges.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "msm_sim/material/shore_hardness.h"

namespace msm_sim::core {
namespace {

// docs/materials.md table 1: Gent's relation evaluated by hand to 4 significant figures, so the
// tolerance is half a unit in the 4th figure.
TEST(ShoreHardness, GentMatchesTheTabulatedModuli) {
  const struct {
    double shore_a, youngs_mpa;
  } rows[] = {{30.0, 1.142}, {50.0, 2.456}, {70.0, 5.521}};
  for (const auto& row : rows) {
    const ShoreConversion result = YoungsFromShoreA(row.shore_a);
    EXPECT_NEAR(result.youngs / 1e6, row.youngs_mpa, 5e-4 * row.youngs_mpa) << row.shore_a;
    EXPECT_EQ(result.shore_a, row.shore_a);
    EXPECT_LT(result.shore_00, 0.0);
  }
}

// Gent's E = F / (C h) with ASTM D2240's type A spring force, 0.55 + 0.075 S N, and full
// indentation 2.5 mm, with Gent's C = 1.37505 mm: an independent check of the transcribed force
// constants (Gent's 2.54 mm full indentation and force constants make them differ by about 2 %).
TEST(ShoreHardness, GentAgreesWithTheAstmSpringForce) {
  const double geometry_mm = 1.37505;
  for (const double shore_a : {20.0, 45.0, 80.0}) {
    const double force = 0.55 + 0.075 * shore_a;
    const double depth_mm = 2.5 * (1.0 - shore_a / 100.0);
    const double youngs_mpa = force / (geometry_mm * depth_mm);
    EXPECT_NEAR(GentYoungsFromShoreA(shore_a) / 1e6 / youngs_mpa, 1.0, 0.025) << shore_a;
  }
}

// docs/materials.md table 2 (the Shore 00 / Shore A comparison): its rows 00 76, 90 and 95 are
// Shore A 25, 50 and 70, which Gent's relation turns into table 1's moduli.
TEST(ShoreHardness, Shore00MatchesTheComparisonTableRows) {
  const struct {
    double shore_00, shore_a, youngs_mpa;
  } rows[] = {{76.0, 25.0, 0.9235}, {90.0, 50.0, 2.456}, {95.0, 70.0, 5.521}};
  for (const auto& row : rows) {
    const ShoreConversion result = YoungsFromShore00(row.shore_00);
    EXPECT_DOUBLE_EQ(result.shore_a, row.shore_a) << row.shore_00;
    EXPECT_EQ(result.shore_00, row.shore_00);
    EXPECT_NEAR(result.youngs / 1e6, row.youngs_mpa, 5e-4 * row.youngs_mpa) << row.shore_00;
  }
}

// docs/materials.md table 3: the type 00 sphere relation (Sneddon) evaluated by a separate
// script to 4 significant figures; 00 55 is Shore A 10 by the comparison table.
TEST(ShoreHardness, SphereRelationMatchesTheTabulatedModuli) {
  const struct {
    double shore_00, youngs_kpa;
  } rows[] = {{10.0, 54.01}, {30.0, 121.4}, {50.0, 265.0}, {55.0, 328.0}, {70.0, 694.8}};
  for (const auto& row : rows) {
    EXPECT_NEAR(SphereYoungsFromShore00(row.shore_00) / 1e3, row.youngs_kpa, 5e-4 * row.youngs_kpa)
        << row.shore_00;
  }
}

// The must-show readings: Ecoflex 00-30 and a Shore A 10 silicone convert, by the sphere relation.
TEST(ShoreHardness, SoftSiliconesConvert) {
  const ShoreConversion gel = YoungsFromShore00(30.0);
  EXPECT_NEAR(gel.youngs, 121.4e3, 0.1e3);
  EXPECT_LT(gel.shore_a, 0.0);  // below the comparison table: no Shore A equivalent
  EXPECT_EQ(gel.shore_00, 30.0);
  EXPECT_NE(gel.conversion.find("Sneddon"), std::string::npos) << gel.conversion;
  EXPECT_NE(gel.uncertainty.find("factor of 2"), std::string::npos) << gel.uncertainty;
  EXPECT_EQ(gel.valid_range.min, 10.0);
  EXPECT_EQ(gel.valid_range.max, 98.0);

  const ShoreConversion rubber = YoungsFromShoreA(10.0);  // = Shore 00 55 by the table
  EXPECT_DOUBLE_EQ(rubber.youngs, SphereYoungsFromShore00(55.0));
  EXPECT_EQ(rubber.shore_a, 10.0);
  EXPECT_LT(rubber.shore_00, 0.0);
  EXPECT_NE(rubber.conversion.find("00 55"), std::string::npos) << rubber.conversion;
  EXPECT_EQ(rubber.valid_range.min, 10.0);
  EXPECT_EQ(rubber.valid_range.max, 90.0);
  EXPECT_DOUBLE_EQ(YoungsFromShore00(55.0).shore_a, 10.0);
}

// docs/materials.md table 4: Smooth-On's datasheet 100 % moduli (psi), E = 3 M100 / 1.75 (an
// incompressible neo-Hookean solid at stretch 2), against the conversion: within the stated
// uncertainty, a factor of 2 on the sphere relation (and on Gent's, for Dragon Skin 20 and 30).
TEST(ShoreHardness, DatasheetModuliLieWithinTheStatedUncertainty) {
  const double pascal_per_psi = 6894.757;
  const struct {
    const char* name;
    bool shore_00;
    double reading, modulus_100_psi;
  } rows[] = {{"Ecoflex 00-10", true, 10.0, 8.0},    {"Ecoflex 00-20", true, 20.0, 8.0},
              {"Ecoflex 00-30", true, 30.0, 10.0},   {"Ecoflex 00-50", true, 50.0, 12.0},
              {"Dragon Skin 10", false, 10.0, 22.0}, {"Dragon Skin 15", false, 15.0, 40.0},
              {"Dragon Skin 20", false, 20.0, 49.0}, {"Dragon Skin 30", false, 30.0, 86.0}};
  for (const auto& row : rows) {
    const double datasheet = 3.0 * row.modulus_100_psi * pascal_per_psi / 1.75;
    const double converted =
        row.shore_00 ? YoungsFromShore00(row.reading).youngs : YoungsFromShoreA(row.reading).youngs;
    EXPECT_GE(converted / datasheet, 0.5) << row.name;
    EXPECT_LE(converted / datasheet, 2.0) << row.name;
  }
}

// A second manufacturer's silicone, measured rather than from a datasheet (docs/materials.md,
// section 5): Polytek PlatSil Gel-10, Shore A 10, pulled to 100 % strain in the Soft Robotics
// Materials Database (github.com/LucMarechal/Soft-Robotics-Materials-Database,
// Tensile-Tests-Data/PlatSil Gel 10.csv: engineering stress 0.146955 MPa at engineering strain
// 1.0). Converted the same way, within the same factor of 2.
TEST(ShoreHardness, AMeasuredPolytekGelLiesWithinTheStatedUncertainty) {
  const double measured = 3.0 * 0.146955e6 / 1.75;
  const double converted = YoungsFromShoreA(10.0).youngs;
  EXPECT_GE(converted / measured, 0.5);
  EXPECT_LE(converted / measured, 2.0);
}

// Where the sphere relation hands over to Gent's (00 70 = Shore A 20) the two agree within 6 %.
TEST(ShoreHardness, SphereAndGentAgreeWhereTheyMeet) {
  const double sphere = SphereYoungsFromShore00(70.0);
  EXPECT_NEAR(sphere / GentYoungsFromShoreA(20.0), 1.0, 0.06);
  EXPECT_LT(sphere, YoungsFromShore00(70.0).youngs);  // so E still increases across the step
}

TEST(ShoreHardness, BothScalesIncreaseMonotonically) {
  double previous = 0.0;
  for (double shore_a = ShoreARange().min; shore_a <= ShoreARange().max; shore_a += 0.25) {
    const double youngs = YoungsFromShoreA(shore_a).youngs;
    EXPECT_GT(youngs, previous) << shore_a;
    previous = youngs;
  }
  previous = 0.0;
  double previous_a = -1.0;
  for (double shore_00 = Shore00Range().min; shore_00 <= Shore00Range().max; shore_00 += 0.25) {
    const ShoreConversion result = YoungsFromShore00(shore_00);
    EXPECT_GT(result.youngs, previous) << shore_00;
    if (result.shore_a >= 0.0) {
      EXPECT_GT(result.shore_a, previous_a) << shore_00;
    }
    previous = result.youngs;
    previous_a = result.shore_a;
  }
}

TEST(ShoreHardness, RangesFollowTheTableGentAndTheSphere) {
  EXPECT_EQ(ShoreARange().min, 10.0);
  EXPECT_EQ(ShoreARange().max, 90.0);
  EXPECT_EQ(GentShoreARange().min, 20.0);
  EXPECT_EQ(GentShoreARange().max, 90.0);
  EXPECT_EQ(Shore00Range().min, 10.0);
  EXPECT_EQ(Shore00Range().max, 98.0);  // the comparison table's last row, Shore A 80
  EXPECT_EQ(SphereShore00Range().min, 10.0);
  EXPECT_EQ(SphereShore00Range().max, 70.0);  // the table's row at Shore A 20
}

TEST(ShoreHardness, OutOfRangeReadingsAreRefusedWithOneLine) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double shore_a : {9.9, 90.1, -5.0, 100.0, nan, inf}) {
    EXPECT_THROW(YoungsFromShoreA(shore_a), std::out_of_range) << shore_a;
  }
  for (const double shore_00 : {9.9, 98.1, 5.0, nan, -inf}) {
    EXPECT_THROW(YoungsFromShore00(shore_00), std::out_of_range) << shore_00;
  }
  EXPECT_THROW(GentYoungsFromShoreA(15.0), std::out_of_range);
  EXPECT_THROW(SphereYoungsFromShore00(75.0), std::out_of_range);
  EXPECT_THROW(SphereYoungsFromShore00(nan), std::out_of_range);
  const auto expect_one_line_naming = [](auto convert, const std::string& range) {
    try {
      convert();
      ADD_FAILURE() << range;
    } catch (const std::out_of_range& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(range), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  expect_one_line_naming([] { YoungsFromShoreA(5.0); }, "Shore A 5 is outside [10, 90]");
  expect_one_line_naming([] { YoungsFromShore00(5.0); }, "Shore 00 5 is outside [10, 98]");
}

}  // namespace
}  // namespace msm_sim::core
