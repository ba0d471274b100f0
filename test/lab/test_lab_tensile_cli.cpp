// `msm_lab fit --tensile`: E and the spring law from a tensile curve (docs/lab.md "fit"), on the
// shipped Ecoflex 00-30 curve (test/data/README.md): JSON, YAML with provenance, PNG, and the
// one-line refusals of bad files and options.

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

const std::string kEcoflex = std::string(MSM_SIM_TEST_DATA_DIR) + "/ecoflex_00_30_tensile.csv";

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "msm_tensile_" + name;
}

std::string ReadFile(const std::string& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

TEST(LabCliTensile, FitsTheEcoflexCurveWithinFivePercent) {
  const LabRun run = RunLab("fit --tensile " + kEcoflex + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_LE(json["rms_error"].get<double>(), 0.05);  // issue 49: RMS of the largest stress
  EXPECT_GT(json["youngs"].get<double>(), 2e4);
  EXPECT_LT(json["youngs"].get<double>(), 6e4);
  EXPECT_LT(json["alpha"].get<double>(), -1.0);
  EXPECT_GT(json["beta"].get<double>(), 0.0);
  EXPECT_EQ(json["max_strain"].get<double>(), 1.0);
  EXPECT_EQ(json["stress_unit"], "MPa");
  EXPECT_EQ(json["strain_column"], "Engineering Strain");
  EXPECT_DOUBLE_EQ(json["poisson"].get<double>(), 0.49);
}

TEST(LabCliTensile, ColumnsByIndexGiveTheSameFit) {
  const LabRun named = RunLab("fit --tensile " + kEcoflex + " --max-strain 0.5 --json");
  const LabRun indexed = RunLab("fit --tensile " + kEcoflex +
                                " --max-strain 0.5 --strain-column 3 --stress-column 4 "
                                "--stress-unit MPa --json");
  ASSERT_EQ(named.exit_code, 0) << named.err;
  ASSERT_EQ(indexed.exit_code, 0) << indexed.err;
  const auto a = nlohmann::json::parse(named.out), b = nlohmann::json::parse(indexed.out);
  EXPECT_EQ(a["youngs"], b["youngs"]);
  EXPECT_EQ(a["alpha"], b["alpha"]);
  EXPECT_EQ(a["max_strain"].get<double>(), 0.5);
  EXPECT_LE(a["strain_range"][1].get<double>(), 0.5);
}

TEST(LabCliTensile, WritesTheMaterialWithItsProvenanceAndAPlot) {
  const std::string yaml = TempPath("ecoflex.yaml"), png = TempPath("ecoflex.png");
  std::remove(png.c_str());
  const LabRun run = RunLab("fit --tensile " + kEcoflex + " --name ecoflex_00_30 --yaml " + yaml +
                            " --plot " + png + " --density 1070");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"Young's modulus", "spring law       alpha", "RMS error"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
  const std::string entry = ReadFile(yaml);
  for (const std::string& text : std::vector<std::string>{
           "materials:\n  ecoflex_00_30:\n    youngs: ", "    poisson: 0.49\n    density: 1070\n",
           "tensile_law: {alpha: ", "file: \"" + kEcoflex + "\"",
           "strain_column: \"Engineering Strain\"", "stress_column: \"Engineering Stress (MPa)\"",
           "stress_unit: MPa", "strain_range: ["}) {
    EXPECT_NE(entry.find(text), std::string::npos) << text << " in\n" << entry;
  }
  std::ifstream image(png, std::ios::binary);
  char magic[4] = {};
  image.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  std::remove(yaml.c_str());
  std::remove(png.c_str());
}

TEST(LabCliTensile, BadFilesGetOneLineNamingTheRow) {
  const std::string csv = TempPath("bad.csv");
  const std::string header = "x;y\nEngineering Strain;Engineering Stress (MPa)\n";
  const std::pair<std::string, std::string> cases[] = {
      {header, "no data rows"},
      {header + "0.1;0.01\n0.2;abc\n", "tensile CSV line 4: not a number"},
      {header + "0.3;0.01\n0.2;0.02\n", "tensile CSV line 4: strain 0.2"},
      {"strain,stress\n0.1,1\n", "no column header with a column named 'Engineering Strain"},
  };
  for (const auto& [text, message] : cases) {
    std::ofstream(csv) << text;
    const LabRun run = RunLab("fit --tensile " + csv);
    EXPECT_EQ(run.exit_code, 2) << text;
    EXPECT_EQ(CountLines(run.err), 1) << run.err;
    EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  std::remove(csv.c_str());
}

TEST(LabCliTensile, RefusesIndentationOptionsAndAMissingCurve) {
  const std::pair<std::string, std::string> cases[] = {
      {"fit --tensile " + kEcoflex + " --size 0.01 0.01 0.01", "--size applies to fit --indent"},
      {"fit --json", "fit needs --indent FILE"},
      {"fit --max-strain 0.5 --indent " + kEcoflex, "--max-strain requires --tensile"},
      {"fit --tensile " + kEcoflex + " --stress-unit GPa", "--stress-unit"},
      {"fit --tensile " + kEcoflex + " --name 9lives", "not a parameter name"},
  };
  for (const auto& [arguments, message] : cases) {
    const LabRun run = RunLab(arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments;
    EXPECT_EQ(CountLines(run.err), 1) << run.err;
    EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
  }
}

}  // namespace
