#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Nodes whose positions a rigid frame dictates: a clamp (fixed frame) or a kinematic grip. The
/// nodes keep their offsets in the frame they had when the group was added.
struct KinematicGroup {
  std::string name;
  std::vector<NodeIndex> nodes;
  /// Frame pose at time t (s). Empty: fixed at the pose the group was added with.
  std::function<Eigen::Isometry3d(double)> pose;
};

}  // namespace msm_sim::core
