// Baudet et al.'s cubic elements with orthogonal correction forces (seeds 003/004), with the
// stiffnesses derived in docs/baudet_derivation.md. Tolerances from the issue "Any Poisson's
// ratio": E and nu within 5 % at nu in {0.1, 0.25, 0.4}.
#include <gtest/gtest.h>

#include "compression_helpers.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"

namespace msm_sim::core {
namespace {

constexpr double kYoungs = 1e5;

CompressionExperimentResult CompressBaudet(double poisson, bool correction) {
  BaudetLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  options.lattice.spacing = 1.0 / 12.0;
  options.orthogonal_correction = correction;
  const Model model =
      BuildBaudetLattice(Material::FromYoungsPoisson(kYoungs, poisson, 1100.0), options);
  return testing::Compress(model, options.size);
}

TEST(Baudet, StiffnessesMatchThePapersStatements) {
  for (const double nu : {-0.5, 0.0, 0.1, 0.25, 0.4, 0.49}) {
    const Material m = Material::FromYoungsPoisson(kYoungs, nu, 1000.0);
    const BaudetStiffness k = ComputeBaudetStiffness(m, 0.1);
    // "Inner diagonals fully define the shearing modulus": k_c = 3 E x0 / (8 (1 + nu)).
    EXPECT_NEAR(k.diagonal, 3.0 * kYoungs * 0.1 / (8.0 * (1.0 + nu)), 1e-9);
    EXPECT_NEAR(k.correction, kYoungs * 0.1 * (4 * nu - 1) / (32 * (1 + nu) * (1 - 2 * nu)), 1e-9);
  }
  // The correction vanishes at nu = 1/4, where the edges alone give k = E a / 5.
  const BaudetStiffness quarter =
      ComputeBaudetStiffness(Material::FromYoungsPoisson(kYoungs, 0.25, 1000.0), 0.1);
  EXPECT_EQ(quarter.correction, 0.0);
  EXPECT_NEAR(quarter.edge, kYoungs * 0.1 / 5.0, 1e-9);
}

TEST(Baudet, MatchesEAndNuWithTheCorrection) {
  for (const double nu : {0.1, 0.25, 0.4}) {
    const CompressionExperimentResult r = CompressBaudet(nu, true);
    EXPECT_NEAR(r.youngs_measured / kYoungs, 1.0, 0.05) << nu;
    EXPECT_NEAR(r.poisson_measured / nu, 1.0, 0.05) << nu;
  }
}

TEST(Baudet, WithoutTheCorrectionOnlyAQuarterWorks) {
  const CompressionExperimentResult quarter = CompressBaudet(0.25, false);
  EXPECT_NEAR(quarter.poisson_measured, 0.25, 0.005);
  EXPECT_NEAR(quarter.youngs_measured / kYoungs, 1.0, 0.01);
  for (const double nu : {0.1, 0.4}) {
    const CompressionExperimentResult r = CompressBaudet(nu, false);
    EXPECT_GT(std::abs(r.poisson_measured - nu), 0.1) << nu;
  }
}

}  // namespace
}  // namespace msm_sim::core
