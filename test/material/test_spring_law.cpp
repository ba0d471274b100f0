// The spring laws (docs/physics.md §4): names, tensions, stiffnesses and energies at lengths worked
// out by hand; the power law of §4.1 against numerical derivatives and integrals of itself and
// against the linear and carrier laws it contains.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"

namespace msm_sim::core {
namespace {

// A spring of k = 200 N/m and rest length 1 cm, stretched to 1.2 cm or compressed to 0.5 cm.
constexpr double kK = 200.0;
constexpr double kRest = 0.01;
constexpr double kStretched = 0.012;
constexpr double kCompressed = 0.005;

TEST(SpringLaw, ParsesTheThreeNames) {
  SpringLaw law = SpringLaw::kNonlinear;
  ASSERT_TRUE(ParseSpringLaw("linear", &law));
  EXPECT_EQ(law, SpringLaw::kLinear);
  ASSERT_TRUE(ParseSpringLaw("nonlinear", &law));
  EXPECT_EQ(law, SpringLaw::kNonlinear);
  ASSERT_TRUE(ParseSpringLaw("power", &law));
  EXPECT_EQ(law, SpringLaw::kPower);
}

TEST(SpringLaw, RejectsOtherNames) {
  for (const std::string name : {"", "Linear", "NONLINEAR", "non-linear", " linear", "linear ",
                                 "carrier", "hooke", "Power"}) {
    SpringLaw law = SpringLaw::kLinear;
    EXPECT_FALSE(ParseSpringLaw(name, &law)) << "'" << name << "'";
  }
}

TEST(SpringLaw, LinearTensionIsHooke) {
  // t = k (L - L0).
  EXPECT_NEAR(LinearSpringLaw::Tension(kK, kRest, kStretched), 0.4, 1e-12);
  EXPECT_NEAR(LinearSpringLaw::Tension(kK, kRest, kCompressed), -1.0, 1e-12);
  EXPECT_EQ(LinearSpringLaw::Tension(kK, kRest, kRest), 0.0);
  // Finite at L = 0: -k L0.
  EXPECT_NEAR(LinearSpringLaw::Tension(kK, kRest, 0.0), -2.0, 1e-12);
  EXPECT_EQ(LinearSpringLaw::TangentStiffness(kK, kRest, kStretched), kK);
  EXPECT_EQ(LinearSpringLaw::TangentStiffness(kK, kRest, kCompressed), kK);
}

TEST(SpringLaw, CarrierTensionDivergesUnderCompression) {
  // t = k L0 (L - L0) / L: 200 * 0.01 * 0.002 / 0.012 = 1/3 and 200 * 0.01 * -0.005 / 0.005 = -2.
  EXPECT_NEAR(CarrierSpringLaw::Tension(kK, kRest, kStretched), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(CarrierSpringLaw::Tension(kK, kRest, kCompressed), -2.0, 1e-12);
  EXPECT_EQ(CarrierSpringLaw::Tension(kK, kRest, kRest), 0.0);
  // Softer than Hooke when stretched, stiffer when compressed, unbounded as L -> 0.
  EXPECT_NEAR(CarrierSpringLaw::Tension(kK, kRest, 1e-6 * kRest), -2.0 * (1e6 - 1.0), 1e-3);
  // dt/dL = k L0^2 / L^2: 200 * 1e-4 / 1.44e-4 = 1250 / 9.
  EXPECT_NEAR(CarrierSpringLaw::TangentStiffness(kK, kRest, kStretched), 1250.0 / 9.0, 1e-9);
  EXPECT_NEAR(CarrierSpringLaw::TangentStiffness(kK, kRest, kCompressed), 4.0 * kK, 1e-9);
}

TEST(SpringLaw, BothLawsHaveTheSameSmallStrainStiffness) {
  EXPECT_DOUBLE_EQ(CarrierSpringLaw::TangentStiffness(kK, kRest, kRest), kK);
  EXPECT_DOUBLE_EQ(LinearSpringLaw::TangentStiffness(kK, kRest, kRest), kK);
  for (const double strain : {1e-6, -1e-6}) {
    const double length = kRest * (1.0 + strain);
    const double linear = LinearSpringLaw::Tension(kK, kRest, length);
    const double carrier = CarrierSpringLaw::Tension(kK, kRest, length);
    // carrier / linear = L0 / L = 1 - strain + O(strain^2).
    EXPECT_NEAR(carrier / linear, 1.0 - strain, 1e-11) << "strain " << strain;
  }
}

TEST(SpringLaw, EnergiesAtChosenLengths) {
  // W = k dL^2 / 2.
  EXPECT_NEAR(LinearSpringLaw::Energy(kK, kRest, kStretched), 4e-4, 1e-15);
  EXPECT_NEAR(LinearSpringLaw::Energy(kK, kRest, kCompressed), 2.5e-3, 1e-15);
  // W = k L0^2 (x - ln(1 + x)), x = dL / L0: 0.02 (0.2 - ln 1.2) and 0.02 (-0.5 - ln 0.5).
  EXPECT_NEAR(CarrierSpringLaw::Energy(kK, kRest, kStretched), 3.535688641209078e-4, 1e-15);
  EXPECT_NEAR(CarrierSpringLaw::Energy(kK, kRest, kCompressed), 3.862943611198906e-3, 1e-15);
  EXPECT_EQ(LinearSpringLaw::Energy(kK, kRest, kRest), 0.0);
  EXPECT_EQ(CarrierSpringLaw::Energy(kK, kRest, kRest), 0.0);
}

// dW/dL = t and dt/dL = the tangent stiffness, by central differences over the range from
// strong compression to strong stretch.
template <typename Law>
void ExpectDerivativesConsistent() {
  for (const double length : {0.002, 0.005, 0.009, 0.0101, 0.012, 0.02, 0.05}) {
    const double step = 1e-6 * length;
    const double energy_slope =
        (Law::Energy(kK, kRest, length + step) - Law::Energy(kK, kRest, length - step)) /
        (2.0 * step);
    const double tension = Law::Tension(kK, kRest, length);
    EXPECT_NEAR(energy_slope, tension, 1e-6 * std::abs(tension) + 1e-9) << "L " << length;
    const double tension_slope =
        (Law::Tension(kK, kRest, length + step) - Law::Tension(kK, kRest, length - step)) /
        (2.0 * step);
    const double tangent = Law::TangentStiffness(kK, kRest, length);
    EXPECT_NEAR(tension_slope, tangent, 1e-6 * tangent) << "L " << length;
    // Convex with its minimum at rest: W >= 0.
    EXPECT_GT(Law::Energy(kK, kRest, length), 0.0) << "L " << length;
  }
}

TEST(SpringLaw, LinearEnergyDerivativeIsTension) { ExpectDerivativesConsistent<LinearSpringLaw>(); }

TEST(SpringLaw, CarrierEnergyDerivativeIsTension) {
  ExpectDerivativesConsistent<CarrierSpringLaw>();
}

// The power law at the fitted range of alpha (docs/materials.md: -4.8 to -2), its limits alpha = 0
// and alpha = -1 and the linear law, with and without the stiffening term.
const PowerSpringLaw kPowerLaws[] = {{1.0, 0.0},  {-1.0, 0.0}, {0.0, 0.0},     {1e-6, 0.2},
                                     {-2.5, 0.0}, {0.5, 0.3},  {-4.54, 0.116}, {-1.0, 0.5},
                                     {0.0, 1.0},  {2.0, 0.1}};
const double kLengths[] = {0.002, 0.005, 0.009, 0.0101, 0.012, 0.02, 0.03};

TEST(PowerSpringLaw, TangentAndTensionAreDerivatives) {
  for (const PowerSpringLaw& law : kPowerLaws) {
    for (const double length : kLengths) {
      const double step = 1e-6 * length;
      const double energy_slope =
          (law.Energy(kK, kRest, length + step) - law.Energy(kK, kRest, length - step)) /
          (2.0 * step);
      const double tension = law.Tension(kK, kRest, length);
      EXPECT_NEAR(energy_slope, tension, 1e-6 * std::abs(tension) + 1e-9)
          << "alpha " << law.alpha << " beta " << law.beta << " L " << length;
      const double tension_slope =
          (law.Tension(kK, kRest, length + step) - law.Tension(kK, kRest, length - step)) /
          (2.0 * step);
      const double tangent = law.TangentStiffness(kK, kRest, length);
      EXPECT_NEAR(tension_slope, tangent, 1e-6 * tangent)
          << "alpha " << law.alpha << " beta " << law.beta << " L " << length;
      EXPECT_GT(law.Energy(kK, kRest, length), 0.0);
    }
    EXPECT_EQ(law.Energy(kK, kRest, kRest), 0.0);
    EXPECT_DOUBLE_EQ(law.TangentStiffness(kK, kRest, kRest), kK);
  }
}

// The integral of the tension from L0 to L by composite Simpson (4000 intervals).
double IntegratedTension(const PowerSpringLaw& law, double length) {
  const int intervals = 4000;
  const double h = (length - kRest) / intervals;
  double sum = law.Tension(kK, kRest, kRest) + law.Tension(kK, kRest, length);
  for (int i = 1; i < intervals; ++i) {
    sum += (i % 2 == 1 ? 4.0 : 2.0) * law.Tension(kK, kRest, kRest + i * h);
  }
  return sum * h / 3.0;
}

TEST(PowerSpringLaw, EnergyIsTheIntegralOfTheTension) {
  for (const PowerSpringLaw& law : kPowerLaws) {
    for (const double length : kLengths) {
      const double integral = IntegratedTension(law, length);
      EXPECT_NEAR(law.Energy(kK, kRest, length), integral, 1e-8 * integral)
          << "alpha " << law.alpha << " beta " << law.beta << " L " << length;
    }
  }
  // Either side of the alpha = 0 switch the energy is continuous to O(alpha^2).
  for (const double length : kLengths) {
    const double below = PowerSpringLaw{0.99e-4, 0.0}.Energy(kK, kRest, length);
    const double above = PowerSpringLaw{1.01e-4, 0.0}.Energy(kK, kRest, length);
    EXPECT_NEAR(below, above, 1e-5 * above) << "L " << length;
  }
}

TEST(PowerSpringLaw, ContainsTheLinearAndCarrierLaws) {
  const PowerSpringLaw linear{1.0, 0.0}, carrier{-1.0, 0.0};
  for (const double length : kLengths) {
    const double t_linear = LinearSpringLaw::Tension(kK, kRest, length);
    const double t_carrier = CarrierSpringLaw::Tension(kK, kRest, length);
    EXPECT_NEAR(linear.Tension(kK, kRest, length), t_linear, 1e-12 * std::abs(t_linear));
    EXPECT_NEAR(carrier.Tension(kK, kRest, length), t_carrier, 1e-12 * std::abs(t_carrier));
    const double w_linear = LinearSpringLaw::Energy(kK, kRest, length);
    const double w_carrier = CarrierSpringLaw::Energy(kK, kRest, length);
    EXPECT_NEAR(linear.Energy(kK, kRest, length), w_linear, 1e-12 * w_linear);
    EXPECT_NEAR(carrier.Energy(kK, kRest, length), w_carrier, 1e-12 * w_carrier);
    EXPECT_NEAR(linear.TangentStiffness(kK, kRest, length),
                LinearSpringLaw::TangentStiffness(kK, kRest, length), 1e-12 * kK);
    EXPECT_NEAR(carrier.TangentStiffness(kK, kRest, length),
                CarrierSpringLaw::TangentStiffness(kK, kRest, length),
                1e-12 * CarrierSpringLaw::TangentStiffness(kK, kRest, length));
  }
  // At alpha = 0: W = k L0^2 (s ln s - s + 1), here at s = 2.
  const PowerSpringLaw logarithmic{0.0, 0.0};
  EXPECT_NEAR(logarithmic.Energy(kK, kRest, 2.0 * kRest),
              kK * kRest * kRest * (2.0 * std::log(2.0) - 1.0), 1e-15);
}

}  // namespace
}  // namespace msm_sim::core
