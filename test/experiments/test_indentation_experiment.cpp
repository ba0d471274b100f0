// The indentation experiment (issue "Real time at real resolution"): a rigid sphere pressed into
// a block clamped at its base, its force against Hertz's.
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/experiments/indentation_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

// 6 x 6 x 3 cm at a = 5 mm: 12 x 12 x 6 = 864 nodes, E = 200 kPa.
std::shared_ptr<const Model> CoarseBlock(double poisson) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.06, 0.06, 0.03);
  lattice_options.lattice.spacing = 0.005;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), lattice_options));
}

TEST(HertzForce, MatchesTheFormulaByHand) {
  // E = 200 kPa, nu = 0.25, R = 1 cm, delta = 4 mm:
  // 4/3 * 2e5 / 0.9375 * 0.1 * 0.004^1.5 = 28444.44 * 2.52982e-4 = 7.19594 N.
  EXPECT_NEAR(HertzForce(2e5, 0.25, 0.01, 0.004), 7.19594, 1e-5);
  EXPECT_EQ(HertzForce(2e5, 0.25, 0.01, 0.0), 0.0);
  EXPECT_EQ(HertzForce(2e5, 0.25, 0.01, -1e-3), 0.0);
}

TEST(IndentationExperiment, ForceGrowsWithDepthNearHertz) {
  IndentationExperimentOptions options;
  options.sphere_radius = 0.01;
  options.depth = 0.004;
  const IndentationExperimentResult result = RunIndentationExperiment(CoarseBlock(0.25), options);
  // 12 nodes a side: the sphere's axis falls between four nodes 3.5 mm away, which it touches
  // s^2 / (2 (R + r)) below the surface that depth is counted from (a few tenths of a mm).
  EXPECT_GT(result.touch_depth, 0.1e-3);
  EXPECT_LT(result.touch_depth, 1e-3);
  // Rows of 16 steps of 5 um from the first touch to 4 mm below the surface.
  const double pressed = 0.004 - result.touch_depth;
  EXPECT_NEAR(static_cast<double>(result.profile.size()), pressed / (16 * 5e-6), 1.0);
  EXPECT_GT(result.contact_time, 0.0);
  // The gap of 0.1 mm closes at the end of step 20 and the first force is recorded at the end
  // of step 21; then the sphere presses the rest of the way at 5 mm/s, in whole steps.
  EXPECT_NEAR(result.contact_time, 0.021, 1e-9);
  EXPECT_NEAR(result.seconds_simulated - result.contact_time, pressed / 0.005, 1.5e-3);
  double previous_depth = -1.0, previous_force = 0.0;
  for (const IndentationSample& row : result.profile) {
    EXPECT_GT(row.depth, previous_depth);
    ASSERT_TRUE(std::isfinite(row.force));
    EXPECT_GE(row.force, 0.0) << "at " << row.depth << " m";
    if (row.depth > 0.001) {
      EXPECT_GT(row.force, previous_force) << "at " << row.depth << " m";
    }
    EXPECT_DOUBLE_EQ(row.hertz_force, HertzForce(2e5, 0.25, 0.01, row.depth));
    previous_depth = row.depth;
    previous_force = row.force;
  }
  EXPECT_NEAR(result.profile.back().depth, 0.004, 1e-4);
  const double ratio = result.profile.back().force / result.profile.back().hertz_force;
  std::printf("  coarse block, 4 mm deep: %.3f N, Hertz %.3f N, ratio %.3f\n",
              result.profile.back().force, result.profile.back().hertz_force, ratio);
  // Measured 1.86 (1.62 at nu = 0.45; 1.69 on a 2,048-node 8 x 8 x 4 cm block). The contact
  // radius sqrt(R D) = 6.3 mm is about one spacing, so one to four nodes carry the load, and they
  // touch through collision spheres of radius ~3 mm (an indenter effectively R + 3 mm wide): the
  // lattice is stiffer than Hertz's half-space here. The band is wide for that, yet fails a
  // force off by a factor of 2 either way (a wrong modulus, a lost or doubled contact impulse).
  // Hertz within a few % needs >= 4 nodes across the contact radius (another issue).
  EXPECT_GT(ratio, 1.2);
  EXPECT_LT(ratio, 2.5);
}

TEST(IndentationExperiment, InvalidOptionsThrow) {
  const auto block = CoarseBlock(0.25);
  const auto bad = [&](auto change) {
    IndentationExperimentOptions options;
    change(&options);
    return options;
  };
  using Options = IndentationExperimentOptions;
  for (const Options& options :
       {bad([](Options* o) { o->sphere_radius = 0.0; }), bad([](Options* o) { o->depth = -0.001; }),
        bad([](Options* o) { o->depth = std::numeric_limits<double>::quiet_NaN(); }),
        bad([](Options* o) { o->speed = 0.0; }), bad([](Options* o) { o->step = -1e-3; }),
        bad([](Options* o) { o->damping_beta = -1e-4; }), bad([](Options* o) { o->samples = 0; }),
        bad([](Options* o) { o->start_gap = -1e-4; }),
        bad([](Options* o) { o->time_step_safety = 0.0; }),
        bad([](Options* o) { o->time_step_safety = 1.5; }),
        bad([](Options* o) { o->depth = 0.03; })}) {  // the block's height
    EXPECT_THROW(RunIndentationExperiment(block, options), std::invalid_argument);
  }
}

}  // namespace
}  // namespace msm_sim::core
