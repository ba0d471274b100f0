// Fitting a material to a measured indentation curve (issue "Materials the way users know
// them"): reading the CSV, Hertz's estimate and the 1-D search on the modulus.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/experiments/indentation_curve.h"
#include "msm_sim/experiments/indentation_fit.h"

namespace msm_sim::core {
namespace {

std::vector<IndentationPoint> Read(const std::string& text) {
  std::istringstream csv(text);
  return ReadIndentationCurve(csv);
}

// The message of the std::invalid_argument that reading `text` throws ("" if none).
std::string RefusalOf(const std::string& text) {
  try {
    Read(text);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(IndentationCurve, ReadsRowsAfterAHeaderSkippingCommentsAndBlankLines) {
  const auto curve = Read("depth_m,force_N\n# probe 1\n\n0.0005, 0.1\n 0.001 ,0.3\r\n");
  ASSERT_EQ(curve.size(), 2u);
  EXPECT_EQ(curve[0].depth, 0.0005);
  EXPECT_EQ(curve[0].force, 0.1);
  EXPECT_EQ(curve[1].depth, 0.001);
  EXPECT_EQ(curve[1].force, 0.3);
  EXPECT_EQ(Read("0,0\n1e-3,2\n").size(), 2u);  // no header
}

TEST(IndentationCurve, RefusesBadRowsNamingTheLine) {
  EXPECT_NE(RefusalOf("").find("no depth_m,force_N rows"), std::string::npos);
  EXPECT_NE(RefusalOf("depth_m,force_N\n").find("no depth_m,force_N rows"), std::string::npos);
  const std::string header = "depth_m,force_N\n0.001,0.1\n";
  EXPECT_NE(RefusalOf(header + "0.002,abc\n").find("line 3: not a number"), std::string::npos);
  EXPECT_NE(RefusalOf(header + "0.002\n").find("line 3: expected two fields"), std::string::npos);
  EXPECT_NE(RefusalOf(header + "0.002,1,2\n").find("line 3: expected two fields"),
            std::string::npos);
  EXPECT_NE(RefusalOf(header + "nan,1\n").find("line 3: NaN"), std::string::npos);
  EXPECT_NE(RefusalOf(header + "0.002,inf\n").find("line 3: NaN or infinite"), std::string::npos);
  EXPECT_NE(RefusalOf("-0.001,0.1\n").find("line 1: negative depth"), std::string::npos);
  EXPECT_NE(RefusalOf(header + "0.001,0.2\n").find("line 3: depth 0.001 is not greater"),
            std::string::npos);
  EXPECT_NE(RefusalOf(header + "0.0005,0.2\n").find("line 3"), std::string::npos);
}

// Hertz's curve of E at these depths.
std::vector<IndentationPoint> HertzCurve(double youngs, double poisson, double radius) {
  std::vector<IndentationPoint> curve;
  for (int i = 1; i <= 20; ++i) {
    const double depth = 1e-4 * i;
    curve.push_back({depth, HertzForce(youngs, poisson, radius, depth)});
  }
  return curve;
}

TEST(IndentationFit, HertzEstimateOfAHertzCurveIsItsModulus) {
  EXPECT_NEAR(HertzYoungsModulus(HertzCurve(3e5, 0.45, 0.005), 0.45, 0.005), 3e5, 1e-6);
  EXPECT_THROW(HertzYoungsModulus({{0.0, 1.0}}, 0.3, 0.01), std::invalid_argument);
  EXPECT_THROW(HertzYoungsModulus({{1e-3, -1.0}}, 0.3, 0.01), std::invalid_argument);
}

// A stand-in for the simulation: a profile whose force is `stiffness` (E / 1 Pa)^power times
// Hertz's at E = 1 Pa, so that the fit's answer is known in closed form.
IndentationSimulator PowerLawSimulator(double stiffness, double power, int* calls) {
  return [=](double youngs) {
    ++*calls;
    std::vector<IndentationSample> profile;
    for (int i = 0; i <= 40; ++i) {
      const double depth = 5e-5 * i;
      profile.push_back(
          {depth, stiffness * std::pow(youngs, power) * HertzForce(1.0, 0.3, 0.01, depth), 0.0});
    }
    return profile;
  };
}

TEST(IndentationFit, ALinearModelIsFittedByTheSecondSimulation) {
  // Forces 1.4x Hertz's: the curve of E = 2e5 is reproduced by E = 2e5 / 1.4.
  int calls = 0;
  IndentationFitOptions options;
  options.poisson = 0.3;
  options.sphere_radius = 0.01;
  const auto fit =
      FitYoungsModulus(HertzCurve(2e5, 0.3, 0.01), PowerLawSimulator(1.4, 1.0, &calls), options);
  EXPECT_TRUE(fit.converged);
  EXPECT_EQ(fit.simulations, 2);
  EXPECT_EQ(calls, 2);
  EXPECT_NEAR(fit.hertz_youngs, 2e5, 1e-6);
  EXPECT_NEAR(fit.youngs / (2e5 / 1.4), 1.0, 1e-9);
  EXPECT_LT(fit.residual, 1e-9);
  ASSERT_EQ(fit.tried.size(), 2u);
  EXPECT_NEAR(fit.tried[0], 2e5, 1e-6);
}

TEST(IndentationFit, ANonLinearModelConvergesByTheSecantWithinTheTolerance) {
  // F ~ E^0.7: the fixed-point step alone would creep; the secant finds (2e5 / 0.9)^(1/0.7).
  int calls = 0;
  IndentationFitOptions options;
  options.poisson = 0.3;
  options.sphere_radius = 0.01;
  const double target = std::pow(2e5 / 0.9, 1.0 / 0.7);
  const auto fit =
      FitYoungsModulus(HertzCurve(2e5, 0.3, 0.01), PowerLawSimulator(0.9, 0.7, &calls), options);
  EXPECT_TRUE(fit.converged);
  EXPECT_LE(fit.simulations, 6);
  EXPECT_NEAR(fit.youngs / target, 1.0, 1.5e-3);  // tolerance 1e-3 on the force, E^0.7
}

TEST(IndentationFit, StopsAtTheLimitWithTheBestModulusSeen) {
  int calls = 0;
  IndentationFitOptions options;
  options.poisson = 0.3;
  options.sphere_radius = 0.01;
  options.max_simulations = 2;
  options.tolerance = 1e-12;
  const auto fit =
      FitYoungsModulus(HertzCurve(2e5, 0.3, 0.01), PowerLawSimulator(0.9, 0.3, &calls), options);
  EXPECT_FALSE(fit.converged);
  EXPECT_EQ(fit.simulations, 2);
  EXPECT_EQ(fit.youngs, fit.tried[1]);  // the fixed-point step is the better of the two
}

TEST(IndentationFit, RefusesASimulationWithoutForce) {
  IndentationFitOptions options;
  int calls = 0;
  EXPECT_THROW(
      FitYoungsModulus(HertzCurve(2e5, 0.3, 0.01), PowerLawSimulator(0.0, 1.0, &calls), options),
      std::runtime_error);
  options.max_simulations = 1;
  EXPECT_THROW(
      FitYoungsModulus(HertzCurve(2e5, 0.3, 0.01), PowerLawSimulator(1.0, 1.0, &calls), options),
      std::invalid_argument);
}

// The fit's resolution rule: kNodesAcrossContactRadius spacings across sqrt(R delta_max), Hertz's
// contact radius at the curve's deepest point (the case: R = 8 mm, 0.4 mm deep).
TEST(ContactResolution, FourSpacingsAcrossTheLargestContactRadius) {
  const std::vector<IndentationPoint> curve = {{1e-4, 0.01}, {4e-4, 0.08}};
  const ContactResolution rule = ResolvingResolution(curve, 0.008);
  EXPECT_NEAR(rule.contact_radius, std::sqrt(0.008 * 4e-4), 1e-15);
  EXPECT_NEAR(rule.spacing, rule.contact_radius / kNodesAcrossContactRadius, 1e-15);
  EXPECT_NEAR(rule.nodes_across, kNodesAcrossContactRadius, 1e-12);
  EXPECT_GE(kNodesAcrossContactRadius, 4.0);  // the floor
  // The former default, about 4,000 nodes on the 18 mm cube: 1.6 nodes across.
  const ContactResolution coarse =
      ResolutionOf(curve, 0.008, std::cbrt(0.018 * 0.018 * 0.018 / 4000));
  EXPECT_NEAR(coarse.nodes_across, 1.58, 0.01);
  EXPECT_THROW(ResolutionOf({}, 0.008, 1e-3), std::invalid_argument);
  EXPECT_THROW(ResolutionOf(curve, 0.008, 0.0), std::invalid_argument);
  EXPECT_THROW(ResolvingResolution({{0.0, 0.0}}, 0.008), std::invalid_argument);
}

// Two stand-in samples: the first's force follows E/(1 - nu^2) (a thick block), the second's
// also rises with nu (a thin clamped layer), each times Hertz's shape at E = 1 Pa.
std::vector<IndentationSample> StandIn(double youngs, double poisson, bool layer) {
  std::vector<IndentationSample> profile;
  for (int i = 0; i <= 40; ++i) {
    const double depth = 5e-5 * i;
    const double stiffness =
        youngs / (1.0 - poisson * poisson) * (layer ? 1.0 + 2.0 * poisson : 1.0);
    profile.push_back({depth, stiffness * HertzForce(1.0, 0.0, 0.01, depth), 0.0});
  }
  return profile;
}

std::vector<IndentationPoint> Measured(const std::vector<IndentationSample>& profile) {
  std::vector<IndentationPoint> curve;
  for (std::size_t i = 1; i < profile.size(); ++i) {
    curve.push_back({profile[i].depth, profile[i].force});
  }
  return curve;
}

TEST(MaterialFit, TwoSamplesThatRespondDifferentlyToNuDetermineBoth) {
  const auto first = Measured(StandIn(2e5, 0.42, false));
  const auto second = Measured(StandIn(2e5, 0.42, true));
  MaterialFitOptions options;
  options.youngs.sphere_radius = 0.01;
  const MaterialFitResult fit = FitYoungsAndPoisson(
      first, second, [](double e, double nu) { return StandIn(e, nu, false); },
      [](double e, double nu) { return StandIn(e, nu, true); }, options);
  EXPECT_TRUE(fit.converged);
  EXPECT_NEAR(fit.poisson, 0.42, 0.002);
  EXPECT_NEAR(fit.youngs / 2e5, 1.0, 0.003);
  EXPECT_GE(fit.trials.size(), 3u);
  EXPECT_LE(fit.trials.size(), 14u);
  EXPECT_EQ(fit.trials[0][0], options.lowest_poisson);  // the bracket's ends come first
  EXPECT_EQ(fit.trials[1][0], options.highest_poisson);
}

TEST(MaterialFit, SamplesThatRespondAlikeAreRefused) {
  const auto first = Measured(StandIn(2e5, 0.3, false));
  MaterialFitOptions options;
  const auto same = [](double e, double nu) { return StandIn(e, nu, false); };
  EXPECT_THROW(FitYoungsAndPoisson(first, first, same, same, options), std::runtime_error);
  options.highest_poisson = 0.5;
  EXPECT_THROW(FitYoungsAndPoisson(first, first, same, same, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
