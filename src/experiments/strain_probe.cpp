#include "msm_sim/experiments/strain_probe.h"

#include <Eigen/LU>

#include "geometry/delaunay.h"

namespace msm_sim::core {

struct StrainProbe::Triangulation {
  delaunay::Triangulation delaunay;
};

StrainProbe::StrainProbe(const Eigen::Matrix3Xd& rest_positions)
    : triangulation_(std::make_unique<Triangulation>(
          Triangulation{delaunay::Tetrahedralise(rest_positions)})) {}

StrainProbe::~StrainProbe() = default;
StrainProbe::StrainProbe(StrainProbe&&) noexcept = default;
StrainProbe& StrainProbe::operator=(StrainProbe&&) noexcept = default;

std::optional<Eigen::Vector3d> StrainProbe::DisplacementAt(
    const Eigen::Vector3d& p, const Eigen::Matrix3Xd& displacements) const {
  const delaunay::Triangulation& delaunay = triangulation_->delaunay;
  const auto cell = delaunay.locate(delaunay::Point(p.x(), p.y(), p.z()));
  if (delaunay.is_infinite(cell)) return std::nullopt;
  // Barycentric coordinates: p = v0 + [v1-v0 v2-v0 v3-v0] w.
  Eigen::Vector3d v[4];
  int node[4];
  for (int i = 0; i < 4; ++i) {
    const delaunay::Point& q = cell->vertex(i)->point();
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
