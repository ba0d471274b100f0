#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

using Tetrahedron = std::array<NodeIndex, 4>;

/// Delaunay tetrahedra of a point set (CGAL), each positively oriented at the given points.
/// Precondition: at least 4 points, not all coplanar (throws std::invalid_argument otherwise).
std::vector<Tetrahedron> DelaunayTetrahedra(const Eigen::Matrix3Xd& points);

/// Signed volume of a tetrahedron at `positions` (m^3, > 0 when positively oriented).
double SignedVolume(const Tetrahedron& tetrahedron, const Eigen::Matrix3Xd& positions);

/// Number of tetrahedra whose signed volume at `positions` is not positive (inverted or flat).
int CountInvertedTetrahedra(const std::vector<Tetrahedron>& tetrahedra,
                            const Eigen::Matrix3Xd& positions);

}  // namespace msm_sim::core
