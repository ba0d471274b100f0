#pragma once

#include <memory>
#include <optional>

#include <Eigen/Core>

namespace msm_sim::core {

/// Strain at a point from node displacements (docs/physics.md §6, thesis 3.1.1).
///
/// The rest positions are tetrahedralised once (CGAL Delaunay); the displacement anywhere inside
/// their convex hull is the barycentric interpolation of the nodes of the enclosing tetrahedron,
/// and the strain is eps = (grad u + grad u^T) / 2 with grad u from central differences
/// (u(r + n d) - u(r - n d)) / 2d along x, y, z.
class StrainProbe {
 public:
  /// Precondition: at least 4 rest positions that are not all coplanar (throws
  /// std::invalid_argument otherwise).
  explicit StrainProbe(const Eigen::Matrix3Xd& rest_positions);
  ~StrainProbe();
  StrainProbe(StrainProbe&&) noexcept;
  StrainProbe& operator=(StrainProbe&&) noexcept;

  /// Displacement at rest-frame point p, or nothing outside the convex hull of the nodes.
  /// Precondition: displacements has one column per rest position.
  std::optional<Eigen::Vector3d> DisplacementAt(const Eigen::Vector3d& p,
                                                const Eigen::Matrix3Xd& displacements) const;

  /// Small-strain tensor at p with central-difference step `step` (the thesis uses 0.5 ã), or
  /// nothing if a sample point falls outside the convex hull.
  std::optional<Eigen::Matrix3d> StrainAt(const Eigen::Vector3d& p,
                                          const Eigen::Matrix3Xd& displacements, double step) const;

 private:
  struct Triangulation;
  std::unique_ptr<Triangulation> triangulation_;
};

}  // namespace msm_sim::core
