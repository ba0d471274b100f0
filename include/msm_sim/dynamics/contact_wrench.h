#pragma once

#include <Eigen/Core>

namespace msm_sim::core {

/// What one body exerted on one collider (or clamp) during a step: the impulses of its
/// microcollisions (or constraint reactions) divided by the step, SI units, world frame.
struct ContactWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< N, on the collider
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< N m, about the collider frame origin
  /// Impulse-weighted mean contact point (m); meaningful when microcollisions > 0.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  int microcollisions = 0;  ///< node contacts (or constrained nodes) that carried impulse
};

}  // namespace msm_sim::core
