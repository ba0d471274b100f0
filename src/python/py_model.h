#pragma once
// What the Python module's files share: its handle on a Model, and poses as the scene YAML
// gives them.

#include <memory>

#include <Eigen/Geometry>

#include "msm_sim/model/model.h"

namespace msm_sim::python {

/// Models are immutable and shared by the Worlds their bodies are in, so Python holds the same
/// shared pointer a World does.
struct PyModel {
  std::shared_ptr<const core::Model> model;
};

/// A pose from a position (m) and roll, pitch, yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll), as in
/// docs/scenes.md.
inline Eigen::Isometry3d Pose(const Eigen::Vector3d& position, const Eigen::Vector3d& rpy) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = position;
  return pose;
}

}  // namespace msm_sim::python
