// Triangle meshes, closed solids and the assimp importer (issue: any mesh in).
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::core {
namespace {

const std::string kMeshDir = std::string(MSM_SIM_TEST_DATA_DIR) + "/meshes/";

TEST(MeshPrimitives, EncloseTheirAnalyticVolumes) {
  EXPECT_NEAR(SignedVolume(MakeBoxMesh(Eigen::Vector3d(1, 2, 3))), 6.0, 1e-12);
  // Inscribed polyhedra fall short of the smooth solid by O(h^2).
  EXPECT_NEAR(SignedVolume(MakeIcosphereMesh(1.0, 5)) / (4.0 / 3.0 * M_PI), 1.0, 2e-3);
  EXPECT_NEAR(SignedVolume(MakeCylinderMesh(0.5, 2.0, 256)) / (M_PI * 0.25 * 2.0), 1.0, 2e-3);
  EXPECT_NEAR(SignedVolume(MakeTorusMesh(1.0, 0.3, 256, 64)) / (2 * M_PI * M_PI * 0.09), 1.0, 3e-3);
  for (const TriangleMesh& mesh : {MakeBoxMesh(Eigen::Vector3d::Ones()), MakeIcosphereMesh(1, 2),
                                   MakeCylinderMesh(1, 1, 8), MakeTorusMesh(2, 1, 8, 6)}) {
    const MeshTopology topology = AnalyzeTopology(mesh);
    EXPECT_TRUE(topology.closed());
    EXPECT_EQ(topology.non_manifold_edges, 0);
    EXPECT_EQ(topology.degenerate_triangles, 0);
  }
}

TEST(MeshPrimitives, RejectBadDimensions) {
  EXPECT_THROW(MakeBoxMesh(Eigen::Vector3d(1, 0, 1)), std::invalid_argument);
  EXPECT_THROW(MakeIcosphereMesh(-1, 2), std::invalid_argument);
  EXPECT_THROW(MakeIcosphereMesh(1, 9), std::invalid_argument);
  EXPECT_THROW(MakeCylinderMesh(1, 1, 2), std::invalid_argument);
  EXPECT_THROW(MakeTorusMesh(1, 1, 8, 8), std::invalid_argument);
}

TEST(TriangleMesh, CountsHolesAndWeldsSeparateCorners) {
  TriangleMesh box = MakeBoxMesh(Eigen::Vector3d::Ones());
  // One vertex per triangle corner, as in STL: nothing is shared until welded.
  TriangleMesh soup;
  soup.vertices.resize(3, 3 * box.num_triangles());
  soup.triangles.resize(3, box.num_triangles());
  for (int t = 0; t < box.num_triangles(); ++t) {
    for (int e = 0; e < 3; ++e) {
      soup.vertices.col(3 * t + e) = box.vertices.col(box.triangles(e, t)) * (1.0 + 1e-12 * e);
      soup.triangles(e, t) = 3 * t + e;
    }
  }
  EXPECT_EQ(AnalyzeTopology(soup).boundary_edges, 36);
  const TriangleMesh welded = WeldVertices(soup, 1e-9);
  EXPECT_EQ(welded.num_vertices(), 8);
  EXPECT_TRUE(AnalyzeTopology(welded).closed());

  TriangleMesh open = box;
  open.triangles = box.triangles.rightCols(10);  // drop the two triangles of one face
  EXPECT_EQ(AnalyzeTopology(open).boundary_edges, 4);
  EXPECT_FALSE(AnalyzeTopology(open).closed());
}

TEST(TriangleMesh, CrossSectionAreaOfBoxCylinderAndTorus) {
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(CrossSectionArea(box, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 6.0, 1e-12);
  EXPECT_NEAR(CrossSectionArea(box, Eigen::Vector3d(0, 0, 1.2), Eigen::Vector3d::UnitZ()), 2.0,
              1e-12);
  EXPECT_NEAR(CrossSectionArea(box, Eigen::Vector3d(0, 0, 2.0), Eigen::Vector3d::UnitZ()), 0.0,
              1e-12);
  const TriangleMesh cylinder = MakeCylinderMesh(0.5, 2.0, 512);
  EXPECT_NEAR(CrossSectionArea(cylinder, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()),
              M_PI * 0.25, 1e-4);
  // Through the torus axis: two discs of the tube radius.
  const TriangleMesh torus = MakeTorusMesh(1.0, 0.3, 512, 128);
  EXPECT_NEAR(CrossSectionArea(torus, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()),
              2 * M_PI * 0.09, 2e-3);
}

TEST(SolidMesh, InsideTestMatchesTheSphereAwayFromItsSurface) {
  const SolidMesh sphere(MakeIcosphereMesh(1.0, 4));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coordinate(-1.3, 1.3);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    // The icosphere lies between radius 0.9985 and 1.
    if (std::abs(p.norm() - 0.999) < 0.003) continue;
    EXPECT_EQ(sphere.Contains(p), p.norm() < 0.999) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 19000);
  EXPECT_GT(sphere.volume(), 0.99 * 4.0 / 3.0 * M_PI);
}

TEST(SolidMesh, ExactOnLatticeAlignedFacesEdgesAndVertices) {
  // Rays from points level with faces, edges and vertices of an axis-aligned box graze them;
  // the exact predicates must still classify every lattice point right.
  const SolidMesh box(MakeBoxMesh(Eigen::Vector3d(2, 2, 2)));
  for (int i = -3; i <= 3; ++i) {
    for (int j = -3; j <= 3; ++j) {
      for (int k = -3; k <= 3; ++k) {
        const Eigen::Vector3d p = 0.5 * Eigen::Vector3d(i, j, k);
        const bool inside = (p.array().abs() <= 1.0).all();
        EXPECT_EQ(box.Contains(p), inside) << p.transpose();
      }
    }
  }
}

TEST(SolidMesh, OrientsInwardFacingAndMixedTriangles) {
  TriangleMesh mesh = MakeIcosphereMesh(1.0, 2);
  for (int t = 0; t < mesh.num_triangles(); t += 3) {
    std::swap(mesh.triangles(1, t), mesh.triangles(2, t));  // flip every third triangle
  }
  const SolidMesh solid(mesh);
  EXPECT_NEAR(solid.volume(), SignedVolume(MakeIcosphereMesh(1.0, 2)), 1e-12);
  EXPECT_NEAR(SignedVolume(solid.surface()), solid.volume(), 1e-12);
}

TEST(SolidMesh, TwoCubesSharingAnEdgeAreClosedThoughNotManifold) {
  TriangleMesh a = MakeBoxMesh(Eigen::Vector3d::Ones());
  TriangleMesh both;
  both.vertices.resize(3, 16);
  both.vertices << a.vertices, (a.vertices.colwise() + Eigen::Vector3d(1, 1, 0));
  both.triangles.resize(3, 24);
  both.triangles << a.triangles, (a.triangles.array() + 8).matrix();
  both = WeldVertices(both, 1e-12);
  const MeshTopology topology = AnalyzeTopology(both);
  EXPECT_GT(topology.non_manifold_edges, 0);
  EXPECT_TRUE(topology.closed());
  const SolidMesh solid(both);
  EXPECT_NEAR(solid.volume(), 2.0, 1e-12);
  EXPECT_TRUE(solid.Contains(Eigen::Vector3d(1.2, 1.2, 0.1)));
  EXPECT_FALSE(solid.Contains(Eigen::Vector3d(1.2, -0.2, 0.1)));
}

TEST(SolidMesh, RefusesOpenAndFlatSurfacesWithAClearMessage) {
  TriangleMesh open = MakeBoxMesh(Eigen::Vector3d::Ones());
  open.triangles = open.triangles.rightCols(10).eval();
  try {
    SolidMesh solid(open);
    FAIL() << "an open surface was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("open: 4 boundary edges"), std::string::npos) << e.what();
  }
  TriangleMesh flat = MakeBoxMesh(Eigen::Vector3d(1, 1, 1));
  flat.vertices.row(2).setZero();
  EXPECT_THROW(SolidMesh{flat}, std::invalid_argument);
  EXPECT_THROW(SolidMesh{TriangleMesh{}}, std::invalid_argument);
}

TEST(SolidMesh, BoxAndSegmentQueries) {
  const SolidMesh box(MakeBoxMesh(Eigen::Vector3d(2, 2, 2)));
  EXPECT_TRUE(
      box.BoxTouchesSurface(Eigen::Vector3d(0.9, -0.1, -0.1), Eigen::Vector3d(1.1, 0.1, 0.1)));
  EXPECT_FALSE(
      box.BoxTouchesSurface(Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5)));
  EXPECT_TRUE(box.SegmentCrossesSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 0, 0)));
  EXPECT_FALSE(box.SegmentCrossesSurface(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.5, 0)));
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const SolidMesh moved = TransformedSolid(box, r, Eigen::Vector3d(5, 0, 0));
  EXPECT_NEAR(moved.volume(), 8.0, 1e-12);
  EXPECT_TRUE(moved.Contains(Eigen::Vector3d(5, 0, 0) + r * Eigen::Vector3d(0.9, 0.9, 0.9)));
  EXPECT_FALSE(moved.Contains(Eigen::Vector3d(5, 0, 0) + r * Eigen::Vector3d(1.1, 0.9, 0.9)));
}

