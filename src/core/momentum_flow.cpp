#include "msm_sim/core/momentum_flow.h"

namespace msm_sim::core {

Eigen::Vector3d MomentumFlowThroughPlane(const Model& model, const Eigen::Matrix3Xd& positions,
                                         const MaterialPlane& plane) {
  const auto& rest = model.rest_positions();
  const auto& a = model.spring_node_a();
  const auto& b = model.spring_node_b();
  const auto& rest_length = model.spring_rest_length();
  const auto& k = model.spring_stiffness();
  Eigen::Vector3d flow = Eigen::Vector3d::Zero();
  for (int s = 0; s < model.num_springs(); ++s) {
    const bool a_plus = plane.normal.dot(rest.col(a[s]) - plane.point) >= 0.0;
    const bool b_plus = plane.normal.dot(rest.col(b[s]) - plane.point) >= 0.0;
    if (a_plus == b_plus) continue;
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    const double length = r.norm();
    const double tension = k[s] * (length - rest_length[s]);
    // r̂ from the - side node to the + side node.
    flow += (b_plus ? 1.0 : -1.0) * tension * r / length;
  }
  return flow;
}

}  // namespace msm_sim::core
