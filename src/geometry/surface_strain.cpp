#include "msm_sim/geometry/surface_strain.h"

#include <stdexcept>
#include <string>

namespace msm_sim::core {

SurfaceStrain::SurfaceStrain(const TriangleMesh& rest_surface)
    : num_vertices_(rest_surface.num_vertices()), triangles_(rest_surface.triangles) {
  rest_edge_lengths_.resize(3 * rest_surface.num_triangles());
  for (int t = 0; t < rest_surface.num_triangles(); ++t) {
    for (int e = 0; e < 3; ++e) {
      rest_edge_lengths_[3 * t + e] = (rest_surface.vertices.col(triangles_(e, t)) -
                                       rest_surface.vertices.col(triangles_((e + 1) % 3, t)))
                                          .norm();
    }
  }
}

Eigen::VectorXd SurfaceStrain::VertexStrains(const Eigen::Matrix3Xd& vertices) const {
  if (vertices.cols() != num_vertices_) {
    throw std::invalid_argument("surface strain: " + std::to_string(vertices.cols()) +
                                " vertex positions for a surface of " +
                                std::to_string(num_vertices_) + " vertices");
  }
  Eigen::VectorXd strain = Eigen::VectorXd::Zero(num_vertices_);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(num_vertices_);
  for (int t = 0; t < triangles_.cols(); ++t) {
    for (int e = 0; e < 3; ++e) {
      const int a = triangles_(e, t), b = triangles_((e + 1) % 3, t);
      const double rest = rest_edge_lengths_[3 * t + e];
      if (!(rest > 0.0)) continue;
      const double s = (vertices.col(a) - vertices.col(b)).norm() / rest - 1.0;
      strain[a] += s;
      strain[b] += s;
      count[a] += 1.0;
      count[b] += 1.0;
    }
  }
  for (int v = 0; v < num_vertices_; ++v) {
    strain[v] = count[v] > 0.0 ? strain[v] / count[v] : 0.0;
  }
  return strain;
}

}  // namespace msm_sim::core