TEST(MeshImport, ReadsAClosedMeshWithScaleAndWelding) {
  MeshImportOptions options;
  options.scale = 0.001;  // the file is in millimetres
  const ImportedMesh imported = ImportTriangleMesh(kMeshDir + "cube_100mm.stl", options);
  EXPECT_EQ(imported.mesh.num_triangles(), 12);
  EXPECT_EQ(imported.mesh.num_vertices(), 8);  // 36 STL corners welded to 8
  EXPECT_TRUE(imported.topology.closed());
  EXPECT_NEAR(SolidMesh(imported.mesh).volume(), 1e-3, 1e-15);
  EXPECT_NEAR(SolidMesh(ImportTriangleMesh(kMeshDir + "tetrahedron.off").mesh).volume(), 1.0 / 6,
              1e-15);
}

TEST(MeshImport, MergesEveryInstanceWithItsNodeTransform) {
  // glTF: one tetrahedron instanced by two nodes, the second translated by 2 m along x.
  const ImportedMesh imported = ImportTriangleMesh(kMeshDir + "two_tetrahedra.gltf");
  EXPECT_EQ(imported.mesh.num_triangles(), 8);
  Eigen::Vector3d lo, hi;
  BoundingBox(imported.mesh, &lo, &hi);
  EXPECT_NEAR(hi.x() - lo.x(), 3.0, 1e-6);
  const SolidMesh solid(imported.mesh);
  EXPECT_NEAR(solid.volume(), 2.0 / 6.0, 1e-6);
  EXPECT_TRUE(solid.Contains(Eigen::Vector3d(2.1, 0.1, 0.1)));
  EXPECT_FALSE(solid.Contains(Eigen::Vector3d(1.5, 0.1, 0.1)));
}

