#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {

std::vector<NodeIndex> NodesInBox(const Model& model, const Eigen::Vector3d& lo,
                                  const Eigen::Vector3d& hi) {
  std::vector<NodeIndex> nodes;
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    const Eigen::Vector3d p = model.rest_positions().col(i);
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) nodes.push_back(i);
  }
  return nodes;
}

std::vector<NodeIndex> NodesInHalfSpace(const Model& model, const Eigen::Vector3d& point,
                                        const Eigen::Vector3d& normal) {
  std::vector<NodeIndex> nodes;
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    if ((model.rest_positions().col(i) - point).dot(normal) <= 0.0) nodes.push_back(i);
  }
  return nodes;
}

}  // namespace msm_sim::core
