#pragma once

#include <Eigen/Core>

#include "msm_sim/geometry/triangle_mesh.h"

namespace msm_sim::core {

/// The strain of a triangle surface against its rest shape, per vertex: the mean relative length
/// change (deformed / rest - 1) of the triangle edges at the vertex. Each triangle counts its own
/// edges, so an edge shared by two triangles counts twice; edges of zero rest length are left
/// out. Used to colour a deformed visual surface (the ROS markers).
///
/// Keeps the rest edge lengths, computed once; immutable after construction.
class SurfaceStrain {
 public:
  /// A surface without vertices.
  SurfaceStrain() = default;
  /// Precondition: triangle indices in range.
  explicit SurfaceStrain(const TriangleMesh& rest_surface);

  int num_vertices() const { return num_vertices_; }

  /// Strain per vertex (V) for the deformed vertex positions `vertices` (3 x V, the rest
  /// surface's vertices in the same order); 0 for a vertex on no edge of positive rest length.
  /// Throws std::invalid_argument unless vertices has num_vertices() columns.
  Eigen::VectorXd VertexStrains(const Eigen::Matrix3Xd& vertices) const;

 private:
  int num_vertices_ = 0;
  Eigen::Matrix3Xi triangles_;
  Eigen::VectorXd rest_edge_lengths_;  // edge e of triangle t (t -> t(e + 1)) at 3 t + e
};

}  // namespace msm_sim::core
