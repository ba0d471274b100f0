// Unit tests of the collision geometry: the collider shapes' signed distances and the border
// nodes' collision spheres.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/collider.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"

namespace msm_sim::core {
namespace {

void ExpectDistance(const ColliderShape& shape, const Eigen::Vector3d& p, double distance,
                    const Eigen::Vector3d& normal) {
  Eigen::Vector3d n, closest;
  EXPECT_NEAR(shape.SignedDistance(p, &n, &closest), distance, 1e-12) << p.transpose();
  EXPECT_LT((n - normal).norm(), 1e-12) << p.transpose() << " normal " << n.transpose();
  // The closest point lies at the signed distance back along the normal.
  EXPECT_LT((closest + distance * n - p).norm(), 1e-12) << p.transpose();
}

TEST(ColliderShape, SignedDistancesOfThePrimitives) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), z = Eigen::Vector3d::UnitZ();
  ExpectDistance(ColliderShape::Plane(), Eigen::Vector3d(3, 4, 0.2), 0.2, z);
  ExpectDistance(ColliderShape::Plane(), Eigen::Vector3d(3, 4, -0.2), -0.2, z);
  const ColliderShape box = ColliderShape::Box(Eigen::Vector3d(2, 2, 2));
  ExpectDistance(box, Eigen::Vector3d(1.5, 0, 0), 0.5, x);
  ExpectDistance(box, Eigen::Vector3d(0.9, 0.2, 0.1), -0.1, x);
  ExpectDistance(box, Eigen::Vector3d(2, 2, 0), std::sqrt(2.0),
                 Eigen::Vector3d(1, 1, 0).normalized());
  ExpectDistance(ColliderShape::Sphere(0.5), Eigen::Vector3d(0, 0, 2), 1.5, z);
  ExpectDistance(ColliderShape::Sphere(0.5), Eigen::Vector3d(0.3, 0, 0), -0.2, x);
  const ColliderShape capsule = ColliderShape::Capsule(0.1, 1.0);
  ExpectDistance(capsule, Eigen::Vector3d(0.3, 0, 0.2), 0.2, x);
  ExpectDistance(capsule, Eigen::Vector3d(0, 0, 0.8), 0.2, z);
  const ColliderShape cylinder = ColliderShape::Cylinder(0.5, 1.0);
  ExpectDistance(cylinder, Eigen::Vector3d(1, 0, 0.1), 0.5, x);
  ExpectDistance(cylinder, Eigen::Vector3d(0.1, 0, 0.9), 0.4, z);
  ExpectDistance(cylinder, Eigen::Vector3d(0.1, 0, 0.45), -0.05, z);
  ExpectDistance(cylinder, Eigen::Vector3d(0.4, 0, 0), -0.1, x);
  EXPECT_THROW(ColliderShape::Sphere(0.0), std::invalid_argument);
  EXPECT_THROW(ColliderShape::Box(Eigen::Vector3d(1, std::nan(""), 1)), std::invalid_argument);
}

TEST(ColliderShape, MeshColliderMatchesTheSphereItApproximates) {
  const auto mesh = std::make_shared<const SolidMesh>(MakeIcosphereMesh(1.0, 5));
  const ColliderShape shape = ColliderShape::Mesh(mesh);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 1.3), Eigen::Vector3d(0.5, -0.4, 0.2),
                                   Eigen::Vector3d(-1.1, 0.6, 0.3)}) {
    Eigen::Vector3d n, closest;
    const double d = shape.SignedDistance(p, &n, &closest);
    EXPECT_NEAR(d, p.norm() - 1.0, 2e-3) << p.transpose();
    EXPECT_GT(n.dot(p.normalized()), 0.999);
  }
}

TEST(BorderNodes, SurfaceOfACubicLatticeWithMeanHalfSpringRadii) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(0.4);
  lattice_options.lattice.spacing = 0.1;  // 4 x 4 x 4 nodes, 8 inside
  const Model model =
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.25, 1000.0), lattice_options);
  const BorderNodes border = FindBorderNodes(model);
  EXPECT_EQ(border.nodes.size(), 56u);
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    EXPECT_GT(border.radii[k], 0.05);                        // half the A spring
    EXPECT_LT(border.radii[k], 0.5 * std::sqrt(2.0) * 0.1);  // half the B spring
  }
}

// A lattice cut by a curved surface: the collision spheres follow the surface (docs/physics.md
// §7). A cut cell's sphere ends as far past the surface as a whole cell's past its face: its
// mean half-spring less a / 2, at most half a face diagonal less a / 2 (plus the icosphere's
// facets). A sliver whose centre lies outside the surface keeps the floor sphere, and only such
// a node: the floor applies where the centre is less than kSliverRadius a inside.
TEST(BorderNodes, SpheresOfACutLatticeFollowTheSurface) {
  const double radius = 1.0, a = 0.1;
  MeshCubicLatticeOptions options;
  options.lattice.spacing = a;
  const Model model = BuildCubicLatticeInSolid(Material::FromYoungsPoisson(1e5, 0.3, 1000.0),
                                               SolidMesh(MakeIcosphereMesh(radius, 4)), options);
  const BorderNodes border = FindBorderNodes(model);
  ASSERT_GT(border.nodes.size(), 100u);
  double farthest = -1.0;
  int floored = 0;
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    ASSERT_GE(border.radii[k], kSliverRadius * a * (1.0 - 1e-12));
    const double outside = model.rest_positions().col(border.nodes[k]).norm() - radius;
    if (border.radii[k] <= kSliverRadius * a * (1.0 + 1e-12)) {
      ++floored;
      EXPECT_GT(outside, -(kSliverRadius + 0.01) * a);
      continue;
    }
    farthest = std::max(farthest, outside + border.radii[k]);
  }
  std::printf("  farthest sphere above the floor past the surface: %.3f a; %d floor spheres\n",
              farthest / a, floored);
  EXPECT_LT(farthest, (0.5 * std::sqrt(2.0) - 0.5 + 0.01) * a);
  EXPECT_GT(farthest, 0.0);
  EXPECT_GT(floored, 0);
  // Whole cells keep their radii: an aligned box has no insets.
  CubicLatticeOptions box;
  box.size = Eigen::Vector3d::Constant(0.4);
  box.lattice.spacing = 0.1;
  EXPECT_EQ(BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.25, 1000.0), box)
                .surface_insets()
                .maxCoeff(),
            0.0);
}

// A sphere lowered onto a hand-made border touches the collision sphere it meets first.
TEST(BorderNodes, SphereTouchdownHeightIsWhereTheSphereFirstTouches) {
  Eigen::Matrix3Xd x(3, 2);
  x << 0.0, 0.3, 0.0, 0.0, 1.0, 1.1;  // two nodes: (0, 0, 1) and (0.3, 0, 1.1)
  BorderNodes border;
  border.nodes = {0, 1};
  border.radii = {0.1, 0.1};
  // Right above node 0, radius 0.5: reaches node 1 (0.3 aside) at 1.1 + sqrt(0.6^2 - 0.3^2).
  EXPECT_NEAR(SphereTouchdownHeight(x, border, Eigen::Vector2d(0, 0), 0.5),
              1.1 + std::sqrt(0.36 - 0.09), 1e-12);
  // A small sphere above node 0 misses node 1: touches node 0's sphere at 1 + 0.1 + 0.05.
  EXPECT_NEAR(SphereTouchdownHeight(x, border, Eigen::Vector2d(0, 0), 0.05), 1.15, 1e-12);
  EXPECT_EQ(SphereTouchdownHeight(x, border, Eigen::Vector2d(5, 0), 0.5),
            -std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace msm_sim::core
