#pragma once

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The mutable part of a simulation (the analogue of MuJoCo's mjData): node positions and
/// velocities, one column per node, in the same frame and order as Model::rest_positions().
struct State {
  Eigen::Matrix3Xd positions;   ///< m
  Eigen::Matrix3Xd velocities;  ///< m/s

  /// The model at rest: positions = rest positions, velocities = 0.
  static State AtRest(const Model& model) {
    State state;
    state.positions = model.rest_positions();
    state.velocities = Eigen::Matrix3Xd::Zero(3, model.num_nodes());
    return state;
  }

  /// Displacement of every node from its rest position.
  Eigen::Matrix3Xd Displacements(const Model& model) const {
    return positions - model.rest_positions();
  }
};

}  // namespace msm_sim::core
