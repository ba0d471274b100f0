// Reading uniaxial tensile curves (ReadTensileCurve): separators, header blocks, columns by name
// or index, stress units, and bad rows named by their line.

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "msm_sim/experiments/tensile_curve.h"

namespace msm_sim::core {
namespace {

TensileCurve Read(const std::string& text, const TensileColumns& columns = {}) {
  std::istringstream csv(text);
  return ReadTensileCurve(csv, columns);
}

// The message ReadTensileCurve refuses `text` with ("" if it reads it).
std::string Refusal(const std::string& text, const TensileColumns& columns = {}) {
  try {
    Read(text, columns);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

const char* const kSemicolonFile =
    "PARAMETER;INFO;URL;;\n"
    "Specimen Thickness (mm);3;;;\n"
    "Material;EcoFlex30;;;\n"
    ";;;;\n"
    "Time (s);True Strain;True Stress (MPa);Engineering Strain;Engineering Stress (MPa)\n"
    "0.3;0.06574;0.0015951;0.06795;0.00149\n"
    "0.4;0.08695;0.0037370;0.09084;0.00343\n";

TEST(TensileCurve, ReadsASemicolonFileWithAHeaderBlockByDefaultColumns) {
  const TensileCurve curve = Read(kSemicolonFile);
  ASSERT_EQ(curve.points.size(), 2u);
  EXPECT_DOUBLE_EQ(curve.points[0].strain, 0.06795);
  EXPECT_DOUBLE_EQ(curve.points[1].stress, 3430.0);  // MPa from the column's name
  EXPECT_EQ(curve.strain_column, "Engineering Strain");
  EXPECT_EQ(curve.stress_column, "Engineering Stress (MPa)");
  EXPECT_EQ(curve.stress_unit, "MPa");
}

TEST(TensileCurve, ChoosesColumnsByNameOrIndex) {
  TensileColumns named;
  named.strain_name = "true strain";
  named.stress_name = "True Stress (MPa)";
  const TensileCurve by_name = Read(kSemicolonFile, named);
  EXPECT_DOUBLE_EQ(by_name.points[0].strain, 0.06574);
  TensileColumns indexed;
  indexed.strain_index = 3;
  indexed.stress_index = 4;
  const TensileCurve by_index = Read(kSemicolonFile, indexed);
  EXPECT_DOUBLE_EQ(by_index.points[1].stress, 3430.0);
  EXPECT_EQ(by_index.stress_column, "Engineering Stress (MPa)");
}

TEST(TensileCurve, ReadsACommaFileWithAGivenUnitAndNoHeader) {
  TensileColumns columns;
  columns.strain_index = 0;
  columns.stress_index = 1;
  columns.stress_unit = "kPa";
  const TensileCurve curve = Read("0.0,0.0\n0.1,12.5\n\n0.2,20\n", columns);
  ASSERT_EQ(curve.points.size(), 3u);
  EXPECT_DOUBLE_EQ(curve.points[2].stress, 2e4);
  TensileColumns named;
  named.strain_name = "Strain (%)";
  named.stress_name = "stress [Pa]";
  const TensileCurve percent = Read("Strain (%),Stress [Pa]\n0,0\n50,1000\n", named);
  EXPECT_DOUBLE_EQ(percent.points[1].strain, 0.5);  // a column named with % holds percent
  EXPECT_DOUBLE_EQ(percent.points[1].stress, 1000.0);
}

TEST(TensileCurve, RefusesMissingColumnsAndUnits) {
  EXPECT_NE(Refusal("a;b\n1;2\n").find("no column header with a column named 'Engineering"),
            std::string::npos);
  TensileColumns no_unit;
  no_unit.strain_name = "e";
  no_unit.stress_name = "s";
  EXPECT_NE(Refusal("e,s\n0.1,2\n", no_unit).find("states no unit; give --stress-unit"),
            std::string::npos);
  TensileColumns contradiction;
  contradiction.stress_unit = "kPa";
  EXPECT_NE(Refusal(kSemicolonFile, contradiction).find("contradicts"), std::string::npos);
  EXPECT_NE(Refusal("Engineering Strain;Engineering Stress (MPa)\n").find("no data rows"),
            std::string::npos);
}

TEST(TensileCurve, BadRowsAreNamedByTheirLine) {
  const std::string header = "Engineering Strain;Engineering Stress (MPa)\n";
  EXPECT_NE(Refusal(header + "0.1;0.01\n0.2;x\n").find("tensile CSV line 3: not a number"),
            std::string::npos);
  EXPECT_NE(Refusal(header + "0.1;0.01\n0.2\n").find("line 3: expected at least 2 fields"),
            std::string::npos);
  EXPECT_NE(Refusal(header + "0.1;nan\n").find("line 2: NaN"), std::string::npos);
  EXPECT_NE(Refusal(header + "0.2;0.01\n0.1;0.02\n").find("line 3: strain 0.1"), std::string::npos);
}

TEST(TensileCurve, ReadsTheShippedEcoflexCurve) {
  std::ifstream file(std::string(MSM_SIM_TEST_DATA_DIR) + "/ecoflex_00_30_tensile.csv");
  ASSERT_TRUE(file.good());
  const TensileCurve curve = ReadTensileCurve(file, TensileColumns{});
  EXPECT_EQ(curve.points.size(), 86u);  // 104 lines: 17 of header block, the column header
  EXPECT_NEAR(curve.points.front().stress, 1490.0, 1e-9);
  EXPECT_LE(curve.points.back().strain, 2.0);
}

}  // namespace
}  // namespace msm_sim::core
