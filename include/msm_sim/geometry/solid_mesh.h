#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::core {

/// A closed triangle surface seen as the solid it bounds: volume, bounding box and robust
/// point-inside, box-touches-surface and segment-crosses-surface queries.
///
/// The queries use CGAL's AABB tree and Side_of_triangle_mesh (ray parity with exact predicates,
/// re-shooting when a ray grazes an edge or a vertex), so they are exact for any closed surface,
/// however the lattice happens to align with its faces. Immutable after construction; the queries
/// are const and cheap (a tree search, not a pass over the triangles; docs/meshes.md).
class SolidMesh {
 public:
  /// Orients the triangles consistently and outwards. Throws std::invalid_argument with a
  /// message saying what to fix if the mesh has no triangles, non-finite vertices, boundary edges
  /// (an open surface: the message counts them), non-manifold edges that leave it without a
  /// well-defined inside, or no enclosed volume. Precondition: vertices welded (WeldVertices).
  explicit SolidMesh(const TriangleMesh& mesh);
  ~SolidMesh();
  SolidMesh(SolidMesh&&) noexcept;
  SolidMesh& operator=(SolidMesh&&) noexcept;
  SolidMesh(const SolidMesh&) = delete;
  SolidMesh& operator=(const SolidMesh&) = delete;

  /// The outward-oriented surface.
  const TriangleMesh& surface() const;
  /// Enclosed volume (m^3), > 0.
  double volume() const;
  const Eigen::Vector3d& min_corner() const;
  const Eigen::Vector3d& max_corner() const;

  /// True if p is inside the solid or on its surface.
  bool Contains(const Eigen::Vector3d& p) const;
  /// True if the axis-aligned box [lo, hi] intersects the surface (not merely lies inside it).
  bool BoxTouchesSurface(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
  /// True if the segment [a, b] intersects the surface.
  bool SegmentCrossesSurface(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  /// The surface point closest to p; *triangle (optional) receives its triangle's index.
  Eigen::Vector3d ClosestPoint(const Eigen::Vector3d& p, int* triangle) const;
  /// Indices (into surface().triangles) of the triangles intersecting the box [lo, hi].
  std::vector<int> TrianglesTouchingBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The same solid rigidly moved: p -> rotation p + translation. Precondition: rotation is a
/// rotation matrix.
SolidMesh TransformedSolid(const SolidMesh& solid, const Eigen::Matrix3d& rotation,
                           const Eigen::Vector3d& translation);

}  // namespace msm_sim::core
