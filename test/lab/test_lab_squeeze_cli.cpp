// Runs the real msm_lab executable's squeeze command (issue 61): its JSON profile, its table, and
// one error line with a non-zero exit code for every input it refuses.

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

// A 4 cm sphere at 8 mm (a few hundred nodes), squeezed by 4 mm in all.
const std::string kCoarseSphere =
    "squeeze --shape sphere --radius 0.02 --spacing 0.008 --youngs 2e5 --poisson 0.3 "
    "--density 1100 --approach 0.004 --speed 0.01 --samples 8";

TEST(LabCliSqueeze, JsonProfileRowsGrowWithTheApproach) {
  const LabRun run = RunLab(kCoarseSphere + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(CountLines(run.out), 1) << run.out;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["command"], "squeeze");
  const auto& profile = json["profile"];
  ASSERT_GE(profile.size(), 6u);
  ASSERT_EQ(json["area"].size(), profile.size());
  double approach = 0.0, force = 0.0;
  for (const auto& row : profile) {
    ASSERT_EQ(row.size(), 3u);  // approach_m, force_N, contact_radius_m
    EXPECT_GT(row[0].get<double>(), approach);
    EXPECT_GE(row[2].get<double>(), 0.0);
    approach = row[0].get<double>();
    force = row[1].get<double>();
  }
  EXPECT_NEAR(approach, 0.004, 0.0005);
  EXPECT_GT(force, 0.0);
  // The force grows with the approach: the last row's is more than the middle one's.
  EXPECT_GT(force, profile[profile.size() / 2][1].get<double>());
}

TEST(LabCliSqueeze, TableGivesTheProfileColumns) {
  const LabRun run = RunLab(kCoarseSphere);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"approach [mm]", "force [N]", "patch radius [mm]", "patch area"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
}

// Squeezed to 60 % of its height without the orientation barrier, the 8 mm lattice folds: the run
// says so on one line and prints no force.
TEST(LabCliSqueeze, AFoldedLatticeIsReportedNotMeasured) {
  const LabRun run = RunLab(
      "squeeze --shape sphere --radius 0.02 --spacing 0.008 --youngs 2e5 --poisson 0.3 "
      "--approach 0.025 --speed 0.02 --orientation-threshold 0 --json");
  EXPECT_EQ(run.exit_code, 1) << run.out;
  EXPECT_TRUE(run.out.empty()) << run.out;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_NE(run.err.find("turned inside out"), std::string::npos) << run.err;
}

struct BadInput {
  const char* arguments;
  const char* mentions;
};

class LabCliSqueezeBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(LabCliSqueezeBadInput, PrintsOneErrorLineAndExitCode2) {
  const BadInput& bad = GetParam();
  const LabRun run = RunLab(std::string("squeeze --youngs 2e5 --poisson 0.3 --shape sphere "
                                        "--radius 0.02 --spacing 0.008 ") +
                            bad.arguments);
  EXPECT_FALSE(run.signalled);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Contract, LabCliSqueezeBadInput,
    ::testing::Values(BadInput{"--approach 0", "--approach"},
                      BadInput{"--approach -0.001", "--approach"}, BadInput{"", "--approach"},
                      BadInput{"--approach 0.05", "plates meet"},
                      BadInput{"--approach 0.002 --friction -0.1", "--friction"},
                      BadInput{"--approach 0.002 --speed 0", "--speed"}));

}  // namespace
