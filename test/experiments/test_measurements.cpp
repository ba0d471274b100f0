#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "geometry/tetrahedralization.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/experiments/hardy_stress.h"
#include "msm_sim/experiments/strain_probe.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/momentum_flow.h"
#include "msm_sim/mechanics/uniaxial_compression.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.25, 1000.0);

// Positions after the affine map x -> centre + (I + strain)(x - centre).
Eigen::Matrix3Xd Affine(const Model& model, const Eigen::Matrix3d& strain,
                        const Eigen::Vector3d& centre) {
  const Eigen::Matrix3Xd r = model.rest_positions().colwise() - centre;
  return (r + strain * r).colwise() + centre;
}

Eigen::VectorXd Tensions(const Model& model, const Eigen::Matrix3Xd& x) {
  ForceEvaluator evaluator(model);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
  evaluator.AccumulateForces(x, &f);
  return evaluator.total_tensions();
}

TEST(MomentumFlow, MatchesTheElasticConstantUnderUniformStrain) {
  // Element-corner lattice: sigma_xx = (lambda + 2 mu) eps_xx = 3 mu eps exactly (lambda = mu).
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  options.lattice.spacing = 0.125;
  options.construction = CubicConstruction::kElementCorner;
  const Model model = BuildCubicLattice(kMaterial, options);
  const double eps = 1e-7;
  const Eigen::Matrix3d strain = Eigen::Vector3d(eps, 0, 0).asDiagonal();
  const Eigen::Vector3d centre(1.0, 0.5, 0.5);
  const Eigen::Matrix3Xd x = Affine(model, strain, centre);
  const double mu = kMaterial.youngs_modulus() / 2.5;
  // The cut through the middle and one between layers give the same, exact force.
  for (const double plane_x : {1.0, 1.0 + 0.5 * options.lattice.spacing}) {
    const Eigen::Vector3d flow = MomentumFlowThroughPlane(
        model, x, Tensions(model, x),
        MaterialPlane{Eigen::Vector3d(plane_x, 0.5, 0.5), Eigen::Vector3d::UnitX()});
    EXPECT_NEAR(flow.x() / (3.0 * mu * eps * 1.0), 1.0, 1e-6);
    EXPECT_NEAR(flow.y(), 0.0, 1e-9);
  }
}

TEST(HardyStress, ConvergesToTheContinuumStressWithProbeSize) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 2.0, 2.0);
  options.lattice.spacing = 0.1;
  const Model model = BuildCubicLattice(kMaterial, options);
  const double eps = 1e-7;
  const Eigen::Matrix3d strain = Eigen::Vector3d(eps, 0, 0).asDiagonal();
  const Eigen::Vector3d centre(1.0, 1.0, 1.0);
  const Eigen::Matrix3Xd x = Affine(model, strain, centre);
  const double mu = kMaterial.youngs_modulus() / 2.5;
  // Tension positive: a stretched lattice has positive sigma_xx = 3 mu eps, sigma_yy = mu eps.
  const Eigen::VectorXd tensions = Tensions(model, x);
  const Eigen::Matrix3d wide =
      HardyStress(model, x, tensions, centre, 5.0 * options.lattice.spacing);
  EXPECT_NEAR(wide(0, 0) / (3.0 * mu * eps), 1.0, 0.03);
  EXPECT_NEAR(wide(1, 1) / (mu * eps), 1.0, 0.05);
  EXPECT_NEAR(wide(0, 1) / (mu * eps), 0.0, 0.02);
  const Eigen::Matrix3d probe =
      HardyStress(model, x, tensions, centre, 1.3 * options.lattice.spacing);
  EXPECT_NEAR(probe(0, 0) / (3.0 * mu * eps), 1.0, 0.1);
}

