// The strain of a deformed surface per vertex (the colouring of the ROS markers), against values
// worked out by hand.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/geometry/surface_strain.h"

namespace msm_sim::core {
namespace {

TriangleMesh Triangle() {
  TriangleMesh mesh;
  mesh.vertices.resize(3, 3);
  mesh.vertices << 0.0, 1.0, 0.2,  //
      0.0, 0.0, 0.8,               //
      0.0, 0.0, 0.3;
  mesh.triangles.resize(3, 1);
  mesh.triangles << 0, 1, 2;
  return mesh;
}

// The unit square in the xy plane as two triangles sharing the diagonal 0-2.
TriangleMesh Square() {
  TriangleMesh mesh;
  mesh.vertices.resize(3, 4);
  mesh.vertices << 0.0, 1.0, 1.0, 0.0,  //
      0.0, 0.0, 1.0, 1.0,               //
      0.0, 0.0, 0.0, 0.0;
  mesh.triangles.resize(3, 2);
  mesh.triangles << 0, 0,  //
      1, 2,                //
      2, 3;
  return mesh;
}

TEST(SurfaceStrain, AtRestIsZero) {
  const TriangleMesh square = Square();
  const Eigen::VectorXd strain = SurfaceStrain(square).VertexStrains(square.vertices);
  ASSERT_EQ(strain.size(), 4);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(strain[v], 0.0) << v;
}

TEST(SurfaceStrain, UniformStretchAndCompressionAreTheScaleChange) {
  const TriangleMesh triangle = Triangle();
  const SurfaceStrain strain(triangle);
  EXPECT_EQ(strain.num_vertices(), 3);
  const Eigen::Vector3d shift(0.5, -2.0, 1.0);  // a translation changes nothing
  const Eigen::VectorXd stretched =
      strain.VertexStrains((1.1 * triangle.vertices).colwise() + shift);
  const Eigen::VectorXd compressed = strain.VertexStrains(0.9 * triangle.vertices);
  for (int v = 0; v < 3; ++v) {
    EXPECT_NEAR(stretched[v], 0.1, 1e-12) << v;
    EXPECT_NEAR(compressed[v], -0.1, 1e-12) << v;
  }
}

// Stretched 10 % along x: the horizontal edges strain 0.1, the vertical ones 0, the diagonal
// sqrt(1.1^2 + 1) / sqrt(2) - 1. Each triangle counts its own edges, so the shared diagonal
// counts twice at vertices 0 and 2.
TEST(SurfaceStrain, IsTheMeanOverTheTrianglesEdgesAtAVertex) {
  const TriangleMesh square = Square();
  Eigen::Matrix3Xd stretched = square.vertices;
  stretched.row(0) *= 1.1;
  const Eigen::VectorXd strain = SurfaceStrain(square).VertexStrains(stretched);
  const double diagonal = std::sqrt(1.21 + 1.0) / std::sqrt(2.0) - 1.0;
  EXPECT_NEAR(strain[0], (0.1 + 2.0 * diagonal + 0.0) / 4.0, 1e-12);
  EXPECT_NEAR(strain[1], (0.1 + 0.0) / 2.0, 1e-12);
  EXPECT_NEAR(strain[2], (0.0 + 2.0 * diagonal + 0.1) / 4.0, 1e-12);
  EXPECT_NEAR(strain[3], (0.1 + 0.0) / 2.0, 1e-12);
}

// An edge of zero rest length has no strain and is left out; a vertex of no triangle gets 0.
TEST(SurfaceStrain, SkipsZeroLengthEdgesAndUnusedVertices) {
  TriangleMesh mesh;
  mesh.vertices.resize(3, 4);
  mesh.vertices << 0.0, 0.0, 1.0, 5.0,  //
      0.0, 0.0, 0.0, 5.0,               //
      0.0, 0.0, 0.0, 5.0;
  mesh.triangles.resize(3, 1);
  mesh.triangles << 0, 1, 2;
  Eigen::Matrix3Xd deformed = mesh.vertices;
  deformed(0, 2) = 1.2;  // both edges to vertex 2 stretch 20 %
  deformed(0, 3) = 7.0;  // moving an unused vertex changes nothing
  const Eigen::VectorXd strain = SurfaceStrain(mesh).VertexStrains(deformed);
  EXPECT_NEAR(strain[0], 0.2, 1e-12);
  EXPECT_NEAR(strain[1], 0.2, 1e-12);
  EXPECT_NEAR(strain[2], 0.2, 1e-12);
  EXPECT_EQ(strain[3], 0.0);
}

TEST(SurfaceStrain, RejectsVerticesOfAnotherSurface) {
  const SurfaceStrain strain(Square());
  EXPECT_THROW(strain.VertexStrains(Eigen::Matrix3Xd::Zero(3, 3)), std::invalid_argument);
  EXPECT_EQ(SurfaceStrain().VertexStrains(Eigen::Matrix3Xd(3, 0)).size(), 0);
}

}  // namespace
}  // namespace msm_sim::core
