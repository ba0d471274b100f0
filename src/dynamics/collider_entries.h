#pragma once
// Private to msm_sim's World: penetration recovery of a collider that appears with border node
// centres inside a body (docs/physics.md §7.2, "A collider that appears inside a body"): it is
// moved back out of the bodies until no collision sphere touches it and pressed back in.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dynamics/world_state.h"

namespace msm_sim::core::internal {

/// A collider's way back in: its contacts use its pose moved by depth along direction (m,
/// world frame), and the depth shrinks at RecoverySpeed(depth) to 0.
struct ColliderEntry {
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();      // unit, out of the bodies
  double depth = 0.0;                                       // m, at the Step's start
  double depth_after = 0.0;                                 // m, at the current Step's end
  Eigen::Vector3d user_velocity = Eigen::Vector3d::Zero();  // the collider's own, m/s
};

/// The entries of a WorldState's colliders, one per collider, kept from Step to Step.
class ColliderEntries {
 public:
  explicit ColliderEntries(WorldState* world) : world_(*world) {}

  /// For each bounded enabled collider: if border node centres of any body lie inside it at
  /// its pose plus its entry, the entry grows to where no collision sphere touches it (along
  /// the way out of the bodies, fixed when the entry starts); returns the poses the substeps
  /// start from (poses plus the entries) and adds the entries' shrinking over dt to the
  /// colliders' velocities. Precondition: poses are the colliders' at the Step's start; call
  /// End after the substeps.
  std::vector<Eigen::Isometry3d> Begin(double dt, const std::vector<Eigen::Isometry3d>& poses);
  /// Gives the colliders their own velocities back; the entries advance if the Step was
  /// accepted and stay where they were if not.
  void End(bool accepted);
  /// Collider c's entry (default: none) as the last Begin or End left it.
  const ColliderEntry& entry(int c) const { return entries_.at(c); }

  /// max over all bodies' border nodes of r - signed distance from the collider at pose (m),
  /// r their collision radius, or 0 if `centres` (the deepest centre); -inf if none is near.
  double DeepestBorderOverlap(const Collider& collider, const Eigen::Isometry3d& pose,
                              bool centres) const;
  /// The unit direction out of the bodies at the node centres inside the collider at pose: minus
  /// the sum of their stars' unit vectors; zero if there is none.
  Eigen::Vector3d WayOutOfBodies(const Collider& collider, const Eigen::Isometry3d& pose) const;
  /// The least distance (>= from, m) the collider at pose must move along direction for no
  /// collision sphere to overlap it (sphere tracing); NaN if none within the collider's size.
  double DistanceToClear(const Collider& collider, const Eigen::Isometry3d& pose,
                         const Eigen::Vector3d& direction, double from) const;

 private:
  WorldState& world_;
  std::vector<ColliderEntry> entries_;  // per collider (Begin)
};

}  // namespace msm_sim::core::internal
