#pragma once

#include <Eigen/Core>

namespace msm_sim::core {

/// An indexed triangle mesh: the boundary of a body or a visual surface (SI units, m).
///
/// Plain data; the functions below analyse it. Triangles are counter-clockwise seen from outside
/// for a consistently oriented closed surface, but nothing here relies on it except SignedVolume.
struct TriangleMesh {
  Eigen::Matrix3Xd vertices;   ///< one column per vertex
  Eigen::Matrix3Xi triangles;  ///< one column per triangle, indices into vertices

  int num_vertices() const { return static_cast<int>(vertices.cols()); }
  int num_triangles() const { return static_cast<int>(triangles.cols()); }
};

/// What is wrong (or not) with a mesh as the boundary of a solid.
struct MeshTopology {
  int boundary_edges = 0;      ///< edges used by exactly one triangle: holes
  int non_manifold_edges = 0;  ///< edges used by three or more triangles
  /// Non-manifold edges used an odd number of times: like a boundary edge, a ray crossing the
  /// surface near them cannot tell inside from outside.
  int odd_non_manifold_edges = 0;
  int degenerate_triangles = 0;  ///< zero-area triangles (repeated or collinear vertices)
  /// Every edge is shared by an even number of triangles: the surface separates an inside from
  /// an outside (two solids touching along an edge are closed but not manifold).
  bool closed() const { return boundary_edges == 0 && odd_non_manifold_edges == 0; }
};

/// Counts boundary and non-manifold edges and degenerate triangles. Vertices must already be
/// welded (WeldVertices) for edges to be shared. Precondition: indices in range.
MeshTopology AnalyzeTopology(const TriangleMesh& mesh);

/// Merges vertices closer than `tolerance` (m) to each other and renumbers the triangles, so
/// that formats storing one vertex per triangle corner (STL) share their edges. Unused vertices
/// are dropped. Precondition: tolerance >= 0, indices in range.
TriangleMesh WeldVertices(const TriangleMesh& mesh, double tolerance);

/// The mesh without triangles whose area is below `min_area` (m^2) or with repeated vertices;
/// *removed (optional) receives how many were dropped.
TriangleMesh RemoveDegenerateTriangles(const TriangleMesh& mesh, double min_area, int* removed);

/// Volume enclosed by a closed, consistently oriented mesh by the divergence theorem (m^3);
/// negative if the triangles face inwards. Meaningless for an open mesh.
double SignedVolume(const TriangleMesh& mesh);

/// Area of the cross-section of the closed mesh by the plane through `point` with normal
/// `normal` (m^2): the area of the region inside the mesh on that plane. Precondition: the mesh
/// is closed and consistently oriented, normal != 0.
double CrossSectionArea(const TriangleMesh& mesh, const Eigen::Vector3d& point,
                        const Eigen::Vector3d& normal);

/// Smallest and largest vertex coordinates. Precondition: at least one vertex.
void BoundingBox(const TriangleMesh& mesh, Eigen::Vector3d* min, Eigen::Vector3d* max);

/// Area-weighted vertex normals of the surface with the given vertex positions (one column per
/// vertex of `mesh`); a vertex touching no triangle of positive area gets a zero normal.
Eigen::Matrix3Xd VertexNormals(const TriangleMesh& mesh, const Eigen::Matrix3Xd& positions);

}  // namespace msm_sim::core
