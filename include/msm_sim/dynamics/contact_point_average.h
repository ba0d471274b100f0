#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/dynamics/contact_point.h"

namespace msm_sim::core {

/// The contact points of any number of bodies over an interval, such as a publication period,
/// merged per (body, collider, node): what a tactile sensor reports. Each point's force is its
/// impulses over the interval's duration (so the points of a collider sum to the time average of
/// its ContactWrench force), its position and normal are impulse-weighted means.
///
/// Keeps its buffers between intervals: after the first intervals, adding and resetting
/// allocate nothing unless more points touch than ever before.
class ContactPointAverage {
 public:
  /// A node's contact with a collider over the interval. SI units, world frame.
  struct Point {
    int body = 0;
    int collider = 0;
    NodeIndex node = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m, impulse-weighted mean
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();    ///< unit, out of the collider
    Eigen::Vector3d force = Eigen::Vector3d::Zero();     ///< N, on the collider
  };

  /// Adds the contact points `points` of body `body` (with `num_nodes` nodes, > every point's
  /// node) recorded during one step (World::contact_points). The interval's duration is counted
  /// apart, by AddStep once per step whatever the number of bodies. Precondition: body >= 0.
  void Add(int body, int num_nodes, const std::vector<ContactPoint>& points);
  /// A step of dt seconds (> 0, finite) passed.
  void AddStep(double dt) { seconds_ += dt; }
  /// Empties the average: a new interval starts.
  void Reset();

  /// Seconds of steps added.
  double seconds() const { return seconds_; }
  /// Number of distinct (body, collider, node) contacts.
  std::size_t size() const { return sums_.size(); }
  /// Contact k (< size()), averaged over seconds() (> 0), in the order they first touched.
  Point Average(std::size_t k) const;

 private:
  struct Sum {
    int body, collider;
    NodeIndex node;
    int next;                        // the node's next contact (another collider), -1: none
    Eigen::Vector3d weighted_point;  // sum of |impulse| point
    double weight;                   // sum of |impulse|
    Eigen::Vector3d normal_impulse;  // sum of normal_impulse normal
    Eigen::Vector3d impulse;         // on the collider
  };
  /// The index in sums_ of (body, collider, node), added if new.
  int Find(int body, int collider, NodeIndex node);

  std::vector<std::vector<int>> first_;  // per body, per node: its first Sum, -1: none
  std::vector<Sum> sums_;
  double seconds_ = 0.0;
};

}  // namespace msm_sim::core
