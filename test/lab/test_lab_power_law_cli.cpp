// msm_lab's --spring power with --alpha and --beta (docs/physics.md §4.1, docs/lab.md): the
// fitted law runs in the lab's experiments, and a power law without its parameters (or
// parameters without it) is one error line and exit code 2. Part of test_lab_cli.

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/mechanics/lattice_uniaxial_tension.h"
#include "run_lab.h"

namespace {

using msm_sim::testing::CountLines;
using msm_sim::testing::LabRun;
using msm_sim::testing::RunLab;

// A node-centred cubic block of 16 x 8 x 8 cells compressed by 20 %.
const std::string kBlock =
    "compression --model cubic --size 1 0.5 0.5 --spacing 0.0625 --youngs 1e5 --poisson 0.3 "
    "--strain 0.2 --json";
// The law `msm_lab fit --tensile` gives for test/data/ecoflex_00_30_tensile.csv (docs/lab.md).
const msm_sim::core::PowerSpringLaw kFittedLaw{-4.54, 0.116};

double MeasuredYoungs(const std::string& arguments) {
  const LabRun run = RunLab(arguments);
  EXPECT_EQ(run.exit_code, 0) << arguments << ": " << run.err;
  if (run.exit_code != 0) return 0.0;
  const auto json = nlohmann::json::parse(run.out);
  // The JSON names the law, and the power law's parameters with it.
  const bool power = arguments.find("--spring power") != std::string::npos;
  EXPECT_EQ(json["spring"], power ? "power" : "linear");
  EXPECT_EQ(json.contains("alpha"), power);
  EXPECT_EQ(json.contains("beta"), power);
  return json["youngs_measured"].get<double>();
}

// alpha < 0 stiffens the springs in compression (the compressive force diverges as L -> 0):
// at 20 % the block carries more than the linear law's load, by the ratio the exact one-cell
// reduction of the lattice (LatticeUniaxialTension, the fit's own model curve) predicts.
TEST(LabPowerLaw, CompressionIsStifferByTheReductionsRatio) {
  const double linear = MeasuredYoungs(kBlock);
  const double power = MeasuredYoungs(kBlock + " --spring power --alpha -4.54 --beta 0.116");
  ASSERT_GT(linear, 0.0);
  const double predicted =
      msm_sim::core::LatticeUniaxialTension(-0.2, 1e5, 0.3, kFittedLaw).nominal_stress /
      msm_sim::core::LatticeUniaxialTension(-0.2, 1e5, 0.3, msm_sim::core::PowerSpringLaw{})
          .nominal_stress;
  EXPECT_GT(predicted, 1.1);
  EXPECT_NEAR(power / linear, predicted, 0.03 * predicted);
  // alpha = 1, beta = 0 is the linear law.
  EXPECT_NEAR(MeasuredYoungs(kBlock + " --spring power --alpha 1 --beta 0"), linear, 1e-9 * linear);
}

TEST(LabPowerLaw, MissingOrMisplacedParametersAreOneErrorLine) {
  const struct {
    std::string options;
    std::string mentions;
  } cases[] = {
      {" --spring power", "--spring power needs --alpha and --beta"},
      {" --spring power --alpha -4.54", "--spring power needs --alpha and --beta"},
      {" --spring power --alpha -4.54 --beta -0.1", "--beta finite and >= 0"},
      {" --spring power --alpha nan --beta 0.1", "alpha"},
      {" --alpha -4.54 --beta 0.116", "--alpha and --beta apply to --spring power"},
      {" --spring nonlinear --beta 0.116", "--alpha and --beta apply to --spring power"},
      {" --spring quadratic", "power"},
  };
  for (const auto& bad : cases) {
    const LabRun run = RunLab(kBlock + bad.options);
    EXPECT_FALSE(run.signalled);
    EXPECT_EQ(run.exit_code, 2) << bad.options << ": " << run.err;
    EXPECT_EQ(CountLines(run.err), 1) << run.err;
    EXPECT_EQ(run.err.rfind("msm_lab: error: ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(bad.mentions), std::string::npos) << bad.options << ": " << run.err;
  }
}

}  // namespace
