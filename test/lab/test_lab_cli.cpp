// Runs the real msm_lab executable and checks the command-line contract: outputs, error lines and
// exit codes (0 ok, 1 failed run, 2 bad arguments; never a signal).

#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "lab_arguments.h"
#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

const char* kCubic =
    "compression --model cubic --size 1 0.5 0.5 --spacing 0.0625 --youngs 2e5 --poisson 0.25";

TEST(LabCli, CompressionJsonHasTheContractKeys) {
  const LabRun run = RunLab(std::string(kCubic) + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  for (const char* key : {"youngs_target", "poisson_target", "youngs_measured", "poisson_measured",
                          "nodes", "springs", "mean_springs_per_node", "seconds"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["nodes"], 16 * 8 * 8);
  EXPECT_NEAR(json["youngs_measured"].get<double>() / 2e5, 1.0, 0.03);
  EXPECT_NEAR(json["poisson_measured"].get<double>(), 0.25, 0.01);
}

TEST(LabCli, CompressionTableIsReadable) {
  const LabRun run = RunLab(std::string(kCubic) + " --construction corner --rotate 0 0 1 10");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("E [Pa]"), std::string::npos);
  EXPECT_NE(run.out.find("nodes"), std::string::npos);
}

TEST(LabCli, RandomCompressionIsDeterministicPerSeed) {
  const std::string command =
      "compression --model random --size 1.2 0.6 0.6 --spacing 0.1 --youngs 1e4 --poisson 0.25 "
      "--seed 7 --min-dist 0.8 --max-dist 1.9 --json";
  const LabRun first = RunLab(command);
  const LabRun second = RunLab(command);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto a = nlohmann::json::parse(first.out);
  const auto b = nlohmann::json::parse(second.out);
  EXPECT_EQ(a["youngs_measured"], b["youngs_measured"]);
  EXPECT_EQ(a["springs"], b["springs"]);
}

TEST(LabCli, DeflectionReportsProfileAndTheory) {
  const LabRun run = RunLab(
      "deflection --model cubic --size 4 1 1 --spacing 0.25 --youngs 1e5 --poisson 0.25 "
      "--force 0.1 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_GT(json["tip_deflection"].get<double>(), 0.0);
  EXPECT_GT(json["theory_tip_deflection"].get<double>(), 0.0);
  ASSERT_EQ(json["profile"].size(), 17u);  // the clamped face, then 16 node layers
  EXPECT_EQ(json["profile"][0].size(), 3u);
}

struct BadInput {
  const char* arguments;
  int exit_code;
  const char* mentions;
};

class LabCliBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(LabCliBadInput, PrintsOneClearErrorLineAndExitCode) {
  const BadInput& bad = GetParam();
  const LabRun run = RunLab(bad.arguments);
  EXPECT_FALSE(run.signalled);
  EXPECT_EQ(run.exit_code, bad.exit_code) << run.err;
  EXPECT_EQ(CountLines(run.err), 1) << run.err;
  EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << run.err;
}

INSTANTIATE_TEST_SUITE_P(
    Contract, LabCliBadInput,
    ::testing::Values(
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs -5 "
                 "--poisson 0.25",
                 2, "Young's modulus"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.5",
                 2, "Poisson"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25 --density 0",
                 2, "density"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs nan "
                 "--poisson 0.25",
                 2, "Young's modulus"},
        BadInput{"compression --model cubic --size 1 -0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25",
                 2, "size"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 3 --youngs 1e5 "
                 "--poisson 0.25",
                 2, "larger than"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25 --frobnicate",
                 2, "frobnicate"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing", 2, "spacing"},
        BadInput{"compression --model cubic --size 1 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25",
                 2, "size"},
        BadInput{"compression --model foam --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25",
                 2, "model"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson -1",
                 2, "Poisson"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25 --spring cubic",
                 2, "spring"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.45 --surface-dispersion 0",
                 2, "--surface-dispersion"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.45 --surface-dispersion 1.5",
                 2, "--surface-dispersion"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.45 --mass-scaling 0.5",
                 2, "--mass-scaling"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.45 --mass-scaling -1",
                 2, "--mass-scaling"},
        BadInput{"compression --model random --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.45 --surface-dispersion 0.5",
                 2, "surface_dispersion is for node-centred cubic"},
        BadInput{"poisson-sweep --model cubic --targets 0.2 0.7", 2, "Poisson"},
        BadInput{"poisson-sweep --model cubic --targets 0.2 --plot /nonexistent/dir/plot.png", 1,
                 "plotting failed"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 0.1 --youngs abc "
                 "--poisson 0.25",
                 2, "youngs"},
        BadInput{"compression --model cubic --size 1 0.5 0.5 --spacing 1e-5 --youngs 1e5 "
                 "--poisson 0.25",
                 2, "use a larger spacing"},
        BadInput{"stretch", 2, "stretch"}, BadInput{"", 2, "subcommand"},
        BadInput{"compression --model random --size 1 0.5 0.5 --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.25 --min-dist 1.4 --max-dist 2",
                 1, "random sequential addition"},
        // Mesh input (issue "Any mesh in").
        BadInput{"build --model cubic --spacing 0.1 --youngs 1e5 --poisson 0.3", 2, "--mesh"},
        BadInput{"build --mesh x.stl --model cubic --youngs 1e5 --poisson 0.3", 2,
                 "--target-nodes"},
        BadInput{"build --mesh x.stl --model cubic --spacing 0.1 --target-nodes 10 --youngs 1e5 "
                 "--poisson 0.3",
                 2, "excludes"},
        BadInput{"build --mesh x.stl --model cubic --spacing 0.1 --youngs 1e5 --poisson 0.3 "
                 "--antialias maybe",
                 2, "antialias"},
        BadInput{"build --mesh x.stl --model cubic --spacing 0.1 --youngs 1e5 --poisson 0.3 "
                 "--scale 0",
                 2, "scale"},
        BadInput{"compression --mesh x.stl --size 1 1 1 --model cubic --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.3",
                 2, "excludes"},
        BadInput{"compression --model cubic --spacing 0.1 --youngs 1e5 --poisson 0.3", 2, "--size"},
        BadInput{"build --mesh /nonexistent.stl --model cubic --spacing 0.1 --youngs 1e5 "
                 "--poisson 0.3",
                 1, "no such file"},
        BadInput{"build --mesh " MSM_SIM_TEST_DATA_DIR "/meshes/open_box.obj --model cubic "
                 "--spacing 0.1 --youngs 1e5 --poisson 0.3",
                 1, "4 boundary edges"},
        BadInput{"build --mesh " MSM_SIM_TEST_DATA_DIR "/meshes/cube_100mm.stl --model cubic "
                 "--spacing 0.1 --youngs 1e5 --poisson 0.3",
                 1, "right scale" /* 100 m across without the mm scale: says which to give */},
        BadInput{"build --mesh " MSM_SIM_TEST_DATA_DIR "/meshes/tetrahedron.off --model baudet "
                 "--spacing 0.1 --youngs 1e5 --poisson 0.3",
                 2, "boxes only"},
        BadInput{"build --mesh " MSM_SIM_TEST_DATA_DIR "/meshes/tetrahedron.off --model cubic "
                 "--spacing 0.1 --youngs 1e5 --poisson 0.3 --out /nonexistent/dir/m.msm",
                 1, "m.msm"},
        // Dynamics (issue "Dynamics").
        BadInput{"slide --nodes 9 4 5 --size 2 1 1 --mass 1 --v0 1 --mu 0.5", 2, "spacings"},
        BadInput{"slide --nodes 9 5 5 --size 2 1 1 --mass 1 --v0 1 --mu -0.5", 2, "--mu"},
        BadInput{"slide --nodes 9 5 5 --size 2 1 1 --mass 0 --v0 1 --mu 0.5", 2, "mass"},
        BadInput{"slide --nodes 1 5 5 --size 2 1 1 --mass 1 --v0 1 --mu 0.5", 2, "nodes"},
        BadInput{"slide --nodes 9 5 5 --size 2 1 1 --mass 1 --v0 1", 2, "--mu"}));

TEST(LabCli, AnyPoissonRatioWithEitherSpringLawAndDispersion) {
  const std::string base =
      "compression --model cubic --size 1 0.5 0.5 --spacing 0.0625 --youngs 2e5 --poisson 0.45 "
      "--json";
  const auto two_pass = nlohmann::json::parse(RunLab(base).out);
  EXPECT_NEAR(two_pass["poisson_measured"].get<double>(), 0.45, 0.02);
  EXPECT_NEAR(two_pass["youngs_measured"].get<double>() / 2e5, 1.0, 0.03);
  EXPECT_NEAR(two_pass["dispersion_ratio"].get<double>(), 4.8, 1e-12);
  // At 1 % strain the carrier law differs from Hooke's only at second order.
  const auto nonlinear = nlohmann::json::parse(RunLab(base + " --spring nonlinear").out);
  EXPECT_NEAR(
      nonlinear["youngs_measured"].get<double>() / two_pass["youngs_measured"].get<double>(), 1.0,
      0.02);
  EXPECT_EQ(nonlinear["spring"], "nonlinear");
}

TEST(LabCli, BaudetModelForAnyPoissonRatio) {
  const LabRun run = RunLab(
      "compression --model baudet --size 1 0.5 0.5 --spacing 0.0625 --youngs 2e5 --poisson 0.4 "
      "--json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_NEAR(json["poisson_measured"].get<double>(), 0.4, 0.02);
  EXPECT_NEAR(json["youngs_measured"].get<double>() / 2e5, 1.0, 0.05);
  EXPECT_EQ(json["nodes"], 17 * 9 * 9);
}

TEST(LabCli, PoissonSweepReportsEveryTargetAndPlots) {
  const std::string png = ::testing::TempDir() + "msm_lab_sweep.png";
  std::remove(png.c_str());
  const LabRun run = RunLab(
      "poisson-sweep --model cubic --size 1 0.5 0.5 --spacing 0.0625 --targets -0.5 0.25 0.45 "
      "--json --plot " +
      png);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  ASSERT_EQ(json["results"].size(), 3u);
  for (const auto& row : json["results"]) {
    EXPECT_NEAR(row["poisson_measured"].get<double>(), row["poisson_target"].get<double>(), 0.02);
    EXPECT_NEAR(row["poisson_theory"].get<double>(), row["poisson_target"].get<double>(), 1e-12);
  }
  std::ifstream image(png, std::ios::binary);
  char magic[4] = {};
  image.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

TEST(LabCli, HelpExitsZero) {
  const LabRun run = RunLab("--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.out.find("compression"), std::string::npos);
}

TEST(LabArguments, ParsesTheFullCompressionContract) {
  const auto outcome = msm_sim::lab::ParseLabArguments(
      {"msm_lab",  "compression", "--model",    "random",    "--size",
       "3",        "2",           "1",          "--spacing", "0.1",
       "--youngs", "5e4",         "--poisson",  "0.25",      "--construction",
       "corner",   "--density",   "900",        "--strain",  "0.02",
       "--rotate", "0",           "0",          "1",         "30",
       "--seed",   "9",           "--min-dist", "0.85",      "--max-dist",
       "1.6",      "--json"});
  ASSERT_TRUE(outcome.arguments.has_value()) << outcome.message;
  const auto& a = *outcome.arguments;
  EXPECT_EQ(a.model.model, "random");
  EXPECT_EQ(a.model.size, Eigen::Vector3d(3, 2, 1));
  EXPECT_DOUBLE_EQ(a.model.youngs, 5e4);
  EXPECT_DOUBLE_EQ(a.model.density, 900);
  EXPECT_DOUBLE_EQ(a.strain, 0.02);
  EXPECT_EQ(a.model.construction, "corner");
  ASSERT_TRUE(a.model.rotate.has_value());
  EXPECT_DOUBLE_EQ((*a.model.rotate)[3], 30.0);
  EXPECT_EQ(a.model.seed, 9u);
  EXPECT_DOUBLE_EQ(a.model.min_dist, 0.85);
  EXPECT_DOUBLE_EQ(a.model.max_dist, 1.6);
  EXPECT_TRUE(a.json);
}

// --- Dynamics (issue "Dynamics") -------------------------------------------------------------

TEST(LabCliSlide, JsonReportsDistanceAgainstTheory) {
  const LabRun run = RunLab("slide --nodes 5 3 3 --size 2 1 1 --mass 2 --v0 1.5 --mu 0.4 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  for (const char* key : {"distance", "theory_distance", "seconds_simulated"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_NEAR(json["theory_distance"].get<double>(), 1.5 * 1.5 / (2 * 0.4 * 9.81), 1e-12);
  EXPECT_NEAR(json["distance"].get<double>() / json["theory_distance"].get<double>(), 1.0, 0.05);
  EXPECT_TRUE(json["stopped"].get<bool>());
  const LabRun table = RunLab("slide --nodes 3 2 2 --size 2 1 1 --mass 1 --v0 1 --mu 0.5");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("theory"), std::string::npos);
}

}  // namespace
