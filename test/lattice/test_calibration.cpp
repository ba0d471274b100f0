// Acceptance tests of the calibrated models against linear elasticity (docs/physics.md §2, §6;
// thesis 3.2.2-3.2.6). Tolerances are those of the project's issue "Calibrated MSM core".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "compression_helpers.h"
#include "msm_sim/experiments/cantilever_experiment.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::core {
namespace {

constexpr double kYoungs = 1e5;
const Material kMaterial = Material::FromYoungsPoisson(kYoungs, 0.25, 1100.0);
const Eigen::Vector3d kBlock(2.0, 1.0, 1.0);  // one physical block, m

using testing::Compress;

CompressionExperimentResult CompressCubic(CubicConstruction construction, double spacing,
                                          double angle_deg = 0.0) {
  CubicLatticeOptions options;
  options.size = kBlock;
  options.lattice.spacing = spacing;
  options.construction = construction;
  options.lattice.rotation_axis = Eigen::Vector3d(0.4, -0.3, 0.7);
  options.lattice.rotation_angle = angle_deg * M_PI / 180.0;
  return Compress(BuildCubicLattice(kMaterial, options), kBlock);
}

// Spacings 1/6, 1/12 and 1/24 m: 6, 12 and 24 cells across; the finest is 1/4 of the coarsest.
const std::vector<double> kResolutions = {1.0 / 6.0, 1.0 / 12.0, 1.0 / 24.0};

TEST(Calibration, ElementCornerCubicMatchesEAndNuAtThreeResolutions) {
  for (const double a : kResolutions) {
    const CompressionExperimentResult r = CompressCubic(CubicConstruction::kElementCorner, a);
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.02) << "spacing " << a;
    EXPECT_NEAR(r.poisson_measured, 0.25, 0.005) << "spacing " << a;
    RecordProperty("element_corner_E_" + std::to_string(a), std::to_string(r.youngs_measured));
  }
}

TEST(Calibration, NodeCentredCubicMatchesEAndNuAtThreeResolutions) {
  for (const double a : kResolutions) {
    const CompressionExperimentResult r = CompressCubic(CubicConstruction::kNodeCentred, a);
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.03) << "spacing " << a;
    EXPECT_NEAR(r.poisson_measured, 0.25, 0.01) << "spacing " << a;
  }
}

TEST(Calibration, SurfaceCompensationIsWhatMakesCoarseNodeCentredBlocksAccurate) {
  CubicLatticeOptions options;
  options.size = kBlock;
  options.lattice.spacing = 1.0 / 6.0;
  options.surface.compensate_surface = false;
  const CompressionExperimentResult r = Compress(BuildCubicLattice(kMaterial, options), kBlock);
  // About 2/(3n) of E is missing without it (n = 6 cells across).
  EXPECT_LT(r.youngs_measured / kYoungs, 0.93);
}

TEST(Calibration, NodeCentredCubicIsIsotropicUnderLatticeRotation) {
  std::vector<double> youngs;
  for (const double angle : {0.0, 15.0, 30.0, 45.0, 60.0, 90.0}) {
    const CompressionExperimentResult r =
        CompressCubic(CubicConstruction::kNodeCentred, 1.0 / 16.0, angle);
    youngs.push_back(r.youngs_measured);
    EXPECT_NEAR(r.poisson_measured, 0.25, 0.01) << angle << " deg";
  }
  const auto [min, max] = std::minmax_element(youngs.begin(), youngs.end());
  double mean = 0.0;
  for (double e : youngs) mean += e / youngs.size();
  EXPECT_LT((*max - *min) / mean, 0.03);
}

