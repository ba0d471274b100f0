#pragma once
// Private to msm_sim's World: the speed penetration recovery separates an overlap at
// (docs/physics.md §7.2), shared by the collider contacts, the node pairs and collider entries.

#include <algorithm>

#include "msm_sim/dynamics/world_options.h"

namespace msm_sim::core::internal {

/// The separation speed (m/s) an overlap this deep (m) is recovered at: min(max speed,
/// depth / recovery time); 0 if depth <= 0.
inline double RecoverySpeed(const WorldOptions& options, double depth) {
  if (depth <= 0.0) return 0.0;
  return std::min(options.penetration_max_speed, depth / options.penetration_recovery_time);
}

}  // namespace msm_sim::core::internal
