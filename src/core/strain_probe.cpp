#include "msm_sim/core/strain_probe.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <Eigen/LU>

namespace msm_sim::core {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;
using Point = Kernel::Point_3;
}  // namespace

struct StrainProbe::Triangulation {
  Delaunay delaunay;
};

StrainProbe::StrainProbe(const Eigen::Matrix3Xd& rest_positions)
    : triangulation_(std::make_unique<Triangulation>()) {
  std::vector<std::pair<Point, int>> points;
  points.reserve(rest_positions.cols());
  for (int i = 0; i < rest_positions.cols(); ++i) {
    const auto p = rest_positions.col(i);
    points.emplace_back(Point(p.x(), p.y(), p.z()), i);
  }
  triangulation_->delaunay.insert(points.begin(), points.end());
  if (triangulation_->delaunay.dimension() < 3) {
    throw std::invalid_argument("strain probe needs at least 4 non-coplanar nodes");
  }
}

StrainProbe::~StrainProbe() = default;
StrainProbe::StrainProbe(StrainProbe&&) noexcept = default;
StrainProbe& StrainProbe::operator=(StrainProbe&&) noexcept = default;

std::optional<Eigen::Vector3d> StrainProbe::DisplacementAt(
    const Eigen::Vector3d& p, const Eigen::Matrix3Xd& displacements) const {
  const Delaunay& delaunay = triangulation_->delaunay;
  const auto cell = delaunay.locate(Point(p.x(), p.y(), p.z()));
  if (delaunay.is_infinite(cell)) return std::nullopt;
  // Barycentric coordinates: p = v0 + [v1-v0 v2-v0 v3-v0] w.
  Eigen::Vector3d v[4];
  int node[4];
  for (int i = 0; i < 4; ++i) {
    const Point& q = cell->vertex(i)->point();
    v[i] = Eigen::Vector3d(q.x(), q.y(), q.z());
    node[i] = cell->vertex(i)->info();
  }
  Eigen::Matrix3d edges;
  edges << v[1] - v[0], v[2] - v[0], v[3] - v[0];
  const Eigen::Vector3d w = edges.fullPivLu().solve(p - v[0]);
  const double w0 = 1.0 - w.sum();
  return w0 * displacements.col(node[0]) + w[0] * displacements.col(node[1]) +
         w[1] * displacements.col(node[2]) + w[2] * displacements.col(node[3]);
}

std::optional<Eigen::Matrix3d> StrainProbe::StrainAt(const Eigen::Vector3d& p,
                                                     const Eigen::Matrix3Xd& displacements,
                                                     double step) const {
  Eigen::Matrix3d gradient;  // gradient(i, j) = d u_i / d x_j
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d offset = step * Eigen::Vector3d::Unit(j);
    const auto forward = DisplacementAt(p + offset, displacements);
    const auto backward = DisplacementAt(p - offset, displacements);
    if (!forward || !backward) return std::nullopt;
    gradient.col(j) = (*forward - *backward) / (2.0 * step);
  }
  return 0.5 * (gradient + gradient.transpose());
}

}  // namespace msm_sim::core
