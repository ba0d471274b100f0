// Exact clipping of a closed solid to axis-aligned boxes (VolumeInsideBox), against volumes
// worked out by hand: a unit cube, a corner tetrahedron and a sphere.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "geometry/box_clipping.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::core {
namespace {

// The result may be off by the 1e-9 inward shift of the box's +x face and +y edge (relative to
// the box), times the areas and lengths involved: a few 1e-9 for the boxes here.
constexpr double kShiftTolerance = 1e-8;

// The unit cube [-0.5, 0.5]^3.
SolidMesh UnitCube() { return SolidMesh(MakeBoxMesh(Eigen::Vector3d::Ones())); }

// The tetrahedron with corners at the origin and at the three unit points, volume 1/6.
SolidMesh CornerTetrahedron() {
  TriangleMesh mesh;
  mesh.vertices.resize(3, 4);
  mesh.vertices << 0, 1, 0, 0,  //
      0, 0, 1, 0,               //
      0, 0, 0, 1;
  mesh.triangles.resize(3, 4);
  mesh.triangles << 0, 0, 0, 1,  //
      2, 1, 3, 2,                //
      1, 3, 2, 3;
  return SolidMesh(mesh);
}

double Volume(const SolidMesh& solid, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return VolumeInsideBox(solid, lo, hi);
}

TEST(BoxClipping, UnitCubeInsideOrOutsideABox) {
  const SolidMesh cube = UnitCube();
  // A box containing the whole cube.
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1)), 1.0,
              kShiftTolerance);
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(-0.7, -2, -0.6), Eigen::Vector3d(3, 0.9, 0.51)), 1.0,
              kShiftTolerance);
  // Boxes that miss it, far away and just beside a face.
  EXPECT_EQ(Volume(cube, Eigen::Vector3d::Constant(2), Eigen::Vector3d::Constant(3)), 0.0);
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(0.51, -1, -1), Eigen::Vector3d(1, 1, 1)), 0.0,
              kShiftTolerance);
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, -0.6, 1)), 0.0,
              kShiftTolerance);
  // A box inside the cube, touching no face: all of it.
  EXPECT_DOUBLE_EQ(Volume(cube, Eigen::Vector3d(-0.25, -0.1, 0.0), Eigen::Vector3d(0.25, 0.3, 0.2)),
                   0.5 * 0.4 * 0.2);
}

TEST(BoxClipping, UnitCubeCutInHalvesAndCorners) {
  const SolidMesh cube = UnitCube();
  // Halves across each axis: the +x face of the first box cuts the cube (face area term), the
  // others cut it with their -y and +z faces.
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(0, 1, 1)), 0.5,
              kShiftTolerance);
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(1, 1, 1)), 0.5,
              kShiftTolerance);
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 0)), 0.5,
              kShiftTolerance);
  // All eight corners, 1/8 each; the box's +x face and +y edge cross the cube for the corners
  // at -x and -y.
  double sum = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    Eigen::Vector3d lo, hi;
    for (int axis = 0; axis < 3; ++axis) {
      const bool upper = (corner >> axis) & 1;
      lo[axis] = upper ? 0.0 : -1.0;
      hi[axis] = upper ? 1.0 : 0.0;
    }
    const double volume = Volume(cube, lo, hi);
    EXPECT_NEAR(volume, 0.125, kShiftTolerance) << "corner " << corner;
    sum += volume;
  }
  EXPECT_NEAR(sum, 1.0, 8 * kShiftTolerance);
  // An off-centre slab: x in [-0.5, 0.2], y in [0.1, 0.5], all z.
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d(-2, 0.1, -2), Eigen::Vector3d(0.2, 2, 2)),
              0.7 * 0.4 * 1.0, kShiftTolerance);
}

TEST(BoxClipping, BoxFacesOnTheSurfaceAreOnADefiniteSide) {
  const SolidMesh cube = UnitCube();
  // The box is the cube itself.
  EXPECT_NEAR(Volume(cube, Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5)), 1.0,
              kShiftTolerance);
  // Lattice cells of edge 0.25 aligned with the cube's faces: each is all in or all out.
  const double h = 0.25;
  double sum = 0.0;
  for (int i = -3; i < 3; ++i) {
    for (int j = -3; j < 3; ++j) {
      for (int k = -3; k < 3; ++k) {
        const Eigen::Vector3d lo = h * Eigen::Vector3d(i, j, k);
        const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(h);
        const bool inside = i >= -2 && i < 2 && j >= -2 && j < 2 && k >= -2 && k < 2;
        const double volume = Volume(cube, lo, hi);
        EXPECT_NEAR(volume, inside ? h * h * h : 0.0, 1e-8 * h * h * h)
            << "cell " << i << ' ' << j << ' ' << k;
        sum += volume;
      }
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-8);
}

