#include "geometry/tetrahedralization.h"

#include <utility>

#include <Eigen/Geometry>

#include "geometry/delaunay.h"

namespace msm_sim::core {

std::vector<Tetrahedron> DelaunayTetrahedra(const Eigen::Matrix3Xd& points) {
  const delaunay::Triangulation triangulation = delaunay::Tetrahedralise(points);
  std::vector<Tetrahedron> tetrahedra;
  tetrahedra.reserve(triangulation.number_of_finite_cells());
  for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end();
       ++cell) {
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