TEST(HardyStress, SegmentFractionInsideBall) {
  const Eigen::Vector3d c = Eigen::Vector3d::Zero();
  EXPECT_DOUBLE_EQ(SegmentFractionInsideBall({-2, 0, 0}, {2, 0, 0}, c, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(SegmentFractionInsideBall({0, 0, 0}, {0.5, 0, 0}, c, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(SegmentFractionInsideBall({0, 0, 0}, {4, 0, 0}, c, 1.0), 0.25);
  EXPECT_DOUBLE_EQ(SegmentFractionInsideBall({-2, 3, 0}, {2, 3, 0}, c, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(SegmentFractionInsideBall({1, 1, 1}, {1, 1, 1}, c, 5.0), 0.0);
}

TEST(StrainProbe, RecoversAnAffineStrainExactly) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(1.0, 1.0, 1.0);
  options.lattice.spacing = 0.125;
  options.lattice.rotation_axis = Eigen::Vector3d(1, 2, 3);
  options.lattice.rotation_angle = 0.4;
  const Model model = BuildCubicLattice(kMaterial, options);
  Eigen::Matrix3d gradient;
  gradient << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, 0.0, 7e-4, 4e-4;
  const Eigen::Matrix3Xd displacement = gradient * model.rest_positions();
  const StrainProbe probe(model.rest_positions());
  const auto strain = probe.StrainAt({0.5, 0.5, 0.5}, displacement, 0.0625);
  ASSERT_TRUE(strain.has_value());
  EXPECT_LT((*strain - 0.5 * (gradient + gradient.transpose())).norm(), 1e-12);
  EXPECT_FALSE(probe.DisplacementAt({5, 5, 5}, displacement).has_value());
}

TEST(StressCorrectedPoisson, InvertsHookesLawForAnyStressState) {
  const double e = 3.0, nu = 0.3;
  const Eigen::Matrix3d stress = Eigen::Vector3d(-2.0, 0.7, 0.3).asDiagonal();
  Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    strain(i, i) = (stress(i, i) - nu * (stress.trace() - stress(i, i))) / e;
  }
  EXPECT_NEAR(StressCorrectedPoisson(strain, stress), nu, 1e-12);
}

TEST(CompressionTest, RejectsImpossibleSetUps) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 1.0, 1.0);
  options.lattice.spacing = 0.125;
  const Model model = BuildCubicLattice(kMaterial, options);
  CompressionExperimentOptions test;
  test.body_size = options.size;
  test.strain = 0.6;
  EXPECT_THROW(RunCompressionExperiment(model, test), std::invalid_argument);
  test.strain = 0.01;  // end regions of 1.5 x sqrt(2) a on a 4-layer block leave nothing free
  EXPECT_THROW(RunCompressionExperiment(model, test), std::invalid_argument);
}

TEST(CompressionTest, ReadsWhatTheUniaxialCompressionMeasures) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  options.lattice.spacing = 0.125;
  const Model model = BuildCubicLattice(kMaterial, options);
  CompressionExperimentOptions test;
  test.body_size = options.size;
  const CompressionExperimentResult result = RunCompressionExperiment(model, test);
  const UniaxialCompression compression = MeasureUniaxialCompression(model, test);
  EXPECT_EQ(result.youngs_measured, compression.youngs);
  EXPECT_EQ(result.poisson_measured, compression.poisson);
  EXPECT_EQ(result.axial_force, compression.axial_force);
  EXPECT_EQ(result.end_nodes, compression.end_nodes);
  EXPECT_EQ(result.central_nodes, compression.central_nodes);
  EXPECT_EQ(result.solver.newton_iterations, compression.solver.newton_iterations);
  // The probes at the centre read the same block: E within a few per cent of the flow's.
  EXPECT_NEAR(result.youngs_stress_corrected / result.youngs_measured, 1.0, 0.1);
}

}  // namespace
}  // namespace msm_sim::core

namespace msm_sim::core {
namespace {

TEST(Tetrahedralization, FillsTheHullWithPositiveTetrahedraAndDetectsInversion) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.3, 0.3);
  options.lattice.spacing = 0.1;
  const Model model = BuildCubicLattice(kMaterial, options);
  const std::vector<Tetrahedron> tetrahedra = DelaunayTetrahedra(model.rest_positions());
  double volume = 0.0;
  for (const Tetrahedron& t : tetrahedra) {
    EXPECT_GT(SignedVolume(t, model.rest_positions()), 0.0);
    volume += SignedVolume(t, model.rest_positions());
  }
  // Node-centred nodes span (4 - 1) x (3 - 1) x (3 - 1) cells of 0.1 m.
  EXPECT_NEAR(volume, 0.3 * 0.2 * 0.2, 1e-12);
  EXPECT_EQ(CountInvertedTetrahedra(tetrahedra, model.rest_positions()), 0);
  // A mirror image inverts every tetrahedron; a rotation inverts none.
  Eigen::Matrix3Xd mirrored = model.rest_positions();
  mirrored.row(0) *= -1.0;
  EXPECT_EQ(CountInvertedTetrahedra(tetrahedra, mirrored), static_cast<int>(tetrahedra.size()));
  const Eigen::Matrix3Xd rotated =
      Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() *
      model.rest_positions();
  EXPECT_EQ(CountInvertedTetrahedra(tetrahedra, rotated), 0);
}

}  // namespace
}  // namespace msm_sim::core
