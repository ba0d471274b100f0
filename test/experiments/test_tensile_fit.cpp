// Fitting E and the spring law of docs/physics.md §4.1 to a measured tensile curve
// (FitTensileCurve) on the shipped Ecoflex 00-30 curve (test/data/README.md).

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/experiments/tensile_fit.h"

namespace msm_sim::core {
namespace {

std::vector<TensilePoint> EcoflexCurve() {
  std::ifstream file(std::string(MSM_SIM_TEST_DATA_DIR) + "/ecoflex_00_30_tensile.csv");
  return ReadTensileCurve(file, TensileColumns{}).points;
}

// The best RMS error a law reaches with E fitted by least squares.
double BestRmsWithLaw(const std::vector<TensilePoint>& points, const PowerSpringLaw& law) {
  const std::vector<double> unit = ModelTensileStress(points, 1.0, 0.49, law);
  double cross = 0.0, square = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    cross += points[i].stress * unit[i];
    square += unit[i] * unit[i];
  }
  std::vector<double> model = unit;
  for (double& stress : model) stress *= cross / square;
  return TensileRmsError(points, model);
}

TEST(TensileFit, FollowsTheEcoflexCurveToFullStrainWithinFivePercent) {
  const TensileFitResult fit = FitTensileCurve(EcoflexCurve(), TensileFitOptions{});
  EXPECT_LE(fit.rms_error, 0.05);  // issue 49's bound, RMS of the largest stress up to 100 %
  EXPECT_GT(fit.youngs, 2e4);      // a soft silicone: tens of kPa
  EXPECT_LT(fit.youngs, 6e4);
  EXPECT_LT(fit.law.alpha, -1.0);  // softer than the carrier law in tension
  EXPECT_GT(fit.law.beta, 0.0);    // and stiffening at large stretch
  ASSERT_EQ(fit.model_stress.size(), fit.fitted.size());
  EXPECT_LE(fit.fitted.back().strain, 1.0);
  EXPECT_GE(fit.fitted.back().strain, 0.97);
  // The reported error is the model's at the fitted E and law.
  const std::vector<double> model = ModelTensileStress(fit.fitted, fit.youngs, 0.49, fit.law);
  EXPECT_NEAR(TensileRmsError(fit.fitted, model), fit.rms_error, 1e-12);
}

// Why the law was extended: a lattice of linear springs stiffens in uniaxial tension at
// nu = 0.49 (geometry and the dispersion), where the silicone softens. Carrier springs soften,
// and with the dispersion weighted by their tangent (docs/physics.md §3) follow it within 5 %.
TEST(TensileFit, TheLinearLawCannotFollowTheCurveTheCarrierLawCan) {
  const std::vector<TensilePoint> points = TensileFitRange(EcoflexCurve(), 1.0);
  EXPECT_GT(BestRmsWithLaw(points, PowerSpringLaw{1.0, 0.0}), 0.05);
  EXPECT_LT(BestRmsWithLaw(points, PowerSpringLaw{-1.0, 0.0}), 0.05);
}

TEST(TensileFit, IsDeterministic) {
  const std::vector<TensilePoint> curve = EcoflexCurve();
  TensileFitOptions options;
  options.max_strain = 0.5;
  const TensileFitResult first = FitTensileCurve(curve, options);
  const TensileFitResult second = FitTensileCurve(curve, options);
  EXPECT_EQ(first.youngs, second.youngs);
  EXPECT_EQ(first.law.alpha, second.law.alpha);
  EXPECT_EQ(first.law.beta, second.law.beta);
  EXPECT_LE(first.rms_error, 0.05);
}

TEST(TensileFit, RefusesTooFewPointsAndBadOptions) {
  const std::vector<TensilePoint> curve = EcoflexCurve();
  TensileFitOptions options;
  options.max_strain = 0.1;  // 2 points below 10 %
  EXPECT_THROW(FitTensileCurve(curve, options), std::invalid_argument);
  options.max_strain = -1.0;
  EXPECT_THROW(FitTensileCurve(curve, options), std::invalid_argument);
  options.max_strain = 1.0;
  options.poisson = 0.5;
  EXPECT_THROW(FitTensileCurve(curve, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
