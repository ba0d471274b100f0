#pragma once

#include <Eigen/Core>

#include "msm_sim/dynamics/contact_wrench.h"

namespace msm_sim::core {

/// The torque of a force and torque about another origin: torque + offset x force, where
/// `offset` is the old origin minus the new one (m). Any units.
Eigen::Vector3d MoveTorque(const Eigen::Vector3d& torque, const Eigen::Vector3d& force,
                           const Eigen::Vector3d& offset);

/// The time average of what a body exerts on one collider (or clamp) over the steps of an
/// interval, such as a publication period: force, torque, normal force and contact area
/// weighted by step duration, the centroid by impulse (|force| dt), the normal by normal impulse
/// (normal_force dt), microcollisions summed; the mean pressure is the mean normal force over
/// the mean area. A wrench is added for every step
/// of the interval, also when it is zero, so that its average is over the whole interval.
class ContactWrenchAverage {
 public:
  /// Adds a step of `dt` seconds (the World's step) during which `wrench` acted.
  /// Precondition: dt > 0 and finite.
  void Add(const ContactWrench& wrench, double dt);
  /// Adds `part`, the average over the same steps of a wrench about another origin, with its
  /// torque moved to this average's origin; `offset` is part's origin minus this one's (m).
  /// Sums several colliders into one (a robot link's collision elements into the link).
  /// Precondition: part and every other part added covered the same steps.
  void AddMoved(const ContactWrenchAverage& part, const Eigen::Vector3d& offset);
  /// Empties the average: a new interval starts.
  void Reset() { *this = ContactWrenchAverage(); }

  /// Force and torque averaged over seconds(), the impulse-weighted centroid (zero when no
  /// impulse was added), microcollisions() (saturated at the int range), the patch (normal,
  /// normal force, area, mean pressure) as ContactWrench describes it.
  /// Precondition: seconds() > 0.
  ContactWrench Average() const;
  /// Seconds of steps added.
  double seconds() const { return seconds_; }
  /// Microcollisions (or constrained nodes) summed over the steps.
  long microcollisions() const { return microcollisions_; }

 private:
  Eigen::Vector3d force_time_ = Eigen::Vector3d::Zero();   // N s
  Eigen::Vector3d torque_time_ = Eigen::Vector3d::Zero();  // N m s
  Eigen::Vector3d weighted_centroid_ = Eigen::Vector3d::Zero();
  double weight_ = 0.0;                                    // N s, the sum of |force| dt
  Eigen::Vector3d normal_time_ = Eigen::Vector3d::Zero();  // N s, sum of normal_force normal dt
  double normal_force_time_ = 0.0;                         // N s
  double area_time_ = 0.0;                                 // m^2 s
  long microcollisions_ = 0;
  double seconds_ = 0.0;
};

}  // namespace msm_sim::core
