// Skinning a visual surface onto MSMs (issue "Any mesh in", must-show 3).
#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/surface_skin.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.3, 1000.0);

// The models a skin must follow: anti-aliased cubic (nodes half a cell inside the surface) and
// random, both built from a coarse sphere and skinned with a finer one.
std::vector<Model> SphereModels() {
  const SolidMesh coarse(MakeIcosphereMesh(1.0, 3));
  MeshCubicLatticeOptions cubic;
  cubic.lattice.spacing = 0.25;
  cubic.lattice.rotation_axis = Eigen::Vector3d(1, 1, 0);
  cubic.lattice.rotation_angle = 0.4;
  RandomLatticeOptions random;
  random.lattice.spacing = 0.25;
  random.max_distance = 1.9;
  std::vector<Model> models;
  models.push_back(BuildCubicLatticeInSolid(kMaterial, coarse, cubic));
  models.push_back(BuildRandomLatticeInSolid(kMaterial, coarse, random));
  return models;
}

// Trilinear coordinates of p in the cell with corners c (index i + 2 j + 4 k), by Newton's
// method on the trilinear map; NaN if it does not converge.
Eigen::Vector3d InvertTrilinear(const std::array<Eigen::Vector3d, 8>& c, const Eigen::Vector3d& p) {
  Eigen::Vector3d u = Eigen::Vector3d::Constant(0.5);
  for (int iteration = 0; iteration < 50; ++iteration) {
    const std::array<double, 8> w = TrilinearWeights(u);
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 8; ++k) {
      x += w[k] * c[k];
      for (int axis = 0; axis < 3; ++axis) {
        // d w_k / d u_axis: the product of the other two factors, signed by the corner's side.
        double derivative = ((k >> axis) & 1) ? 1.0 : -1.0;
        for (int other = 0; other < 3; ++other) {
          if (other != axis) derivative *= ((k >> other) & 1) ? u[other] : 1.0 - u[other];
        }
        jacobian.col(axis) += derivative * c[k];
      }
    }
    if ((p - x).norm() < 1e-13) return u;
    u += jacobian.fullPivLu().solve(p - x);
  }
  return Eigen::Vector3d::Constant(std::nan(""));
}

TEST(SurfaceSkin, RestStateReproducesTheSurface) {
  const TriangleMesh fine = MakeIcosphereMesh(1.0, 4);
  for (const Model& model : SphereModels()) {
    const SurfaceSkin skin = SurfaceSkin::Embed(model, fine);
    const Eigen::Matrix3Xd vertices = skin.DeformedVertices(model.rest_positions());
    EXPECT_LT((vertices - fine.vertices).cwiseAbs().maxCoeff(), 1e-9);
    const Eigen::Matrix3Xd normals = skin.DeformedNormals(vertices);
    // On a sphere the vertex normals point (nearly) radially.
    for (int v = 0; v < skin.num_vertices(); ++v) {
      EXPECT_GT(normals.col(v).dot(fine.vertices.col(v).normalized()), 0.999);
    }
  }
}

TEST(SurfaceSkin, RigidMotionMovesTheSkinRigidly) {
  const TriangleMesh fine = MakeIcosphereMesh(1.0, 4);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gaussian;
  for (const Model& model : SphereModels()) {
    const SurfaceSkin skin = SurfaceSkin::Embed(model, fine);
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Matrix3d r =
          Eigen::AngleAxisd(
              3.0 * gaussian(rng),
              Eigen::Vector3d(gaussian(rng), gaussian(rng), gaussian(rng)).normalized())
              .toRotationMatrix();
      const Eigen::Vector3d t(10 * gaussian(rng), 10 * gaussian(rng), 10 * gaussian(rng));
      const Eigen::Matrix3Xd moved_nodes = (r * model.rest_positions()).colwise() + t;
      const Eigen::Matrix3Xd expected = (r * fine.vertices).colwise() + t;
      const Eigen::Matrix3Xd vertices = skin.DeformedVertices(moved_nodes);
      // Relative error: against the size of the moved coordinates (radius 1, offsets ~10).
      EXPECT_LE(
          (vertices - expected).colwise().norm().maxCoeff() / expected.colwise().norm().maxCoeff(),
          1e-9);
      const Eigen::Matrix3Xd normals = skin.DeformedNormals(vertices);
      const Eigen::Matrix3Xd rest_normals = skin.DeformedNormals(fine.vertices);
      // Normals of the fine surface's small triangles amplify rounding by ~1 / edge length.
      EXPECT_LE((normals - r * rest_normals).cwiseAbs().maxCoeff(), 1e-8);
    }
  }
}

TEST(SurfaceSkin, VerticesStayInsideTheirDeformedHostCells) {
  const TriangleMesh fine = MakeIcosphereMesh(1.0, 4);
  for (const Model& model : SphereModels()) {
    const SurfaceSkin skin = SurfaceSkin::Embed(model, fine);
    // A large non-affine deformation: twist about z, bend about y, and a squash.
    Eigen::Matrix3Xd nodes = model.rest_positions();
    for (int i = 0; i < nodes.cols(); ++i) {
      const Eigen::Vector3d p = nodes.col(i);
      const double twist = 0.4 * p.z();
      Eigen::Vector3d q(std::cos(twist) * p.x() - std::sin(twist) * p.y(),
                        std::sin(twist) * p.x() + std::cos(twist) * p.y(), 0.8 * p.z());
      q.x() += 0.2 * q.z() * q.z();
      nodes.col(i) = q;
    }
    const Eigen::Matrix3Xd corners = skin.CornerPositions(nodes);
    const Eigen::Matrix3Xd vertices = skin.DeformedVertices(nodes);
    for (int v = 0; v < skin.num_vertices(); ++v) {
      std::array<Eigen::Vector3d, 8> cell;
      for (int k = 0; k < 8; ++k) cell[k] = corners.col(skin.host_corners()[v][k]);
      const Eigen::Vector3d u = InvertTrilinear(cell, vertices.col(v));
      ASSERT_TRUE(u.allFinite()) << "vertex " << v;
      EXPECT_TRUE((u.array() >= -1e-9).all() && (u.array() <= 1.0 + 1e-9).all())
          << "vertex " << v << " at " << u.transpose();
      EXPECT_LT((u - skin.cell_coordinates().col(v)).norm(), 1e-9);
    }
    // And the deformation did move the skin (the test would be empty otherwise).
    EXPECT_GT((vertices - fine.vertices).colwise().norm().maxCoeff(), 0.1);
  }
}

TEST(SurfaceSkin, RefusesASurfaceFarFromTheModel) {
  const Model model = SphereModels().front();
  TriangleMesh far = MakeIcosphereMesh(1.0, 1);
  far.vertices.colwise() += Eigen::Vector3d(50, 0, 0);
  EXPECT_THROW(SurfaceSkin::Embed(model, far), std::invalid_argument);
  EXPECT_THROW(SurfaceSkin::Embed(model, TriangleMesh{}), std::invalid_argument);
  const SurfaceSkin skin = SurfaceSkin::Embed(model, MakeIcosphereMesh(1.0, 1));
  EXPECT_THROW(skin.DeformedVertices(Eigen::Matrix3Xd::Zero(3, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
