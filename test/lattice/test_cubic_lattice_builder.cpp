#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(2e5, 0.25, 1100.0);

// Sum of k L^2 over all springs: 6 E V for a calibrated isotropic network (docs/physics.md §2).
double SumKL2(const Model& model) {
  double sum = 0.0;
  for (int s = 0; s < model.num_springs(); ++s) {
    sum += model.spring_stiffness()[s] * std::pow(model.spring_rest_length()[s], 2);
  }
  return sum;
}

// Index of the node at rest position p (within 1e-9), or -1.
int NodeAt(const Model& model, const Eigen::Vector3d& p) {
  for (int i = 0; i < model.num_nodes(); ++i) {
    if ((model.rest_positions().col(i) - p).norm() < 1e-9) return i;
  }
  return -1;
}

double StiffnessBetween(const Model& model, int a, int b) {
  for (int s = 0; s < model.num_springs(); ++s) {
    const int sa = model.spring_node_a()[s];
    const int sb = model.spring_node_b()[s];
    if ((sa == a && sb == b) || (sa == b && sb == a)) return model.spring_stiffness()[s];
  }
  return 0.0;
}

TEST(CubicLatticeBuilder, NodeCentredCountsMassesAndSprings) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(1.0, 1.0, 1.0);
  options.lattice.spacing = 0.25;
  options.surface.compensate_surface = false;
  const Model model = BuildCubicLattice(kMaterial, options);
  const ModelStatistics stats = ComputeModelStatistics(model);
  EXPECT_EQ(stats.nodes, 64);
  // A springs: 3 axes x 3 x 4 x 4; B springs: 3 planes x 2 diagonals x 3 x 3 x 4.
  EXPECT_EQ(stats.springs, 144 + 216);
  EXPECT_NEAR(stats.total_mass, 1100.0, 1e-9);
  // Nodes sit half a cell inside the surface.
  EXPECT_NEAR(model.rest_positions().minCoeff(), 0.125, 1e-12);
  EXPECT_NEAR(model.rest_positions().maxCoeff(), 0.875, 1e-12);
  const double kappa = 0.4 * 2e5 * 0.25;
  for (double k : model.spring_stiffness()) EXPECT_DOUBLE_EQ(k, kappa);
  // An interior node has all 18 A+B neighbours.
  EXPECT_EQ(model.num_incident_springs(NodeAt(model, {0.375, 0.375, 0.375})), 18);
}

TEST(CubicLatticeBuilder, SurfaceCompensationMovesMissingHalfSpringsInward) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(1.0, 1.0, 1.0);
  options.lattice.spacing = 0.25;
  const Model model = BuildCubicLattice(kMaterial, options);
  const double kappa = 0.4 * 2e5 * 0.25;
  // A node on the x = 0 face (not on an edge) misses its -x neighbour: the +x spring carries it.
  const int face = NodeAt(model, {0.125, 0.375, 0.375});
  const int inner = NodeAt(model, {0.375, 0.375, 0.375});
  const int deeper = NodeAt(model, {0.625, 0.375, 0.375});
  ASSERT_GE(face, 0);
  EXPECT_DOUBLE_EQ(StiffnessBetween(model, face, inner), 1.5 * kappa);
  EXPECT_DOUBLE_EQ(StiffnessBetween(model, inner, deeper), kappa);
  // A full network has sum k L^2 = 6 E V = 960 kappa a^2 for these 64 nodes (15 kappa a^2 each).
  // Without compensation 576 kappa a^2 are there (144 A springs, 216 B springs of length sqrt2 a).
  // With it, only half-springs whose node misses both i + d and i - d stay lost: on each of the 12
  // edges, 4 nodes lack 2 face diagonals in the plane across the edge, 12 x 4 x 2 x kappa a^2.
  const double target = 6.0 * 2e5 * 1.0;
  options.surface.compensate_surface = false;
  const double plain = SumKL2(BuildCubicLattice(kMaterial, options));
  const double compensated = SumKL2(model);
  EXPECT_NEAR(plain / target, 576.0 / 960.0, 1e-12);
  EXPECT_NEAR(compensated / target, (960.0 - 96.0) / 960.0, 1e-12);
}

