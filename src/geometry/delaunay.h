#pragma once
// Private: the CGAL Delaunay tetrahedralisation of node positions, each vertex tagged with its
// node index. Keeps CGAL's heavy templates out of the public headers.

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <Eigen/Core>

namespace msm_sim::core::delaunay {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase>;
using Triangulation = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;
using Point = Kernel::Point_3;

/// Tetrahedralises the columns of `points`; throws std::invalid_argument if they span less than
/// three dimensions (fewer than 4 points, or all coplanar).
Triangulation Tetrahedralise(const Eigen::Matrix3Xd& points);

}  // namespace msm_sim::core::delaunay
