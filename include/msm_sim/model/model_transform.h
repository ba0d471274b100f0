#pragma once

#include <Eigen/Geometry>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The same model rigidly moved: every rest position x becomes pose * x; masses, springs,
/// stiffnesses, dispersion weights and correction elements are unchanged (rest lengths are
/// recomputed from the moved positions, equal up to rounding). Builders work in the object's
/// frame; this places the object in the world. Precondition: pose is a rigid transform.
Model TransformedModel(const Model& model, const Eigen::Isometry3d& pose);

}  // namespace msm_sim::core
