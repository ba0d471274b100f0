#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "msm_sim/geometry/triangle_mesh.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

struct SurfaceSkinOptions {
  /// Edge of the embedding cells (m); <= 0: half the model's characteristic length, which keeps
  /// every corner within about one node spacing of the surface.
  double cell_size = 0.0;
  /// Each cell corner follows the nodes within this many cell sizes of it, grown (by 1.5^3 at most)
  /// where they do not surround it well enough to fix an affine map.
  double fit_radius = 3.0;
};

/// A visual surface embedded in an MSM: deformed vertex positions and normals from any state
/// (thesis 3.2.7: the mesh "within which the MSM is embedded").
///
/// Trilinear in lattice cells: every vertex lies in one cell of a regular grid of edge h around
/// the surface and keeps its trilinear coordinates in it. Each cell corner is carried by the
/// nodes around it through a weighted least-squares affine fit (moving least squares), which is
/// a fixed linear combination of node positions reproducing any affine motion exactly. So the
/// skin follows rigid motions and uniform strains of the nodes exactly, interpolates smoothly
/// in between, and covers vertices outside the nodes' hull (the nodes of a node-centred lattice
/// sit half a cell inside the surface, where a tetrahedral embedding would have to extrapolate).
/// A vertex stays inside its deformed host cell: its coordinates are in [0, 1]^3 and the cell
/// is the trilinear image of the deformed corners.
///
/// Immutable after Embed; works for any model (cubic, random, Baudet) and any triangle mesh,
/// open or closed, finer or coarser than the one that built the model.
class SurfaceSkin {
 public:
  /// Throws std::invalid_argument if the model has fewer than 4 nodes, the mesh has no
  /// triangles or non-finite vertices, a cell corner has fewer than 4 nodes within 3 fit radii
  /// (the surface lies far from the model: a mesh for another object or in another frame), or
  /// the options are not finite.
  static SurfaceSkin Embed(const Model& model, const TriangleMesh& surface,
                           const SurfaceSkinOptions& options = {});

  const TriangleMesh& rest_surface() const { return surface_; }
  int num_vertices() const { return surface_.num_vertices(); }

  /// Vertex positions (3 x V) for node positions (3 x N, N = model nodes).
  Eigen::Matrix3Xd DeformedVertices(const Eigen::Matrix3Xd& node_positions) const;
  /// Unit area-weighted vertex normals of the surface with those vertex positions.
  Eigen::Matrix3Xd DeformedNormals(const Eigen::Matrix3Xd& deformed_vertices) const;

  // Inspection (tests, visual debugging) of the embedding.
  /// Positions of the host cells' corners for node positions (3 x corners).
  Eigen::Matrix3Xd CornerPositions(const Eigen::Matrix3Xd& node_positions) const;
  /// Per vertex: its host cell's corner indices, corner (i, j, k) at index i + 2 j + 4 k.
  const std::vector<std::array<int, 8>>& host_corners() const { return host_corners_; }
  /// Per vertex: trilinear coordinates in its host cell, each in [0, 1].
  const Eigen::Matrix3Xd& cell_coordinates() const { return cell_coordinates_; }

 private:
  TriangleMesh surface_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> corner_weights_;  // corners x nodes
  std::vector<std::array<int, 8>> host_corners_;
  Eigen::Matrix3Xd cell_coordinates_;
};

/// The trilinear weights of the 8 cell corners (index i + 2 j + 4 k) at coordinates u in [0,1]^3.
std::array<double, 8> TrilinearWeights(const Eigen::Vector3d& u);

}  // namespace msm_sim::core