// The fidelity issue, must-show 4: a box on a rotated node-centred lattice, 10 cells across,
// built anti-aliased (through the box as a solid, BodyRecipe::antialias): E within 3 % and nu
// within 0.01 at each of six rotations (the box lattice alone read E -6.6 % at 37 degrees about
// (0.2, 0.9, -0.4)).
TEST(Calibration, AntiAliasedRotatedBoxMatchesEAndNuAtSixRotations) {
  const std::vector<std::pair<Eigen::Vector3d, double>> rotations = {
      {Eigen::Vector3d(0.2, 0.9, -0.4), 37.0}, {Eigen::Vector3d(1.0, 0.0, 0.0), 20.0},
      {Eigen::Vector3d(0.0, 1.0, 1.0), 45.0},  {Eigen::Vector3d(1.0, 1.0, 1.0), 30.0},
      {Eigen::Vector3d(0.4, -0.3, 0.7), 60.0}, {Eigen::Vector3d(-0.6, 0.2, 0.5), 75.0}};
  for (const auto& [axis, degrees] : rotations) {
    BodyRecipe recipe(kMaterial);
    recipe.box_size = kBlock;
    recipe.lattice.spacing = 0.1;
    recipe.lattice.rotation_axis = axis;
    recipe.lattice.rotation_angle = degrees * M_PI / 180.0;
    const CompressionExperimentResult r = Compress(BuildModel(recipe), kBlock);
    std::printf("  %4.0f deg about (%.1f, %.1f, %.1f): E %+.2f %%, nu %.4f\n", degrees, axis.x(),
                axis.y(), axis.z(), 100.0 * (r.youngs_measured / kYoungs - 1.0),
                r.poisson_measured);
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.03) << degrees << " deg";
    EXPECT_NEAR(r.poisson_measured, 0.25, 0.01) << degrees << " deg";
  }
}

TEST(Calibration, RandomLatticeMatchesEAndNuForTwoSeeds) {
  for (const std::uint64_t seed : {1u, 2u}) {
    RandomLatticeOptions options;
    options.size = Eigen::Vector3d(3.0, 1.0, 1.0);
    options.lattice.spacing = 0.1;
    options.min_distance = 0.8;
    options.max_distance = 1.9;
    options.seed = seed;
    const Model model = BuildRandomLattice(kMaterial, options);
    const ModelStatistics stats = ComputeModelStatistics(model);
    ASSERT_GE(stats.mean_springs_per_node, 15.0);
    ASSERT_LE(stats.mean_springs_per_node, 25.0);
    const CompressionExperimentResult r = Compress(model, options.size);
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.05) << "seed " << seed;
    EXPECT_NEAR(r.poisson_measured, 0.25, 0.02) << "seed " << seed;
  }
}

TEST(Calibration, NodeCentredCantileverFollowsEulerBernoulliAtTwoResolutions) {
  std::vector<double> tips;
  for (const double a : {1.0 / 16.0, 1.0 / 20.0}) {
    CubicLatticeOptions lattice_options;
    lattice_options.size = Eigen::Vector3d(4.0, 1.0, 1.0);
    lattice_options.lattice.spacing = a;
    const Model model = BuildCubicLattice(kMaterial, lattice_options);
    CantileverExperimentOptions options;
    options.body_size = lattice_options.size;
    options.total_force = 0.1;  // tip deflection ~ 2.5e-4 m: small deflection
    const CantileverExperimentResult r = RunCantileverExperiment(model, options);
    ASSERT_TRUE(r.solver.converged) << r.solver.message;
    EXPECT_NEAR(r.tip_deflection / r.theory_tip_deflection, 1.0, 0.05) << "spacing " << a;
    // The whole profile bends the right way: deflection grows along the bar.
    for (std::size_t i = 1; i < r.profile.size(); ++i) {
      EXPECT_GT(r.profile[i].deflection, r.profile[i - 1].deflection);
    }
    tips.push_back(r.tip_deflection);
  }
  EXPECT_NEAR(tips[0] / tips[1], 1.0, 0.03);
}

// The 20 x 10 x 10-node block of kBlock at `poisson`, compressed by `strain`; surface_dispersion
// as CubicLatticeOptions'.
CompressionExperimentResult CompressTenCellsAcross(double poisson, double strain,
                                                   double surface_dispersion = 1.0) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = kBlock;
  lattice_options.lattice.spacing = 0.1;
  lattice_options.surface.surface_dispersion = surface_dispersion;
  const Model model =
      BuildCubicLattice(Material::FromYoungsPoisson(kYoungs, poisson, 1100.0), lattice_options);
  CompressionExperimentOptions options;
  options.body_size = kBlock;
  options.strain = strain;
  return RunCompressionExperiment(model, options);
}

