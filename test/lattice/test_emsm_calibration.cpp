// Acceptance tests of the extended MSM (any Poisson's ratio, docs/physics.md §3) against linear
// elasticity; tolerances are those of the project's issue "Any Poisson's ratio".
#include <vector>

#include <gtest/gtest.h>

#include "compression_helpers.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::core {
namespace {

constexpr double kYoungs = 1e5;
const std::vector<double> kTargets = {-0.9, -0.5, 0.0, 0.25, 0.33, 0.45, 0.49};

using testing::Compress;

class CubicEmsm : public ::testing::TestWithParam<CubicConstruction> {};

TEST_P(CubicEmsm, MatchesAnyPoissonRatio) {
  for (const double nu : kTargets) {
    CubicLatticeOptions options;
    options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
    options.lattice.spacing = 1.0 / 12.0;
    options.construction = GetParam();
    const Model model =
        BuildCubicLattice(Material::FromYoungsPoisson(kYoungs, nu, 1100.0), options);
    const CompressionExperimentResult r = Compress(model, options.size);
    EXPECT_NEAR(r.poisson_measured, nu, 0.02) << "target nu " << nu;
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.03) << "target nu " << nu;
  }
}

INSTANTIATE_TEST_SUITE_P(Constructions, CubicEmsm,
                         ::testing::Values(CubicConstruction::kNodeCentred,
                                           CubicConstruction::kElementCorner));

class RandomEmsm : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomEmsm, MatchesAnyPoissonRatio) {
  for (const double nu : kTargets) {
    RandomLatticeOptions options;
    options.size = Eigen::Vector3d(3.0, 1.0, 1.0);
    options.lattice.spacing = 0.1;
    options.max_distance = 1.9;
    options.seed = GetParam();
    const Model model =
        BuildRandomLattice(Material::FromYoungsPoisson(kYoungs, nu, 1100.0), options);
    const double springs_per_node = ComputeModelStatistics(model).mean_springs_per_node;
    ASSERT_GE(springs_per_node, 15.0);
    ASSERT_LE(springs_per_node, 25.0);
    const CompressionExperimentResult r = Compress(model, options.size);
    EXPECT_NEAR(r.poisson_measured, nu, 0.03) << "target nu " << nu;
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.05) << "target nu " << nu;
  }
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomEmsm, ::testing::Values(1u, 2u));

}  // namespace
}  // namespace msm_sim::core