TEST(BoxClipping, TetrahedronCutByHalfBoxes) {
  const SolidMesh tetrahedron = CornerTetrahedron();
  const Eigen::Vector3d far_lo = Eigen::Vector3d::Constant(-1);
  const Eigen::Vector3d far_hi = Eigen::Vector3d::Constant(2);
  EXPECT_NEAR(Volume(tetrahedron, far_lo, far_hi), 1.0 / 6.0, kShiftTolerance);
  for (const double t : {0.2, 0.5, 0.75}) {
    // The part beyond the plane x_axis = t is the tetrahedron scaled by 1 - t about the corner
    // on that axis: (1 - t)^3 / 6.
    const double tip = std::pow(1.0 - t, 3) / 6.0;
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d below_hi = far_hi, above_lo = far_lo;
      below_hi[axis] = t;
      above_lo[axis] = t;
      EXPECT_NEAR(Volume(tetrahedron, far_lo, below_hi), 1.0 / 6.0 - tip, kShiftTolerance)
          << "t " << t << " axis " << axis;
      EXPECT_NEAR(Volume(tetrahedron, above_lo, far_hi), tip, kShiftTolerance)
          << "t " << t << " axis " << axis;
    }
  }
}

TEST(BoxClipping, TetrahedronCutByCornerBoxes) {
  const SolidMesh tetrahedron = CornerTetrahedron();
  const Eigen::Vector3d lo = Eigen::Vector3d::Constant(-1);
  // [0, 0.3]^3 lies inside (x + y + z <= 0.9).
  EXPECT_NEAR(Volume(tetrahedron, lo, Eigen::Vector3d::Constant(0.3)), 0.027, kShiftTolerance);
  // [0, 0.5]^3 loses the corner x + y + z > 1, a tetrahedron of legs 0.5: 1/8 - 1/48.
  EXPECT_NEAR(Volume(tetrahedron, lo, Eigen::Vector3d::Constant(0.5)), 5.0 / 48.0, kShiftTolerance);
  // A box around the far corner (1, 0, 0): x >= 0.6 is the tip of legs 0.4.
  EXPECT_NEAR(Volume(tetrahedron, Eigen::Vector3d(0.6, -1, -1), Eigen::Vector3d(2, 1, 1)),
              std::pow(0.4, 3) / 6.0, kShiftTolerance);
}

TEST(BoxClipping, SphereHalvesCapsAndAPartition) {
  const double radius = 1.0;
  const SolidMesh sphere(MakeIcosphereMesh(radius, 5));
  // The icosphere is symmetric under x -> -x and z -> -z, so each half holds exactly half of
  // the polyhedron; within its O(h^2) deficit, that is the half ball 2/3 pi r^3.
  const double half = 0.5 * sphere.volume();
  const Eigen::Vector3d far = Eigen::Vector3d::Constant(2.0);
  EXPECT_NEAR(Volume(sphere, -far, Eigen::Vector3d(0, 2, 2)), half, 1e-7);
  EXPECT_NEAR(Volume(sphere, Eigen::Vector3d(0, -2, -2), far), half, 1e-7);
  EXPECT_NEAR(Volume(sphere, -far, Eigen::Vector3d(2, 2, 0)), half, 1e-7);
  EXPECT_NEAR(half / (2.0 / 3.0 * M_PI * std::pow(radius, 3)), 1.0, 2e-3);
  // A cap of height 0.5: pi h^2 (3 r - h) / 3.
  const double h = 0.5;
  EXPECT_NEAR(Volume(sphere, Eigen::Vector3d(-2, -2, radius - h), far) /
                  (M_PI * h * h * (3 * radius - h) / 3.0),
              1.0, 5e-3);

  // Cells of a grid off the mesh's vertices partition the solid: their volumes add up to it.
  const double cell = 0.3;
  const Eigen::Vector3d origin = Eigen::Vector3d(-1.17, -1.21, -1.13);
  double sum = 0.0;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 9; ++j) {
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d lo = origin + cell * Eigen::Vector3d(i, j, k);
        const double volume = Volume(sphere, lo, lo + Eigen::Vector3d::Constant(cell));
        EXPECT_GE(volume, -1e-12);
        EXPECT_LE(volume, cell * cell * cell * (1 + 1e-12));
        sum += volume;
      }
    }
  }
  EXPECT_NEAR(sum, sphere.volume(), 1e-7);
}

}  // namespace
}  // namespace msm_sim::core
