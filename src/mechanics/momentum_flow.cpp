#include "msm_sim/mechanics/momentum_flow.h"

namespace msm_sim::core {

Eigen::Vector3d MomentumFlowThroughPlane(const Model& model, const Eigen::Matrix3Xd& positions,
                                         const Eigen::VectorXd& tensions,
                                         const MaterialPlane& plane) {
  const auto& rest = model.rest_positions();
  const auto& a = model.spring_node_a();
  const auto& b = model.spring_node_b();
  Eigen::Vector3d flow = Eigen::Vector3d::Zero();
  for (int s = 0; s < model.num_springs(); ++s) {
    const bool a_plus = plane.normal.dot(rest.col(a[s]) - plane.point) >= 0.0;
    const bool b_plus = plane.normal.dot(rest.col(b[s]) - plane.point) >= 0.0;
    if (a_plus == b_plus) continue;
    const Eigen::Vector3d r = positions.col(b[s]) - positions.col(a[s]);
    // r̂ from the - side node to the + side node.
    flow += (b_plus ? 1.0 : -1.0) * tensions[s] * r / r.norm();
  }
  return flow;
}

}  // namespace msm_sim::core
