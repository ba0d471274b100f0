// Acceptance tests of the random lattice's self-calibration (docs/physics.md §2.2; issue
// "Fidelity against FEM", must-show 3): with <S> in 15-25, nu in {-0.6, 0, 0.25, 0.45, 0.49} and
// two seeds, E within 2 % and nu within 0.01 in the virtual compression test. The body is
// measured with seeds different from the representative block's.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "compression_helpers.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/material/extended_msm.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::core {
namespace {

constexpr double kYoungs = 1e5;
const std::vector<double> kTargets = {-0.6, 0.0, 0.25, 0.45, 0.49};
// The bodies are compressed by 10^-3, the small-strain moduli the calibration measures (and
// targets). At the default 1 % the corrected nu = 0.49 bodies (q = 55) took 23 minutes of
// static solves, and read E -0.53 / -0.52 %, nu -0.0055 / +0.0015 (seeds 1 / 2).
constexpr double kStrain = 1e-3;
const std::vector<std::uint64_t> kSeeds = {1u, 2u};

using testing::Compress;

// The random lattice: minL 0.8 l, maxL 1.8 l (<S> about 20), a 3 x 1 x 1 m block 15
// spacings wide. The correction is for bulk material; a block 10 spacings wide read about 1.5 %
// stiffer than the bulk, and seeds differ by about 1.5 % there (docs/physics.md §2.2).
RandomLatticeOptions BodyOptions(std::uint64_t seed) {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(3.0, 1.0, 1.0);
  options.lattice.spacing = 1.0 / 15.0;
  options.min_distance = 0.8;
  options.max_distance = 1.8;
  options.seed = seed;
  return options;
}

struct Errors {
  double youngs;   // relative
  double poisson;  // absolute
};

Errors Measure(const Material& material, const RandomLatticeOptions& options) {
  const Model model = BuildRandomLattice(material, options);
  const double springs_per_node = ComputeModelStatistics(model).mean_springs_per_node;
  EXPECT_GE(springs_per_node, 15.0);
  EXPECT_LE(springs_per_node, 25.0);
  const CompressionExperimentResult r = Compress(model, options.size, kStrain);
  return Errors{r.youngs_measured / kYoungs - 1.0, r.poisson_measured - material.poisson_ratio()};
}

// One calibration per nu serves both seeds (the representative block has its own seed), as a
// cached correction would. Without it, the largest errors over the grid are what the issue
// reports (E -4 to -5 %); with it, every case meets the target.
TEST(RandomSelfCalibration, MeetsTargetForEveryPoissonRatioAndSeed) {
  double worst_plain_youngs = 0.0, worst_plain_poisson = 0.0;
  for (const double nu : kTargets) {
    const Material material = Material::FromYoungsPoisson(kYoungs, nu, 1100.0);
    RandomLatticeOptions calibrate = BodyOptions(1);
    const RandomSelfCalibration calibration = MeasureRandomSelfCalibration(material, calibrate);
    for (const std::uint64_t seed : kSeeds) {
      ASSERT_NE(seed, calibrate.calibration_seed);
      RandomLatticeOptions options = BodyOptions(seed);
      const Errors plain = Measure(material, options);
      worst_plain_youngs = std::max(worst_plain_youngs, std::abs(plain.youngs));
      worst_plain_poisson = std::max(worst_plain_poisson, std::abs(plain.poisson));
      options.calibration = calibration;
      const Errors corrected = Measure(material, options);
      std::printf(
          "  nu %.2f seed %d: E %+.2f %%, nu %+.4f -> E %+.2f %%, nu %+.4f (k x %.4f, q %.4f)\n",
          nu, static_cast<int>(seed), 100.0 * plain.youngs, plain.poisson, 100.0 * corrected.youngs,
          corrected.poisson, calibration.stiffness_factor, calibration.dispersion_fraction);
      EXPECT_NEAR(corrected.youngs, 0.0, 0.02) << "nu " << nu << " seed " << seed;
      EXPECT_NEAR(corrected.poisson, 0.0, 0.01) << "nu " << nu << " seed " << seed;
    }
  }
  // The fix matters: uncorrected, the same grid misses the target.
  EXPECT_GT(worst_plain_youngs, 0.04);
  EXPECT_GT(worst_plain_poisson, 0.02);
}

// self_calibrate measures the same correction as MeasureRandomSelfCalibration and is
// deterministic: the same options give identical springs.
TEST(RandomSelfCalibration, IsDeterministicAndEqualsTheMeasuredCorrection) {
  const Material material = Material::FromYoungsPoisson(kYoungs, 0.45, 1100.0);
  RandomLatticeOptions options = BodyOptions(3);
  options.size = Eigen::Vector3d(1.0, 0.5, 0.5);
  options.calibration_block_cells = 8;
  options.self_calibrate = true;
  const Model first = BuildRandomLattice(material, options);
  const Model second = BuildRandomLattice(material, options);
  ASSERT_EQ(first.num_springs(), second.num_springs());
  for (int s = 0; s < first.num_springs(); ++s) {
    ASSERT_EQ(first.spring_stiffness()[s], second.spring_stiffness()[s]);
  }
  EXPECT_EQ(first.dispersion_fraction(), second.dispersion_fraction());

  const RandomSelfCalibration calibration = MeasureRandomSelfCalibration(material, options);
  options.self_calibrate = false;
  const Model plain = BuildRandomLattice(material, options);
  EXPECT_EQ(first.dispersion_fraction(), calibration.dispersion_fraction);
  EXPECT_NE(first.dispersion_fraction(), plain.dispersion_fraction());
  EXPECT_NEAR(first.spring_stiffness()[0] / plain.spring_stiffness()[0],
              calibration.stiffness_factor, 1e-12);
  EXPECT_NE(calibration.stiffness_factor, 1.0);
}

}  // namespace
}  // namespace msm_sim::core
