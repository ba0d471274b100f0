// The parallel-jaw grip (issue "real time"): a block squeezed between two rigid jaws and lifted
// is held when 2 mu F_n >= 1.3 m g and slides out when 2 mu F_n <= 0.6 m g, with both
// integrators (docs/physics.md §7 and §7.1).
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/experiments/grip_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

// 4 x 4 x 4 cm at a = 5 mm: 512 nodes, E = 200 kPa, nu = 0.45, rho = 1100 (70 g). The jaws
// squeeze it by 0.2 mm each (1 % of its width).
std::shared_ptr<const Model> GripBlock(double poisson = 0.45, double surface_dispersion = 1.0) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.04, 0.04, 0.04);
  lattice_options.lattice.spacing = 0.005;
  lattice_options.surface.surface_dispersion = surface_dispersion;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), lattice_options));
}

GripExperimentResult RunGrip(Integrator integrator, double ratio,
                             std::shared_ptr<const Model> block = GripBlock()) {
  GripExperimentOptions options;
  options.integrator = integrator;
  options.hold_ratio = ratio;
  const GripExperimentResult r = RunGripExperiment(block, options);
  std::printf(
      "  %s, 2 mu F_n = %.1f m g: m g %.4f N, F_n %.4f N before, %.4f N (least %.4f N) during "
      "the lift, mu %.4f; slip %.3f mm after %.2f s (largest %.3f mm)%s\n",
      IntegratorName(integrator), ratio, r.weight, r.normal_force, r.lift_normal_force_mean,
      r.lift_normal_force_min, r.friction, 1e3 * r.slip, r.seconds_lifted, 1e3 * r.max_slip,
      r.left_jaws ? ", left the jaws" : "");
  // mu is derived from the measurement, not chosen.
  EXPECT_NEAR(2.0 * r.friction * r.normal_force, ratio * r.weight, 1e-9 * r.weight);
  return r;
}

void ExpectHeld(const GripExperimentResult& r) {
  EXPECT_TRUE(r.held);
  EXPECT_FALSE(r.left_jaws);
  EXPECT_LT(r.max_slip, 1e-3);
  EXPECT_NEAR(r.seconds_lifted, 2.0, 1e-9);
}

// Sliding out: the block falls out of the jaws within the lift, and at no more than free fall.
void ExpectDropped(const GripExperimentResult& r) {
  EXPECT_FALSE(r.held);
  EXPECT_TRUE(r.left_jaws);
  EXPECT_LT(r.seconds_lifted, 2.0);
  EXPECT_LT(r.slip, 0.05 * r.seconds_lifted + 0.5 * 9.81 * std::pow(r.seconds_lifted, 2) + 1e-3);
}

TEST(GripExperiment, ExplicitHoldsAtOnePointThreeWeights) {
  ExpectHeld(RunGrip(Integrator::kExplicit, 1.3));
}

TEST(GripExperiment, ExplicitDropsAtZeroPointSixWeights) {
  ExpectDropped(RunGrip(Integrator::kExplicit, 0.6));
}

TEST(GripExperiment, ImplicitHoldsAtOnePointThreeWeights) {
  ExpectHeld(RunGrip(Integrator::kImplicit, 1.3));
}

TEST(GripExperiment, ImplicitDropsAtZeroPointSixWeights) {
  ExpectDropped(RunGrip(Integrator::kImplicit, 0.6));
}

// The softer outer layer (NodeCentredSurfaceOptions::surface_dispersion, docs/physics.md §7) where
// it is recommended, nu = 0.49: the jaws squeeze the outer layer, and the grip still holds and
// drops as it should (measured: slip 0.054 mm in 2 s at 1.3 m g, as 0.055 mm without it).
TEST(GripExperiment, ExplicitWithASofterOuterLayerHoldsAndDropsAtNu049) {
  for (const double share : {0.5, 0.25}) {
    SCOPED_TRACE(share);
    const auto block = GripBlock(0.49, share);
    ExpectHeld(RunGrip(Integrator::kExplicit, 1.3, block));
    ExpectDropped(RunGrip(Integrator::kExplicit, 0.6, block));
  }
}

TEST(GripExperiment, InvalidOptionsThrow) {
  const auto block = GripBlock();
  GripExperimentOptions options;
  options.squeeze = 0.0;
  EXPECT_THROW(RunGripExperiment(block, options), std::invalid_argument);
  options = GripExperimentOptions{};
  options.hold_ratio = std::nan("");
  EXPECT_THROW(RunGripExperiment(block, options), std::invalid_argument);
  options = GripExperimentOptions{};
  options.measure_time = 2.0 * options.settle_time;
  EXPECT_THROW(RunGripExperiment(block, options), std::invalid_argument);
  options = GripExperimentOptions{};
  options.lift_speed = -1.0;
  EXPECT_THROW(RunGripExperiment(block, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
