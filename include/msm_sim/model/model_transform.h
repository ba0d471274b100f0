#pragma once

#include <Eigen/Geometry>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The same model rigidly moved: every rest position x becomes pose * x; masses, springs,
/// stiffnesses, dispersion weights and correction elements are unchanged (rest lengths are
/// recomputed from the moved positions, equal up to rounding). Builders work in the object's
/// frame; this places the object in the world. Precondition: pose is a rigid transform.
Model TransformedModel(const Model& model, const Eigen::Isometry3d& pose);

/// The same model with every spring following `law` (`power` its alpha, beta for
/// SpringLaw::kPower; ModelBuilder::SetSpringLaw): the lattice builders take the law from
/// LatticeOptions, which names no (alpha, beta) yet. Stiffnesses are unchanged, as the laws
/// share the small-strain stiffness k (docs/physics.md §4.1).
Model WithSpringLaw(const Model& model, SpringLaw law, const PowerSpringLaw& power = {});

}  // namespace msm_sim::core
