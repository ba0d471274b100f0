#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

// Regions that pick nodes by their rest positions: what clamps and kinematic grips are made of
// (World::AddKinematicGroup takes the indices).

/// Nodes whose rest position lies in the axis-aligned box [lo, hi] (m).
std::vector<NodeIndex> NodesInBox(const Model& model, const Eigen::Vector3d& lo,
                                  const Eigen::Vector3d& hi);

/// Nodes whose rest position lies in the half-space (x - point) . normal <= 0, i.e. behind the
/// plane through `point` facing `normal`. Precondition: normal != 0.
std::vector<NodeIndex> NodesInHalfSpace(const Model& model, const Eigen::Vector3d& point,
                                        const Eigen::Vector3d& normal);

}  // namespace msm_sim::core
