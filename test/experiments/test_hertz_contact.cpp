// Hertz's contact as the acceptance test of the microcollision contact (issue "Contact that
// recovers and reports", item Hertz): a rigid sphere of radius R pressed to depth 0.05 R into a
// block clamped at its base, 10 contact radii wide and deep, with 4 nodes across the contact
// radius at the deepest point. On that block an independent CalculiX run is within 2 % of
// Hertz's half-space force (the clamped base's +9-12 % cancelled by the free sides), so plain
// Hertz is the reference; the issue asks for 10 %.
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "msm_sim/experiments/indentation_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

constexpr double kRadius = 0.01;           // R (m)
constexpr double kDepth = 0.05 * kRadius;  // 0.5 mm
constexpr double kSpacing = 0.00055;       // a = sqrt(R D) / 4.07
constexpr double kSide = 41 * kSpacing;    // 22.55 mm >= 10 sqrt(R D) = 22.36 mm

void ExpectHertz(double poisson, double surface_dispersion = 1.0) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(kSide);
  lattice_options.lattice.spacing = kSpacing;
  lattice_options.surface.surface_dispersion = surface_dispersion;
  const auto model = std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1100.0), lattice_options));
  ASSERT_EQ(model->num_nodes(), 41 * 41 * 41);
  IndentationExperimentOptions options;
  options.sphere_radius = kRadius;
  options.depth = kDepth;
  options.speed = 0.02;  // 25 ms of pressing: ten times the block's slowest period, quasi-static
  options.samples = 10;
  const IndentationExperimentResult result = RunIndentationExperiment(model, options);
  ASSERT_FALSE(result.profile.empty());
  std::printf(
      "  nu %.2f, surface dispersion %.2f, %d nodes: depth [mm], force [N], Hertz [N], "
      "ratio\n",
      poisson, surface_dispersion, model->num_nodes());
  for (const IndentationSample& row : result.profile) {
    std::printf("  %.3f  %.5f  %.5f  %.3f\n", 1e3 * row.depth, row.force, row.hertz_force,
                row.force / row.hertz_force);
  }
  const IndentationSample& deepest = result.profile.back();
  EXPECT_NEAR(deepest.depth, kDepth, 0.05 * kDepth);
  EXPECT_GE(std::sqrt(kRadius * deepest.depth) / kSpacing, 3.9);  // nodes across the radius
  EXPECT_NEAR(deepest.force / deepest.hertz_force, 1.0, 0.10);
}

TEST(HertzContact, SphereIntoABlockTenContactRadiiWideMatchesHertzAtNu025) { ExpectHertz(0.25); }

TEST(HertzContact, SphereIntoABlockTenContactRadiiWideMatchesHertzAtNu045) { ExpectHertz(0.45); }

// The softer outer layer (NodeCentredSurfaceOptions::surface_dispersion, docs/physics.md §7) at the
// nu where it is meant to be used: the contact, resolved, still matches Hertz (measured 0.939
// at 0.48 mm against 0.943 without it).
TEST(HertzContact, WithASofterOuterLayerMatchesHertzAtNu049) { ExpectHertz(0.49, 0.5); }

// And with a quarter of its bulk, the recommended share at nu >= 0.48 (measured 0.932 at
// 0.48 mm).
TEST(HertzContact, WithAQuarterShareOuterLayerMatchesHertzAtNu049) { ExpectHertz(0.49, 0.25); }

}  // namespace
}  // namespace msm_sim::core
