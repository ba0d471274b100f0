#pragma once

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// One microcollision of a border node with a collider (World::contact_points, recorded with
/// WorldOptions::record_contact_points). SI units, world frame.
struct ContactPoint {
  int collider = 0;  ///< World collider index
  NodeIndex node = 0;
  int substep = 0;  ///< within its Step, from 0
  /// On the collider's surface (m), at the collider's mid-substep pose.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  /// Unit, out of the collider's surface (towards the node).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// N s >= 0: the node pressed the collider with normal_impulse along -normal ...
  double normal_impulse = 0.0;
  /// ... and with this impulse (N s) along the surface (perpendicular to normal): friction.
  Eigen::Vector3d tangential_impulse = Eigen::Vector3d::Zero();

  /// The whole impulse on the collider (N s), as summed into its ContactWrench.
  Eigen::Vector3d impulse() const { return tangential_impulse - normal_impulse * normal; }
};

}  // namespace msm_sim::core
