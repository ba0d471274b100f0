#pragma once
// Private to msm_sim's World: stages 5-6 of the substep between border nodes (of two bodies, or
// of a folded one): detect the touching pairs, stop every approach, leave the rebound pending,
// recover overlaps (docs/physics.md §7, §7.2).

#include <vector>

#include <Eigen/Core>

#include "dynamics/world_state.h"

namespace msm_sim::core::internal {

/// The mean unit vector from a node to its spring neighbours at their current positions: into
/// its body at a border node, whose star is one-sided.
Eigen::Vector3d NodeStar(const Body& body, NodeIndex node);

/// A contact between two border nodes during a substep.
struct PairContact {
  Body* body_i;
  NodeIndex i;
  Body* body_j;
  NodeIndex j;
  Eigen::Vector3d normal;  // from j to i (the way out of both bodies if they coincide)
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
  /// The touching pairs of border nodes, in a fixed order (the order of their bodies and border
  /// nodes), tested among the candidates (FindCandidates) while those still hold. A pair deeper
  /// than it is frictionless whose nodes have passed each other faces the way out of both bodies
  /// (docs/physics.md §7.2).
  std::vector<PairContact> FindTouchingPairs();
  /// False when no body may touch itself and no two bodies' border nodes come within reach.
  bool MayHaveTouchingPairs() const;

 private:
  /// Whether nodes i and j of one body may touch: only if it folds (see self_collision).
  static bool MayTouchItself(const Body& body, NodeIndex i, NodeIndex j);
  /// Adds the pair if |d| = |x_i - x_j| (m, where the contacts see them) is below reach (m) and
  /// one of them may move.
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
  /// The body's slot of shifts_, zero-filled when its node count changes.
  Eigen::Matrix3Xd& ShiftOf(const Body* body);

  /// Two border nodes that were within their reach plus skin_ of each other: the pairs that can
  /// touch while no border node has moved skin_ / 2 from found_at_.
  struct Candidate {
    int body_i;
    NodeIndex i;
    int body_j;
    NodeIndex j;
    double reach;  // sum of the collision radii (m)
  };
  /// A border node of a body, with its collision radius (m).
  struct BorderEntry {
    int body;
    NodeIndex node;
    double radius;
  };
  /// Whether candidates_ still hold every pair that can touch: the same bodies with the same
  /// models, and no border node farther than skin_ / 2 from where they were found.
  bool CandidatesHold() const;
  /// Finds the candidates with a spatial hash over the border nodes near another body (or of a
  /// body that may touch itself), in the order of their bodies and border nodes.
  void FindCandidates();
  /// The border nodes within `margin` (m) of another body's border nodes' bounding box, and every
  /// border node of a body that may touch itself, in the order of their bodies and border nodes.
  std::vector<BorderEntry> NodesNearOtherBodies(double margin) const;

  WorldState& world_;
  std::vector<Candidate> candidates_;
  std::vector<Eigen::Matrix3Xd>
      found_at_;  // per body, its border nodes when candidates_ were found
  std::vector<const Model*> found_models_;  // per body, its model then
  double skin_ = 0.0;                       // m
  std::vector<Eigen::Matrix3Xd> shifts_;    // per body, the recovery's sums: zero between stages
};

}  // namespace msm_sim::core::internal
