// Runs the real msm_lab executable's grasp command (issue "Grasp and lift"): its JSON keys, its
// table, and one error line with exit code 2 for every bad combination of shape options.

#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

// A 4 cm sphere at 8 mm (a few hundred nodes), lifted 2 cm over half a second.
const std::string kCoarseSphere =
    "grasp --shape sphere --radius 0.02 --spacing 0.008 --youngs 2e5 --poisson 0.3 "
    "--density 1100 --lift 0.02 --lift-time 0.5";

TEST(LabCliGrasp, JsonHasExactlyTheKeysAndHoldsTheSphere) {
  const LabRun run = RunLab(kCoarseSphere + " --force-ratio 1.5 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(CountLines(run.out), 1) << run.out;
  const auto json = nlohmann::json::parse(run.out);
  std::set<std::string> keys;
  for (const auto& item : json.items()) keys.insert(item.key());
  EXPECT_EQ(keys, (std::set<std::string>{"shape", "friction", "force_ratio", "integrator", "nodes",
                                         "added_mass", "squeeze_force", "rise", "slip", "held",
                                         "max_node_speed", "energy_max", "real_time_factor"}));
  // The sphere's cut cells carry mass scaling's added mass (docs/physics.md §7), at most 1 % of
  // its 37 g.
  EXPECT_GT(json["added_mass"].get<double>(), 0.0);
  EXPECT_LE(json["added_mass"].get<double>(), 0.01 * 4.0 / 3.0 * M_PI * 0.02 * 0.02 * 0.02 * 1100);
  EXPECT_EQ(json["shape"], "sphere");
  EXPECT_TRUE(json["held"].get<bool>());
  EXPECT_GE(json["rise"].get<double>(), 0.98 * 0.02);
  EXPECT_GT(json["real_time_factor"].get<double>(), 0.0);
}

TEST(LabCliGrasp, TableGivesTheSqueezeAndTheVerdict) {
  const LabRun run = RunLab(kCoarseSphere + " --force-ratio 0.6");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"squeeze per pad", "rise", "slip", "verdict          not held"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
}

struct BadInput {
  const char* arguments;
  const char* mentions;
};

class LabCliGraspBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(LabCliGraspBadInput, PrintsOneErrorLineAndExitCode2) {
  const BadInput& bad = GetParam();
  const LabRun run = RunLab(std::string("grasp --youngs 2e5 --poisson 0.3 ") + bad.arguments);
  EXPECT_FALSE(run.signalled);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Contract, LabCliGraspBadInput,
    ::testing::Values(
        BadInput{"--shape sphere --spacing 0.01", "--radius"},
        BadInput{"--shape cylinder --radius 0.02 --spacing 0.01", "--length"},
        BadInput{"--shape box --radius 0.02 --spacing 0.01", "--size"},
        BadInput{"--shape ellipsoid --spacing 0.01", "--size"},
        BadInput{"--shape mesh --spacing 0.01", "--mesh"},
        BadInput{"--shape sphere --radius 0.02", "--spacing"},
        BadInput{"--shape torus --radius 0.02 --spacing 0.01", "--shape"},
        BadInput{"--shape sphere --radius 0.02 --spacing 0.01 --friction 0", "--friction"},
        BadInput{"--shape sphere --radius 0.02 --spacing 0.01 --force-ratio nan", "--force-ratio"},
        BadInput{"--shape sphere --radius -1 --spacing 0.01", "--radius"},
        BadInput{"--shape sphere --radius 0.02 --spacing 0.01 --integrator semi", "integrator"}));

}  // namespace
