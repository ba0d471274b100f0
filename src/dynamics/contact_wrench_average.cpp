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
  seconds_ += dt;
}

void ContactWrenchAverage::AddMoved(const ContactWrenchAverage& part,
                                    const Eigen::Vector3d& offset) {
  force_time_ += part.force_time_;
  torque_time_ += MoveTorque(part.torque_time_, part.force_time_, offset);
  weighted_centroid_ += part.weighted_centroid_;
  weight_ += part.weight_;
  microcollisions_ += part.microcollisions_;
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
  return average;
}

}  // namespace msm_sim::core
