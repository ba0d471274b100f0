#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msm_sim/model/model.h"

namespace msm_sim::core::internal {

/// One corner of the orientation barrier evaluated in double (docs/physics.md §4).
struct BarrierCorner {
  Eigen::Vector3d e[3];         // current edges from the apex
  Eigen::Vector3d gradient[4];  // dJ / dx of apex, ends 1, 2, 3
  double ratio = 0.0;           // J
};

/// The corner `nodes` (apex, ends) at `x`: every caller evaluates a corner with this one
/// function, built without FP contraction (CMakeLists.txt), so that a corner's J and forces
/// are the same bits whichever screen selected it.
inline BarrierCorner EvaluateBarrierCorner(const Eigen::Matrix3Xd& x,
                                           const std::array<NodeIndex, 4>& nodes,
                                           double inverse_rest_det) {
  BarrierCorner c;
  for (int i = 0; i < 3; ++i) c.e[i] = x.col(nodes[i + 1]) - x.col(nodes[0]);
  c.gradient[1] = inverse_rest_det * c.e[1].cross(c.e[2]);
  c.gradient[2] = inverse_rest_det * c.e[2].cross(c.e[0]);
  c.gradient[3] = inverse_rest_det * c.e[0].cross(c.e[1]);
  c.gradient[0] = -(c.gradient[1] + c.gradient[2] + c.gradient[3]);
  c.ratio = c.e[0].dot(c.gradient[1]);
  return c;
}

}  // namespace msm_sim::core::internal
