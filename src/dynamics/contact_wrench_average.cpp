#include "msm_sim/dynamics/contact_wrench_average.h"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

namespace msm_sim::core {

Eigen::Vector3d MoveTorque(const Eigen::Vector3d& torque, const Eigen::Vector3d& force,
                           const Eigen::Vector3d& offset) {
  return torque + offset.cross(force);
}

void ContactWrenchAverage::Add(const ContactWrench& wrench, double dt) {
  const double weight = wrench.force.norm() * dt;
  force_time_ += wrench.force * dt;
  torque_time_ += wrench.torque * dt;
  weighted_centroid_ += weight * wrench.centroid;
  weight_ += weight;
  microcollisions_ += wrench.microcollisions;
  normal_time_ += wrench.normal_force * dt * wrench.normal;
  normal_force_time_ += wrench.normal_force * dt;
  area_time_ += wrench.area * dt;
  seconds_ += dt;
}

void ContactWrenchAverage::AddMoved(const ContactWrenchAverage& part,
                                    const Eigen::Vector3d& offset) {
  force_time_ += part.force_time_;
  torque_time_ += MoveTorque(part.torque_time_, part.force_time_, offset);
  weighted_centroid_ += part.weighted_centroid_;
  weight_ += part.weight_;
  microcollisions_ += part.microcollisions_;
  normal_time_ += part.normal_time_;
  normal_force_time_ += part.normal_force_time_;
  area_time_ += part.area_time_;
  // The parts cover the same steps: the interval is theirs, not their sum.
  seconds_ = part.seconds_;
}

ContactWrench ContactWrenchAverage::Average() const {
  ContactWrench average;
  average.force = force_time_ / seconds_;
  average.torque = torque_time_ / seconds_;
  average.centroid =
      weight_ > 0.0 ? Eigen::Vector3d(weighted_centroid_ / weight_) : Eigen::Vector3d::Zero();
  average.microcollisions =
      static_cast<int>(std::min<long>(microcollisions_, std::numeric_limits<int>::max()));
  const double normal_norm = normal_time_.norm();
  average.normal =
      normal_norm > 0.0 ? Eigen::Vector3d(normal_time_ / normal_norm) : Eigen::Vector3d::Zero();
  average.normal_force = normal_force_time_ / seconds_;
  average.area = area_time_ / seconds_;
  average.mean_pressure = area_time_ > 0.0 ? normal_force_time_ / area_time_ : 0.0;
  return average;
}

}  // namespace msm_sim::core