TEST(CubicLatticeBuilder, ElementCornerSumsElementContributions) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  options.lattice.spacing = 1.0;
  options.construction = CubicConstruction::kElementCorner;
  const Model model = BuildCubicLattice(kMaterial, options);
  const double kappa = 0.4 * 2e5 * 1.0;
  ASSERT_EQ(model.num_nodes(), 12);
  EXPECT_NEAR(model.masses().sum(), 2.0 * 1100.0, 1e-9);
  // Shared face (x = 1): its corners carry 2/8 of an element's mass, its edges 2 x 0.25 kappa
  // and its diagonals 2 x 0.5 kappa; an outer edge 0.25 kappa.
  const int shared = NodeAt(model, {1, 0, 0});
  EXPECT_NEAR(model.masses()[shared], 2.0 * 1100.0 / 8.0, 1e-9);
  EXPECT_DOUBLE_EQ(StiffnessBetween(model, shared, NodeAt(model, {1, 1, 0})), 0.5 * kappa);
  EXPECT_DOUBLE_EQ(StiffnessBetween(model, shared, NodeAt(model, {1, 1, 1})), kappa);
  EXPECT_DOUBLE_EQ(StiffnessBetween(model, NodeAt(model, {0, 0, 0}), NodeAt(model, {1, 0, 0})),
                   0.25 * kappa);
  EXPECT_DOUBLE_EQ(StiffnessBetween(model, NodeAt(model, {0, 0, 0}), NodeAt(model, {1, 1, 1})),
                   0.0);  // no body diagonals in the A+B model
  // Each element contributes exactly 15 kappa a^2 = 6 E a^3 (docs/physics.md §2).
  EXPECT_NEAR(SumKL2(model), 6.0 * 2e5 * 2.0, 1e-6);
}

TEST(CubicLatticeBuilder, RotatedLatticeStaysInsideTheBoxAndFillsIt) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  options.lattice.spacing = 0.1;
  options.lattice.rotation_axis = Eigen::Vector3d(0.4, -0.3, 0.7);
  options.lattice.rotation_angle = 30.0 * M_PI / 180.0;
  const Model model = BuildCubicLattice(kMaterial, options);
  EXPECT_GE(model.rest_positions().minCoeff(), -1e-9);
  EXPECT_TRUE(
      (model.rest_positions().rowwise().maxCoeff().array() <= options.size.array() + 1e-9).all());
  EXPECT_NEAR(model.num_nodes() * 1e-3 / 2.0, 1.0, 0.02);
  // The lattice really is rotated: the first spring is not axis aligned.
  const Eigen::Vector3d r = model.rest_positions().col(model.spring_node_b()[0]) -
                            model.rest_positions().col(model.spring_node_a()[0]);
  EXPECT_LT(r.cwiseAbs().maxCoeff() / r.norm(), 0.99);
}

TEST(CubicLatticeBuilder, RejectsBadGeometry) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(1.0, 1.0, 1.0);
  options.lattice.spacing = 2.0;  // larger than the body
  EXPECT_THROW(BuildCubicLattice(kMaterial, options), std::invalid_argument);
  options.lattice.spacing = nan;
  EXPECT_THROW(BuildCubicLattice(kMaterial, options), std::invalid_argument);
  options.lattice.spacing = 0.1;
  options.size.x() = -1.0;
  EXPECT_THROW(BuildCubicLattice(kMaterial, options), std::invalid_argument);
  options.size.x() = 1.0;
  options.lattice.rotation_axis.setZero();
  options.lattice.rotation_angle = 0.3;
  EXPECT_THROW(BuildCubicLattice(kMaterial, options), std::invalid_argument);
  options.lattice.rotation_axis = Eigen::Vector3d::UnitZ();
  options.lattice.spacing = 1e-4;  // 1e12 nodes
  EXPECT_THROW(BuildCubicLattice(kMaterial, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
