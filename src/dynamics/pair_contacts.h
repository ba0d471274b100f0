#pragma once
// Private to msm_sim's World: stages 5-6 of the substep between border nodes (of two bodies, or
// of a folded one): detect the touching pairs, stop every approach, leave the rebound pending,
// recover overlaps (docs/physics.md §7, §7.2).

#include <vector>

#include <Eigen/Core>

#include "dynamics/world_state.h"

namespace msm_sim::core::internal {

/// A contact between two border nodes during a substep.
struct PairContact {
  Body* body_i;
  NodeIndex i;
  Body* body_j;
  NodeIndex j;
  Eigen::Vector3d normal;  // from j to i
  double inverse_mass_i, inverse_mass_j, reduced_mass, restitution, friction;
  double overlap;        // reach - distance (m, > 0)
  double reach;          // sum of the collision radii (m)
  double stopped = 0.0;  // normal impulse that stopped the approach
};

/// The contacts between the border nodes of a WorldState's bodies: a pair's normal impulse stops
/// its approach, shared by inverse masses, its friction up to mu times (1 + e) that.
class PairContacts {
 public:
  explicit PairContacts(WorldState* world) : world_(*world) {}

  /// Stops every approach between touching border nodes (of two bodies, or a folded one).
  void CollideNodes(int* microcollisions);
  /// The touching pairs of border nodes, found with a spatial hash.
  std::vector<PairContact> FindTouchingPairs();
  /// False when no body may touch itself and no two bodies' border nodes come within reach.
  bool MayHaveTouchingPairs() const;

 private:
  /// Whether nodes i and j of one body may touch: only if it folds (see self_collision).
  static bool MayTouchItself(const Body& body, NodeIndex i, NodeIndex j);
  /// Adds the pair if |d| = |x_i - x_j| (m) is below reach (m) and one of them may move.
  static void AddPairIfTouching(Body* body_i, NodeIndex i, Body* body_j, NodeIndex j,
                                const Eigen::Vector3d& d, double reach,
                                std::vector<PairContact>* pairs);
  /// Up to contact_iterations Gauss-Seidel sweeps taking every pair's approach out.
  void StopPairApproaches(std::vector<PairContact>* pairs) const;
  /// Friction between the pair's nodes, their rebound pending. Precondition: stopped > 0.
  static void RespondToPairContact(const PairContact& pair);
  /// Moves the nodes of the pairs that overlap beyond the slop apart, by the part of the
  /// recovery speed their relative velocity lacks, times h, shared by inverse masses; each
  /// node's summed shift capped at penetration_max_speed times h.
  void RecoverFromPairs(const std::vector<PairContact>& pairs);
  /// The body's slot of *shifts (one per body), zero-filled on first use.
  Eigen::Matrix3Xd& ShiftOf(const Body* body, std::vector<Eigen::Matrix3Xd>* shifts) const;

  WorldState& world_;
};

}  // namespace msm_sim::core::internal