// The fidelity issue, must-show 2: a node-centred cubic block 10 cells across (20 x 10 x 10
// nodes) reads E within 1 % and nu within 0.003 of the target for nu = -0.5, 0.25 and 0.45.
// E and nu are small-strain moduli, so the block is compressed by 1e-3 (as the random lattices'
// self-calibration measures them). At the experiment's default 1 % the secant reads lower
// (measured -0.5 %, -1.1 %, -1.6 % against -0.4 %, -0.5 %, -0.7 % at 1e-3): a linear spring
// network softens under finite compression, as its springs turn (docs/physics.md section 6).
TEST(Calibration, NodeCentredCubicTenCellsAcrossMatchesSmallStrainEAndNu) {
  for (const double poisson : {-0.5, 0.25, 0.45}) {
    const CompressionExperimentResult small = CompressTenCellsAcross(poisson, 1e-3);
    ASSERT_TRUE(small.solver.converged) << small.solver.message;
    std::printf("  nu %+.2f, strain 1e-3: E %+.3f %%, nu %.4f\n", poisson,
                100.0 * (small.youngs_measured / kYoungs - 1.0), small.poisson_measured);
    EXPECT_NEAR(small.youngs_measured / kYoungs, 1.0, 0.01) << "nu " << poisson;
    EXPECT_NEAR(small.poisson_measured, poisson, 0.003) << "nu " << poisson;
    // The finite-strain secant is softer, by about 0.7 E per unit of strain at nu = 0.25.
    const CompressionExperimentResult finite = CompressTenCellsAcross(poisson, 1e-2);
    ASSERT_TRUE(finite.solver.converged) << finite.solver.message;
    EXPECT_LT(finite.youngs_measured, small.youngs_measured) << "nu " << poisson;
  }
}

// The softer outer layer (NodeCentredSurfaceOptions::surface_dispersion = 0.5, docs/physics.md §7)
// keeps the block's summed bulk, so the same block still reads E within 1 %; its nu reads a
// little high where the bulk matters more (measured +0.0042 at nu = 0.45, +0.0012 at 0.49,
// against -0.0007 and -0.0006 without it), hence 0.005 here instead of 0.003.
TEST(Calibration, NodeCentredCubicWithASofterOuterLayerKeepsEAndNu) {
  for (const double poisson : {0.33, 0.45, 0.49}) {
    const CompressionExperimentResult r = CompressTenCellsAcross(poisson, 1e-3, 0.5);
    ASSERT_TRUE(r.solver.converged) << r.solver.message;
    std::printf("  nu %.2f, outer layer at half its bulk: E %+.3f %%, nu %.4f\n", poisson,
                100.0 * (r.youngs_measured / kYoungs - 1.0), r.poisson_measured);
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.01) << "nu " << poisson;
    EXPECT_NEAR(r.poisson_measured, poisson, 0.005) << "nu " << poisson;
  }
}

// A quarter of its bulk in the outer layer (the share docs/physics.md §7 recommends at
// nu >= 0.48) still reads E within 1 % and nu within the plain lattice's 0.003 at nu = 0.49
// (measured E -0.69 %, nu 0.4922); at nu = 0.45 nu reads 0.4563, which is why it is not
// recommended there.
TEST(Calibration, NodeCentredCubicWithAQuarterShareOuterLayerKeepsEAndNuAtNu049) {
  const CompressionExperimentResult r = CompressTenCellsAcross(0.49, 1e-3, 0.25);
  ASSERT_TRUE(r.solver.converged) << r.solver.message;
  std::printf("  nu 0.49, outer layer at a quarter of its bulk: E %+.3f %%, nu %.4f\n",
              100.0 * (r.youngs_measured / kYoungs - 1.0), r.poisson_measured);
  EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.01);
  EXPECT_NEAR(r.poisson_measured, 0.49, 0.003);
}

}  // namespace
}  // namespace msm_sim::core
