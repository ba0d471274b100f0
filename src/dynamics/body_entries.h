#pragma once
// Private to msm_sim's World: penetration recovery of a body found with border node centres
// inside another (docs/physics.md §7.2, "A body found inside another"): the pair contacts see
// it moved out of the other body until no collision spheres touch, and pressed back in, as
// ColliderEntries moves a collider.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dynamics/world_state.h"

namespace msm_sim::core::internal {

/// A body's way back in: its pair contacts see its nodes moved by depth along direction (m,
/// world frame), and the depth shrinks at RecoverySpeed(depth) to 0.
struct BodyEntry {
  int other = -1;                                       // the body it was found inside
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit, out of the other body
  double depth = 0.0;                                   // m, at the Step's start
  double step_depth = 0.0;   // m, at the current Step's start, once it was found inside again
  double depth_after = 0.0;  // m, at the current Step's end
};

/// The entries of a WorldState's bodies, one per body, kept from Step to Step.
class BodyEntries {
 public:
  explicit BodyEntries(WorldState* world) : world_(*world) {}

  /// For each two bodies whose border nodes' boxes overlap: if a border node centre of either
  /// lies inside the other (Overlapping), the entering one's entry (Entering) grows to where no
  /// collision spheres of the two touch, along the way out fixed when the entry starts
  /// (WayOut). Gives every entering body the velocity of its entry's shrinking over dt (s);
  /// call Place before each substep's pair contacts and End after the substeps.
  void Begin(double dt);
  /// Moves every entering body's contact_offset to where its entry is tau (s) into the Step.
  void Place(double tau);
  /// Zeroes the bodies' contact offsets and velocities; the entries advance if the Step was
  /// accepted and stay where they were if not.
  void End(bool accepted);
  /// Body b's entry (default: none) as the last Begin or End left it.
  const BodyEntry& entry(int b) const { return entries_.at(static_cast<std::size_t>(b)); }

  /// Which of bodies a and b is moved out of the other: one without constrained nodes rather
  /// than a clamped or driven one, else the lighter, else the one added later.
  int Entering(int a, int b) const;
  /// Whether a border node centre of body a, seen moved by offset (m), lies inside body b, or one
  /// of b's inside a so moved (Inside).
  bool Overlapping(int a, const Eigen::Vector3d& offset, int b) const;
  /// The way out of body b for body a: of the six directions along the world axes, the one in
  /// which a's border nodes clear b's bounding box after the least travel; ties against gravity.
  Eigen::Vector3d WayOut(int a, int b) const;
  /// The least distance (>= from, m) body a must move along direction for its border nodes to
  /// lie beyond b's along it and no collision sphere of a to touch one of b.
  double DistanceToClear(int a, int b, const Eigen::Vector3d& direction, double from) const;

 private:
  /// Begin's part for bodies a and b: the entering one's step_depth grows if it (further) lies
  /// inside the other.
  void EnterIfInside(int a, int b);
  /// Whether a border node centre of `body`, moved by offset (m), lies inside `other`: its
  /// nearest node of `other` within twice other's largest collision radius is an interior
  /// node, or a border node it lies on or behind (on the inner side of that node's star).
  static bool Inside(const Body& body, const Eigen::Vector3d& offset, const Body& other,
                     const Eigen::Vector3d& other_offset);

  WorldState& world_;
  std::vector<BodyEntry> entries_;  // per body (Begin)
  double dt_ = 0.0;                 // s, of the Step under way
};

}  // namespace msm_sim::core::internal
