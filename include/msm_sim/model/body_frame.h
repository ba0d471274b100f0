#pragma once

#include <Eigen/Geometry>

#include "msm_sim/model/model.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core {

/// Where a deformed body is, as one rigid frame: the translation is its centre of mass, the
/// rotation the rotation part (polar decomposition) of the mass-weighted best affine fit from
/// the rest positions to the current ones, sum_i m_i (x_i - c)(X_i - C)^T. For a rigid motion
/// of the whole body it returns exactly that motion's rotation; a reflection is never returned
/// (the fit's singular vector of least weight is flipped instead).
///
/// The frame is the body's "pose" for tf: it follows the material, not any one node.
/// Precondition: state.positions has model.num_nodes() columns.
Eigen::Isometry3d BodyFrame(const Model& model, const State& state);

}  // namespace msm_sim::core
