// Hardness to modulus (docs/materials.md): Gent's relation against the hand-evaluated table of
// docs/materials.md, the Shore 00 path against the comparison table's rows, and the ranges.
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

TEST(ShoreHardness, BothScalesIncreaseMonotonically) {
  double previous = 0.0;
  for (double shore_a = GentShoreARange().min; shore_a <= GentShoreARange().max; shore_a += 0.25) {
    const double youngs = GentYoungsFromShoreA(shore_a);
    EXPECT_GT(youngs, previous) << shore_a;
    previous = youngs;
  }
  previous = 0.0;
  double previous_a = 0.0;
  for (double shore_00 = Shore00Range().min; shore_00 <= Shore00Range().max; shore_00 += 0.25) {
    const ShoreConversion result = YoungsFromShore00(shore_00);
    EXPECT_GT(result.youngs, previous) << shore_00;
    EXPECT_GT(result.shore_a, previous_a) << shore_00;
    previous = result.youngs;
    previous_a = result.shore_a;
  }
}

TEST(ShoreHardness, RangesFollowTheTableAndGent) {
  EXPECT_EQ(GentShoreARange().min, 20.0);
  EXPECT_EQ(GentShoreARange().max, 90.0);
  // The table's row at Shore A 20 is 00 70; its last row, 00 98, is Shore A 80.
  EXPECT_EQ(Shore00Range().min, 70.0);
  EXPECT_EQ(Shore00Range().max, 98.0);
}

TEST(ShoreHardness, OutOfRangeReadingsAreRefusedWithOneLine) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double shore_a : {19.9, 90.1, -5.0, 100.0, nan, inf}) {
    EXPECT_THROW(YoungsFromShoreA(shore_a), std::out_of_range) << shore_a;
  }
  // 00 30 is Ecoflex 00-30's datasheet hardness: below the table's mapping to Shore A 20.
  for (const double shore_00 : {69.9, 98.1, 30.0, nan, -inf}) {
    EXPECT_THROW(YoungsFromShore00(shore_00), std::out_of_range) << shore_00;
  }
  try {
    YoungsFromShore00(30.0);
    ADD_FAILURE();
  } catch (const std::out_of_range& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("[70, 98]"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace msm_sim::core
