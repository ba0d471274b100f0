// The softer outer layer of the eMSM dispersion (src/lattice/outer_layer_dispersion.h,
// NodeCentredSurfaceOptions::surface_dispersion, docs/physics.md §7 "A softer outer layer"). Its
// effect on the stable step is in test/mechanics/test_stable_time_step.cpp, on compression in
// test/lattice/test_calibration.cpp, on a resolved contact in
// test/experiments/test_hertz_contact.cpp, on a grip in test_grip_experiment.cpp and on bending
// against CalculiX in test_cantilever_faces.cpp.
#include "lattice/outer_layer_dispersion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"

namespace msm_sim::core {
namespace {

const Material kRubber = Material::FromYoungsPoisson(2e5, 0.49, 1100.0);

Model Box(double keep, const Material& material = kRubber) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.06, 0.05, 0.04);  // 12 x 10 x 8 cells
  options.lattice.spacing = 0.005;
  options.surface.surface_dispersion = keep;
  return BuildCubicLattice(material, options);
}

// W_x = sum of v k L0^2 over node x's spring ends (Model::dispersion_weight_a).
std::vector<double> StarWeights(const Model& model) {
  std::vector<double> star(model.num_nodes(), 0.0);
  for (int s = 0; s < model.num_springs(); ++s) {
    const double w =
        model.spring_stiffness()[s] * model.spring_rest_length()[s] * model.spring_rest_length()[s];
    star[model.spring_node_a()[s]] += model.dispersion_weight_a()[s] * w;
    star[model.spring_node_b()[s]] += model.dispersion_weight_b()[s] * w;
  }
  return star;
}

// How many cells node i lies from the box's surface: 0 for the outer layer.
int Depth(const Model& model, int i, const Eigen::Vector3d& size, double spacing) {
  const Eigen::Array3d x = model.rest_positions().col(i).array();
  const double from_face = std::min(x.minCoeff(), (size.array() - x).minCoeff());
  return static_cast<int>(std::lround(from_face / spacing - 0.5));
}

// Each outer node keeps `keep` of its star, each node of the second layer grows by one common
// factor (within 1 % here, after the fitting's 100 sweeps), deeper nodes are untouched, and the
// sum, which is what a uniform strain meets, is unchanged.
TEST(OuterLayerDispersion, MovesTheOuterLayersBulkOneLayerInAndKeepsItsSum) {
  const Model plain = Box(1.0);
  const Model softer = Box(0.5);
  ASSERT_EQ(plain.num_springs(), softer.num_springs());
  EXPECT_EQ(plain.spring_stiffness(), softer.spring_stiffness());
  const std::vector<double> before = StarWeights(plain);
  const std::vector<double> after = StarWeights(softer);
  const Eigen::Vector3d size(0.06, 0.05, 0.04);
  double sum_before = 0.0, sum_after = 0.0, outer_before = 0.0, beneath_before = 0.0;
  double lowest = 1e9, highest = 0.0;
  for (int i = 0; i < plain.num_nodes(); ++i) {
    sum_before += before[i];
    sum_after += after[i];
    const double ratio = after[i] / before[i];
    const int depth = Depth(plain, i, size, 0.005);
    if (depth == 0) {
      outer_before += before[i];
      EXPECT_NEAR(ratio, 0.5, 1e-12) << "node " << i;
    } else if (depth == 1) {
      beneath_before += before[i];
      lowest = std::min(lowest, ratio);
      highest = std::max(highest, ratio);
    } else {
      EXPECT_NEAR(ratio, 1.0, 1e-12) << "node " << i;
    }
  }
  EXPECT_NEAR(sum_after / sum_before, 1.0, 1e-12);
  const double common = 1.0 + 0.5 * outer_before / beneath_before;
  std::printf("  second layer: x%.4f to x%.4f (x%.4f if all alike)\n", lowest, highest, common);
  EXPECT_NEAR(lowest / common, 1.0, 0.01);
  EXPECT_NEAR(highest / common, 1.0, 0.01);
}

// Only the dispersion weights change: the springs, masses and q are the calibrated ones.
TEST(OuterLayerDispersion, ChangesNothingButTheDispersionWeights) {
  const Model plain = Box(1.0);
  const Model softer = Box(0.3);
  EXPECT_EQ(plain.masses(), softer.masses());
  EXPECT_EQ(plain.spring_node_a(), softer.spring_node_a());
  EXPECT_EQ(plain.spring_node_b(), softer.spring_node_b());
  EXPECT_EQ(plain.spring_stiffness(), softer.spring_stiffness());
  EXPECT_EQ(plain.dispersion_fraction(), softer.dispersion_fraction());
  EXPECT_NE(plain.dispersion_weight_a(), softer.dispersion_weight_a());
}

// Where the dispersion adds no bulk (nu <= 1/4, q <= 0) there is nothing to soften.
TEST(OuterLayerDispersion, LeavesModelsWithoutAddedBulkAlone) {
  for (const double poisson : {0.25, -0.3}) {
    const Material material = Material::FromYoungsPoisson(2e5, poisson, 1100.0);
    EXPECT_EQ(Box(1.0, material).dispersion_weight_a(), Box(0.5, material).dispersion_weight_a())
        << "nu " << poisson;
  }
}

// A box-shaped solid aligned with the lattice is built like the box, softer layer included.
TEST(OuterLayerDispersion, AMeshBoxGetsTheBoxsWeights) {
  const Eigen::Vector3d size(0.06, 0.05, 0.04);
  TriangleMesh mesh = MakeBoxMesh(size);
  MeshCubicLatticeOptions options;
  options.lattice.spacing = 0.005;
  options.surface.surface_dispersion = 0.5;
  const Model from_mesh = BuildCubicLatticeInSolid(kRubber, SolidMesh(mesh), options);
  const Model box = Box(0.5);
  ASSERT_EQ(from_mesh.num_nodes(), box.num_nodes());
  const std::vector<double> mesh_star = StarWeights(from_mesh);
  const std::vector<double> box_star = StarWeights(box);
  double mesh_sum = 0.0, box_sum = 0.0;
  for (int i = 0; i < box.num_nodes(); ++i) {
    mesh_sum += mesh_star[i];
    box_sum += box_star[i];
  }
  EXPECT_NEAR(mesh_sum / box_sum, 1.0, 1e-6);
  std::vector<double> sorted_mesh = mesh_star, sorted_box = box_star;
  std::sort(sorted_mesh.begin(), sorted_mesh.end());
  std::sort(sorted_box.begin(), sorted_box.end());
  for (int i = 0; i < box.num_nodes(); ++i) {
    EXPECT_NEAR(sorted_mesh[i] / sorted_box[i], 1.0, 1e-6) << i;
  }
}

TEST(OuterLayerDispersion, RefusesAShareOutsideZeroToOne) {
  for (const double keep : {0.0, -0.5, 1.5, std::nan("")}) {
    EXPECT_THROW(Box(keep), std::invalid_argument) << keep;
  }
  CubicLatticeOptions corner;
  corner.size = Eigen::Vector3d(0.06, 0.05, 0.04);
  corner.lattice.spacing = 0.005;
  corner.construction = CubicConstruction::kElementCorner;
  corner.surface.surface_dispersion = 0.5;
  EXPECT_THROW(BuildCubicLattice(kRubber, corner), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
