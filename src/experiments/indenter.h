#pragma once
// The rigid sphere the contact experiments press into a body (indentation, real-time run).

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/collider.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A sphere collider of `radius` (m) above the centre of the model's bounding box (at rest),
/// `gap` (m) above the first collision sphere under it (a negative gap: that far inside the
/// body), moving down at `speed` (m/s). Throws std::invalid_argument if no collision sphere lies
/// under it. Preconditions: radius > 0, all finite.
Collider SphereIndenter(const Model& model, const BorderNodes& border, double radius, double gap,
                        double speed);

}  // namespace msm_sim::core
