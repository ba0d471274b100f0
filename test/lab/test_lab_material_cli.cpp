// `msm_lab material` (issue "Hardness → modulus"): the published conversions at three readings
// per scale (docs/materials.md tables 1 and 2), soft silicones by the type 00 sphere relation
// (table 3), the contract keys, and out-of-range readings refused with one error line and exit
// code 1.

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

nlohmann::json RunJson(const std::string& arguments) {
  const LabRun run = RunLab("material " + arguments + " --json");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return nlohmann::json::parse(run.out);
}

// docs/materials.md table 1: Gent's relation by hand, 4 significant figures.
TEST(LabCliMaterial, ShoreAMatchesGentsTabulatedModuli) {
  const struct {
    const char* shore_a;
    double youngs;
  } rows[] = {{"30", 1.142e6}, {"50", 2.456e6}, {"70", 5.521e6}};
  for (const auto& row : rows) {
    const auto json = RunJson(std::string("--shore-a ") + row.shore_a);
    EXPECT_NEAR(json["youngs"].get<double>(), row.youngs, 5e-4 * row.youngs) << row.shore_a;
    EXPECT_TRUE(json["shore_00"].is_null());
    EXPECT_EQ(json["valid_range"]["scale"], "A");
    EXPECT_EQ(json["valid_range"]["min"], 10.0);
    EXPECT_EQ(json["valid_range"]["max"], 90.0);
  }
}

// docs/materials.md table 2 rows 00 76, 90, 95 = Shore A 25, 50, 70, then table 1.
TEST(LabCliMaterial, Shore00MatchesTheComparisonTableThenGent) {
  const struct {
    const char* shore_00;
    double shore_a, youngs;
  } rows[] = {{"76", 25.0, 0.9235e6}, {"90", 50.0, 2.456e6}, {"95", 70.0, 5.521e6}};
  for (const auto& row : rows) {
    const auto json = RunJson(std::string("--shore-00 ") + row.shore_00);
    EXPECT_DOUBLE_EQ(json["shore_a"].get<double>(), row.shore_a) << row.shore_00;
    EXPECT_NEAR(json["youngs"].get<double>(), row.youngs, 5e-4 * row.youngs) << row.shore_00;
    EXPECT_EQ(json["valid_range"]["scale"], "00");
    EXPECT_EQ(json["valid_range"]["min"], 10.0);
    EXPECT_EQ(json["valid_range"]["max"], 98.0);
  }
}

// docs/materials.md table 3: Ecoflex 00-30's hardness and a Shore A 10 silicone's (00 55 by the
// comparison table) by the type 00 sphere relation, with its own uncertainty.
TEST(LabCliMaterial, SoftSiliconesUseTheSphereRelation) {
  const auto gel = RunJson("--shore-00 30");
  EXPECT_NEAR(gel["youngs"].get<double>(), 121.4e3, 0.1e3);
  EXPECT_TRUE(gel["shore_a"].is_null());  // below the comparison table
  EXPECT_EQ(gel["shore_00"], 30.0);
  EXPECT_NE(gel["conversion"].get<std::string>().find("Sneddon"), std::string::npos);
  EXPECT_NE(gel["uncertainty"].get<std::string>().find("factor of 2"), std::string::npos);
  const auto rubber = RunJson("--shore-a 10");
  EXPECT_NEAR(rubber["youngs"].get<double>(), 328.0e3, 0.2e3);
  EXPECT_EQ(rubber["shore_a"], 10.0);
  EXPECT_TRUE(rubber["shore_00"].is_null());
  EXPECT_EQ(rubber["valid_range"]["min"], 10.0);

  const LabRun run = RunLab("material --shore-00 30 --poisson 0.49");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"Shore 00 30: E = 1.214e+05 Pa", "Sneddon",
                           "valid range: Shore 00 10 to 98", "uncertainty: up to a factor of 2"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
}

TEST(LabCliMaterial, JsonHasTheContractKeysAndThePoissonGivesTheShearModulus) {
  const auto json = RunJson("--shore-a 50 --poisson 0.45");
  for (const char* key : {"command", "shore_a", "shore_00", "youngs", "poisson", "shear_modulus",
                          "conversion", "valid_range", "uncertainty"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json.size(), 9u);
  EXPECT_NE(json["conversion"].get<std::string>().find("Gent"), std::string::npos);
  EXPECT_NEAR(json["shear_modulus"].get<double>(), json["youngs"].get<double>() / 2.9, 1.0);
}

TEST(LabCliMaterial, TableNamesTheConversionRangeAndUncertainty) {
  const LabRun run = RunLab("material --shore-00 90 --poisson 0.45");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"Shore 00 90 = Shore A 50", "E = 2.456e+06 Pa", "G = ", "Gent",
                           "valid range: Shore 00 10 to 98", "uncertainty: tens of percent"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
}

struct BadReading {
  const char* arguments;
  int exit_code;
  const char* mentions;
};

class LabCliMaterialBad : public ::testing::TestWithParam<BadReading> {};

TEST_P(LabCliMaterialBad, PrintsOneErrorLineAndTheExitCode) {
  const BadReading& bad = GetParam();
  const LabRun run = RunLab(std::string("material ") + bad.arguments);
  EXPECT_FALSE(run.signalled);
  EXPECT_EQ(run.exit_code, bad.exit_code) << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;
}

// Readings outside a conversion's range: exit 1 (the conversion cannot be made); malformed
// arguments: exit 2, as for every command.
INSTANTIATE_TEST_SUITE_P(
    Contract, LabCliMaterialBad,
    ::testing::Values(BadReading{"--shore-a 5", 1, "Shore A 5 is outside [10, 90]"},
                      BadReading{"--shore-a 95 --json", 1, "Shore A 95 is outside [10, 90]"},
                      BadReading{"--shore-00 5", 1, "Shore 00 5 is outside [10, 98]"},
                      BadReading{"--shore-00 99", 1, "Shore 00 99 is outside [10, 98]"},
                      BadReading{"--shore-a nan", 1, "outside [10, 90]"},
                      BadReading{"--shore-a 50 --poisson 0.5", 2, "Poisson"},
                      BadReading{"--shore-a soft", 2, "--shore-a"},
                      BadReading{"--shore-a 50 --shore-00 90", 2, "excludes"},
                      BadReading{"", 2, "--shore-a S or --shore-00 S"}));

}  // namespace
