#include "msm_sim/experiments/hardy_stress.h"

#include <algorithm>
#include <cmath>

namespace msm_sim::core {

double SegmentFractionInsideBall(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                 const Eigen::Vector3d& centre, double radius) {
  // |p0 + s d - c|^2 = R^2  ->  s^2 |d|^2 + 2 s d.(p0 - c) + |p0 - c|^2 - R^2 = 0.
  const Eigen::Vector3d d = p1 - p0;
  const Eigen::Vector3d m = p0 - centre;
  const double qa = d.squaredNorm();
  if (qa == 0.0) return 0.0;
  const double qb = d.dot(m);
  const double qc = m.squaredNorm() - radius * radius;
  const double discriminant = qb * qb - qa * qc;
  if (discriminant <= 0.0) return 0.0;
  const double root = std::sqrt(discriminant);
  const double s_in = std::max(0.0, (-qb - root) / qa);
  const double s_out = std::min(1.0, (-qb + root) / qa);
  return std::max(0.0, s_out - s_in);
}

Eigen::Matrix3d HardyStress(const Model& model, const Eigen::Matrix3Xd& positions,
                            const Eigen::VectorXd& tensions, const Eigen::Vector3d& point,
                            double radius) {
  const auto& a = model.spring_node_a();
  const auto& b = model.spring_node_b();
  Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();
  for (int s = 0; s < model.num_springs(); ++s) {
    const Eigen::Vector3d pa = positions.col(a[s]);
    const Eigen::Vector3d pb = positions.col(b[s]);
    const double bond = SegmentFractionInsideBall(pa, pb, point, radius);
    if (bond == 0.0) continue;
    const Eigen::Vector3d r = pb - pa;
    stress += (tensions[s] * bond / r.norm()) * r * r.transpose();
  }
  const double probe_volume = 4.0 / 3.0 * M_PI * radius * radius * radius;
  return stress / probe_volume;
}

}  // namespace msm_sim::core