TEST(MeshImport, OpenSurfaceImportsButIsNoSolid) {
  const ImportedMesh imported = ImportTriangleMesh(kMeshDir + "open_box.obj");
  EXPECT_EQ(imported.topology.boundary_edges, 4);
  EXPECT_THROW(SolidMesh{imported.mesh}, std::invalid_argument);
}

// Each broken file gives one line that names the file and says what is wrong.
void ExpectImportError(const std::string& file, const std::string& expected,
                       const MeshImportOptions& options = {}) {
  try {
    ImportTriangleMesh(kMeshDir + file, options);
    ADD_FAILURE() << file << " was accepted";
  } catch (const MeshImportError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file), std::string::npos) << message;
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(MeshImport, BrokenFilesGiveOneClearLine) {
  ExpectImportError("no_such_file.stl", "no such file");
  ExpectImportError("empty.stl", "empty");
  ExpectImportError("garbage.obj", "cannot be read as a mesh");
  ExpectImportError("truncated_binary.stl", "declares 1000 triangles, so 50084 bytes");
  ExpectImportError("lines_only.obj", "cannot be read as a mesh");
  ExpectImportError("nan_vertex.obj", "not finite");
  ExpectImportError("huge.obj", "give the right scale");
  MeshImportOptions bad_scale;
  bad_scale.scale = -1.0;
  ExpectImportError("tetrahedron.off", "scale must be", bad_scale);
  ExpectImportError("", "is a directory");  // the directory itself
}

}  // namespace
}  // namespace msm_sim::core
