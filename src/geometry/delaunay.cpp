#include "geometry/delaunay.h"

#include <stdexcept>
#include <utility>
#include <vector>

namespace msm_sim::core::delaunay {

Triangulation Tetrahedralise(const Eigen::Matrix3Xd& points) {
  std::vector<std::pair<Point, int>> input;
  input.reserve(points.cols());
  for (int i = 0; i < points.cols(); ++i) {
    input.emplace_back(Point(points(0, i), points(1, i), points(2, i)), i);
  }
  Triangulation triangulation(input.begin(), input.end());
  if (triangulation.dimension() < 3) {
    throw std::invalid_argument("tetrahedralisation needs at least 4 non-coplanar points");
  }
  return triangulation;
}

}  // namespace msm_sim::core::delaunay
