// The uniaxial compression measurement (MeasureUniaxialCompression) that the compression
// experiment and the random lattices' self-calibration share.

#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/uniaxial_compression.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.25, 1000.0);

Model Block(const Eigen::Vector3d& size) {
  CubicLatticeOptions options;
  options.size = size;
  options.lattice.spacing = 0.125;
  return BuildCubicLattice(kMaterial, options);
}

TEST(UniaxialCompression, ReadsTheCalibratedModuliOfANodeCentredBlock) {
  const Eigen::Vector3d size(2.0, 1.0, 1.0);
  const Model model = Block(size);
  UniaxialCompressionOptions options;
  options.body_size = size;
  options.strain = 1e-3;
  const UniaxialCompression result = MeasureUniaxialCompression(model, options);
  ASSERT_TRUE(result.solver.converged);
  // 8 cells across at small strain: within a few per mille of the calibration (docs/physics.md
  // §6 gives -0.5 % at 10 cells).
  EXPECT_NEAR(result.youngs / kMaterial.youngs_modulus(), 1.0, 0.02);
  EXPECT_NEAR(result.poisson, kMaterial.poisson_ratio(), 0.01);
  EXPECT_NEAR(result.axial_force, result.youngs * options.strain * size.y() * size.z(), 1e-9);
  EXPECT_GT(result.end_nodes, 0);
  EXPECT_GE(result.central_nodes, 8);
  EXPECT_EQ(result.positions.cols(), model.num_nodes());
  EXPECT_EQ(result.tensions.size(), model.num_springs());
}

TEST(UniaxialCompression, CompressesAlongTheAxisItIsGiven) {
  const Eigen::Vector3d size(1.0, 1.0, 2.0);
  const Model model = Block(size);
  UniaxialCompressionOptions options;
  options.body_size = size;
  options.axis = 2;
  options.strain = 1e-3;
  const UniaxialCompression result = MeasureUniaxialCompression(model, options);
  ASSERT_TRUE(result.solver.converged);
  EXPECT_NEAR(result.youngs / kMaterial.youngs_modulus(), 1.0, 0.02);
  EXPECT_NEAR(result.poisson, kMaterial.poisson_ratio(), 0.01);
}

TEST(UniaxialCompression, RejectsImpossibleSetUps) {
  const Eigen::Vector3d size(0.5, 1.0, 1.0);
  const Model model = Block(size);
  UniaxialCompressionOptions options;
  options.body_size = size;
  options.axis = 3;
  EXPECT_THROW(MeasureUniaxialCompression(model, options), std::invalid_argument);
  options.axis = 0;
  options.strain = 0.6;
  EXPECT_THROW(MeasureUniaxialCompression(model, options), std::invalid_argument);
  options.strain = 0.01;  // end regions of 1.5 x sqrt(2) a on a 4-layer block leave nothing free
  EXPECT_THROW(MeasureUniaxialCompression(model, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
