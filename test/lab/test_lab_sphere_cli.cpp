// Runs the real msm_lab executable's sphere commands (issue "Real time at real resolution"):
// `realtime` and `indent`, their outputs, error lines and exit codes.

#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

// 4 x 4 x 2 cm at a = 5 mm: 256 nodes.
const std::string kSmallBlock = "--size 0.04 0.04 0.02 --spacing 0.005 --poisson 0.25";

TEST(LabCliRealtime, JsonHasExactlyTheIssuesKeys) {
  const LabRun run = RunLab("realtime " + kSmallBlock + " --seconds 0.05 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(CountLines(run.out), 1) << run.out;
  const auto json = nlohmann::json::parse(run.out);
  std::set<std::string> keys;
  for (const auto& item : json.items()) keys.insert(item.key());
  EXPECT_EQ(keys, (std::set<std::string>{"nodes", "added_mass", "springs", "integrator", "step",
                                         "substeps", "wall_per_simulated_second",
                                         "real_time_factor", "peak_force"}));
  EXPECT_EQ(json["nodes"], 256);
  EXPECT_EQ(json["integrator"], "explicit");
  EXPECT_EQ(json["step"], 1e-3);
  EXPECT_GE(json["substeps"].get<int>(), 1);
  EXPECT_GT(json["peak_force"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(json["real_time_factor"].get<double>(),
                   1.0 / json["wall_per_simulated_second"].get<double>());
}

TEST(LabCliRealtime, ImplicitIntegratorTakesOneSubstepPerStep) {
  const LabRun run =
      RunLab("realtime " + kSmallBlock + " --seconds 0.02 --integrator implicit --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["integrator"], "implicit");
  EXPECT_EQ(json["substeps"], 1);
  const LabRun table = RunLab("realtime " + kSmallBlock + " --seconds 0.02 --integrator implicit");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("CG iterations per step"), std::string::npos) << table.out;
}

TEST(LabCliRealtime, TableUsesTheIssuesBlockByDefault) {
  // 10 x 10 x 5 cm, rho 1100: 0.55 kg; at a = 1 cm 10 x 10 x 5 nodes.
  const LabRun run = RunLab("realtime --spacing 0.01 --poisson 0.49 --seconds 0.02");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (const char* text : {"real-time factor", "0.55 kg", "500", "explicit", "peak force"}) {
    EXPECT_NE(run.out.find(text), std::string::npos) << text << " in\n" << run.out;
  }
}

// --surface-dispersion reaches the model (docs/physics.md §7, "A softer outer layer"): the
// realtime block at nu = 0.49 takes 11 substeps per ms at half the bulk and 10 at a quarter
// instead of 15, and the table says so.
TEST(LabCliRealtime, ASofterOuterLayerTakesFewerSubsteps) {
  const std::string block = "realtime --spacing 0.005 --poisson 0.49 --seconds 0.003";
  const LabRun plain = RunLab(block + " --json");
  const LabRun softer = RunLab(block + " --surface-dispersion 0.5 --json");
  const LabRun quarter = RunLab(block + " --surface-dispersion 0.25 --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(softer.exit_code, 0) << softer.err;
  ASSERT_EQ(quarter.exit_code, 0) << quarter.err;
  const int plain_substeps = nlohmann::json::parse(plain.out)["substeps"];
  const int softer_substeps = nlohmann::json::parse(softer.out)["substeps"];
  const int quarter_substeps = nlohmann::json::parse(quarter.out)["substeps"];
  EXPECT_EQ(plain_substeps, 15);
  EXPECT_EQ(softer_substeps, 11);
  EXPECT_EQ(quarter_substeps, 10);
  // --time-step-safety scales the substep: at 0.4 instead of 0.8, twice as many (rounded up).
  const LabRun half = RunLab(block + " --time-step-safety 0.4 --json");
  ASSERT_EQ(half.exit_code, 0) << half.err;
  const int half_substeps = nlohmann::json::parse(half.out)["substeps"];
  EXPECT_GE(half_substeps, 2 * plain_substeps - 1);
  EXPECT_LE(half_substeps, 2 * plain_substeps);
  const LabRun table = RunLab(block + " --surface-dispersion 0.5");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("outer layer keeping 0.5 of its bulk"), std::string::npos) << table.out;
}

TEST(LabCliIndent, JsonProfileRowsAreDepthForceHertz) {
  const LabRun run =
      RunLab("indent " + kSmallBlock + " --youngs 2e5 --sphere-radius 0.01 --depth 0.002 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["nodes"], 256);
  // The sphere first touches the lattice touch_depth below the surface (8 nodes a side: its axis
  // falls between four nodes), then presses to 2 mm below it at 5 mm/s, in rows of 2 mm / 50.
  const double touch_depth = json["touch_depth"].get<double>();
  EXPECT_GT(touch_depth, 0.0);
  EXPECT_LT(touch_depth, 1e-3);
  EXPECT_GT(json["seconds"].get<double>(), (0.002 - touch_depth) / 0.005);
  ASSERT_NEAR(static_cast<double>(json["profile"].size()), (0.002 - touch_depth) / 4e-5, 1.0);
  for (const auto& row : json["profile"]) {
    ASSERT_EQ(row.size(), 3u);
    for (const auto& value : row) EXPECT_TRUE(value.is_number());
  }
  EXPECT_NEAR(json["profile"].back()[0].get<double>(), 0.002, 1e-4);
  EXPECT_EQ(json["integrator"], "explicit");
  const LabRun implicit = RunLab("indent " + kSmallBlock +
                                 " --youngs 2e5 --sphere-radius 0.01 --depth 0.001 "
                                 "--integrator implicit --json");
  ASSERT_EQ(implicit.exit_code, 0) << implicit.err;
  EXPECT_EQ(nlohmann::json::parse(implicit.out)["integrator"], "implicit");
  const LabRun table =
      RunLab("indent " + kSmallBlock + " --youngs 2e5 --sphere-radius 0.01 --depth 0.001");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("Hertz [N]"), std::string::npos) << table.out;
}

// --friction sets the sphere-block Coulomb coefficient. On this coarse block at nu 0.49 the
// default 0.5 holds the few nodes under the curved sphere from sliding outwards (docs/physics.md
// §7.1): frictionless, the force at 2 mm is 12 % lower (8.84 against 10.08 N, measured); the
// table says which coefficient was used.
TEST(LabCliIndent, FrictionIsTheSpheresAndZeroPressesLess) {
  const std::string indent =
      "indent --size 0.04 0.04 0.02 --spacing 0.005 --poisson 0.49 --youngs 2e5 "
      "--sphere-radius 0.01 --depth 0.002 --json";
  const LabRun with = RunLab(indent);
  const LabRun without = RunLab(indent + " --friction 0");
  ASSERT_EQ(with.exit_code, 0) << with.err;
  ASSERT_EQ(without.exit_code, 0) << without.err;
  const double f_with = nlohmann::json::parse(with.out)["profile"].back()[1].get<double>();
  const double f_without = nlohmann::json::parse(without.out)["profile"].back()[1].get<double>();
  EXPECT_GT(f_without, 0.0);
  EXPECT_LT(f_without, 0.95 * f_with);
  const LabRun table = RunLab("indent " + kSmallBlock +
                              " --youngs 2e5 --sphere-radius 0.01 --depth 0.001 --friction 0.3");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("friction 0.3"), std::string::npos) << table.out;
}

struct BadInput {
  const char* arguments;
  const char* mentions;
};

class LabCliSphereBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(LabCliSphereBadInput, PrintsOneErrorLineAndExitCode2) {
  const BadInput& bad = GetParam();
  const LabRun run = RunLab(bad.arguments);
  EXPECT_FALSE(run.signalled);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Contract, LabCliSphereBadInput,
    ::testing::Values(
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0.01 --depth -0.001",
                 "--depth"},
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0 --depth 0.001",
                 "--sphere-radius"},
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0.01",
                 "--depth"},
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0.01 --depth 0.05",
                 "height"},
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0.01 --depth 0.001 --frobnicate",
                 "frobnicate"},
        BadInput{"realtime --spacing 0.01 --poisson 0.25 --seconds 0", "--seconds"},
        BadInput{"realtime --spacing 0.01 --poisson 0.25 --integrator semi", "integrator"},
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0.01 --depth 0.001 --integrator verlet",
                 "integrator"},
        BadInput{"indent --size 0.04 0.04 0.02 --spacing 0.005 --youngs 2e5 --poisson 0.25 "
                 "--sphere-radius 0.01 --depth 0.001 --friction -0.5",
                 "--friction"},
        BadInput{"realtime --spacing 0.01 --poisson 0.7", "Poisson"},
        BadInput{"realtime --spacing 0.01 --poisson 0.25 --time-step-safety 1.5",
                 "--time-step-safety"},
        BadInput{"realtime --poisson 0.25", "--spacing"}));

}  // namespace
