#include "msm_sim/core/tetrahedralization.h"

#include <stdexcept>
#include <utility>

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <Eigen/Geometry>

namespace msm_sim::core {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;
}  // namespace

std::vector<Tetrahedron> DelaunayTetrahedra(const Eigen::Matrix3Xd& points) {
  std::vector<std::pair<Kernel::Point_3, int>> input;
  input.reserve(points.cols());
  for (int i = 0; i < points.cols(); ++i) {
    input.emplace_back(Kernel::Point_3(points(0, i), points(1, i), points(2, i)), i);
  }
  const Delaunay delaunay(input.begin(), input.end());
  if (delaunay.dimension() < 3) {
    throw std::invalid_argument("tetrahedralisation needs at least 4 non-coplanar points");
  }
  std::vector<Tetrahedron> tetrahedra;
  tetrahedra.reserve(delaunay.number_of_finite_cells());
  for (auto cell = delaunay.finite_cells_begin(); cell != delaunay.finite_cells_end(); ++cell) {
    Tetrahedron t = {cell->vertex(0)->info(), cell->vertex(1)->info(), cell->vertex(2)->info(),
                     cell->vertex(3)->info()};
    if (SignedVolume(t, points) < 0.0) std::swap(t[2], t[3]);
    tetrahedra.push_back(t);
  }
  return tetrahedra;
}

double SignedVolume(const Tetrahedron& t, const Eigen::Matrix3Xd& positions) {
  const Eigen::Vector3d p0 = positions.col(t[0]);
  return (positions.col(t[1]) - p0)
             .dot((positions.col(t[2]) - p0).cross(positions.col(t[3]) - p0)) /
         6.0;
}

int CountInvertedTetrahedra(const std::vector<Tetrahedron>& tetrahedra,
                            const Eigen::Matrix3Xd& positions) {
  int inverted = 0;
  for (const Tetrahedron& t : tetrahedra) inverted += SignedVolume(t, positions) <= 0.0;
  return inverted;
}

}  // namespace msm_sim::core
