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

  // The contact patch (colliders only; zero for clamps and without contact).
  /// Unit mean of the contact normals (out of the collider, into the body), weighted by their
  /// normal impulses; zero without normal impulse.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// N >= 0: the normal impulses (each along its own normal, pressing the collider) over the step.
  double normal_force = 0.0;
  /// m^2: the surface shares (BorderNodes::surface_shares) of the free border nodes touching the
  /// collider, averaged over the step's substeps. Touching: the node's collision sphere, enlarged
  /// by the factor 1.1 (the radii of face, edge and corner nodes differ by a few percent), overlaps
  /// it.
  double area = 0.0;
  /// Pa: normal_force / area; 0 without area.
  double mean_pressure = 0.0;
};

}  // namespace msm_sim::core
