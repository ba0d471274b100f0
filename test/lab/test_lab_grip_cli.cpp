// Runs the real msm_lab executable's grip command (issue "real time"): its outputs, error lines
// and exit codes.

#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

// The default 4 cm cube at a = 1 cm (64 nodes, 70 g), lifted for 0.5 s.
const std::string kCoarseGrip = "grip --spacing 0.01 --poisson 0.45 --lift-time 0.5";

TEST(LabCliGrip, JsonHasExactlyTheKeysAndHoldsAboveTheWeight) {
  const LabRun run = RunLab(kCoarseGrip + " --ratio 1.3 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(CountLines(run.out), 1) << run.out;
  const auto json = nlohmann::json::parse(run.out);
  std::set<std::string> keys;
  for (const auto& item : json.items()) keys.insert(item.key());
  EXPECT_EQ(keys, (std::set<std::string>{"ratio", "integrator", "nodes", "added_mass", "weight",
                                         "normal_force", "lift_normal_force", "mu", "slip",
                                         "max_slip", "seconds_lifted", "held"}));
  EXPECT_EQ(json["added_mass"], 0.0);  // a box has no cut cells
  EXPECT_EQ(json["nodes"], 64);
  EXPECT_EQ(json["integrator"], "explicit");
  EXPECT_NEAR(json["weight"].get<double>(), 0.04 * 0.04 * 0.04 * 1100 * 9.81, 1e-9);
  // mu comes from the measured normal force: 2 mu F_n = 1.3 m g.
  EXPECT_NEAR(2 * json["mu"].get<double>() * json["normal_force"].get<double>(),
              1.3 * json["weight"].get<double>(), 1e-9);
  EXPECT_TRUE(json["held"].get<bool>());
  EXPECT_LT(json["max_slip"].get<double>(), 1e-3);
}

TEST(LabCliGrip, SlidesOutBelowTheWeightWithEitherIntegrator) {
  for (const char* integrator : {"explicit", "implicit"}) {
    const LabRun run = RunLab(kCoarseGrip + " --ratio 0.6 --integrator " + integrator + " --json");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["integrator"], integrator);
    EXPECT_FALSE(json["held"].get<bool>());
    EXPECT_LT(json["seconds_lifted"].get<double>(), 0.5);  // out of the jaws early
  }
}

TEST(LabCliGrip, TableGivesTheForcesAndTheVerdict) {
  const LabRun run = RunLab(kCoarseGrip);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"F_n per jaw", "mu", "slip", "verdict          held", "0.0704 kg"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
}

struct BadInput {
  const char* arguments;
  const char* mentions;
};

class LabCliGripBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(LabCliGripBadInput, PrintsOneErrorLineAndExitCode2) {
  const BadInput& bad = GetParam();
  const LabRun run = RunLab(bad.arguments);
  EXPECT_FALSE(run.signalled);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Contract, LabCliGripBadInput,
    ::testing::Values(BadInput{"grip --spacing 0.01 --poisson 0.45 --ratio 0", "--ratio"},
                      BadInput{"grip --spacing 0.01 --poisson 0.45 --squeeze nan", "--squeeze"},
                      BadInput{"grip --spacing 0.01 --poisson 0.45 --integrator semi",
                               "integrator"},
                      BadInput{"grip --poisson 0.45", "--spacing"}));

}  // namespace
