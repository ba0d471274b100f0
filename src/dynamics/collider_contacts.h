#pragma once
// Private to msm_sim's World: stages 5-6 of the substep against the rigid colliders (detect the
// border nodes' contacts, stop every approach with friction, leave the rebound pending, recover
// overlaps), run on the node shares of a body's force loops.

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dynamics/world_state.h"

namespace msm_sim::core::internal {

/// A collider's frame for detection, computed once per body and substep.
struct ColliderFrame {
  bool bounded;            // planes are unbounded
  Eigen::Vector3d lo, hi;  // bounds in the collider's frame
  // The bounds' box in the world frame: most border nodes are far from a bounded collider, and
  // this test skips their transform into its frame (docs/design/speed-against-bullet.md).
  Eigen::AlignedBox3d world_box;
  // A plane's normal and offset in the world frame (distance = normal . x - offset): the same
  // shortcut for the nodes high above the ground.
  Eigen::Vector3d plane_normal;
  double plane_offset;
  Eigen::Isometry3d inverse;
  // Whether the collider has a twist: a still one's material is at rest, and skipping
  // VelocityAt's cross product (through the stack) took a sixth of a resting block's detection.
  bool moving;

  Eigen::Vector3d VelocityAt(const Collider& collider, const Eigen::Vector3d& point) const {
    return moving ? collider.VelocityAt(point) : Eigen::Vector3d::Zero();
  }
};

/// A contact of one node with one collider during the detection of a substep.
struct NodeContact {
  int collider;
  Eigen::Vector3d normal;    // unit, out of the collider
  Eigen::Vector3d point;     // on the collider's surface
  Eigen::Vector3d velocity;  // of the collider's material there
  double distance;           // signed, of the node from the surface (m)
  double stopped = 0.0;      // normal velocity change that stopped the approach (>= 0)
};

/// What a body's contact stage of one substep shares between its node shares.
struct ContactStage {
  std::vector<ColliderFrame> frames;  // FrameColliders()
  std::vector<double> frictions;      // Friction(body, c) per collider: once per substep, not a
                                      // square root per contact
  std::vector<int> counts;            // microcollisions per node share
};

/// Coulomb friction's velocity change for a node sliding at `sliding` (tangential, relative to
/// the collider) when it may change by at most `limit` (>= 0): against the sliding, never
/// reversing it. A sticking node (|sliding| <= limit) takes exactly -sliding, without a square
/// root or division.
inline Eigen::Vector3d CoulombFriction(const Eigen::Vector3d& sliding, double limit) {
  const double slide_sq = sliding.squaredNorm();
  if (slide_sq <= limit * limit) return -sliding;
  return -(limit / std::sqrt(slide_sq)) * sliding;
}

/// The contacts of the bodies' border nodes with the colliders of a WorldState (docs/physics.md
/// §7). Each contact's normal velocity change is (1 + e) times the approach speed, its friction
/// up to mu times that; a node overlapping deeper than its collision sphere allows is moved out
/// (penetration recovery, §7.2).
class ColliderContacts {
 public:
  explicit ColliderContacts(WorldState* world) : world_(*world) {}

  /// Coulomb coefficient of a body against a collider: the pair's, or sqrt(mu_body mu_collider).
  double Friction(const Body& body, int collider) const;
  /// Stops every approach of body's free border nodes towards the colliders, with friction.
  /// Runs on the node shares of the body's force loops (internal::NodeShares::ForEach), each
  /// share taking the border nodes among its nodes and recording into its own ContactRecords,
  /// added to the body's in share order: with one share the body's records directly.
  /// Precondition: the body's impulses are sized (StepLoop::ClearStepRecords).
  void CollideWithColliders(Body* body, int* microcollisions);
  /// At a Step's start: cuts the body's node shares at equal work, counting the work of the
  /// border nodes the last contact stage found near a collider (internal::NodeShares::Cut),
  /// or, without `cut`, into equal shares.
  void CutNodeSharesAtContacts(Body* body, bool cut) const;
  /// CollideWithColliders in three parts. Begin: the colliders' frames (at their current
  /// poses) and frictions, the near flags and the shares' records sized. Precondition: some
  /// collider.
  ContactStage BeginContactStage(Body* body) const;
  /// Node share `share` [begin, end): its border nodes, recorded into the body's records (share
  /// 0, its rebounds into *first_pending) or the share's own.
  void CollideShare(ContactStage* stage, Body* body, int share, int begin, int end,
                    std::vector<PendingResponse>* first_pending) const;
  /// End: the records of the shares after the first added to the body's in share order, and
  /// the microcollisions to *microcollisions.
  static void EndContactStage(const ContactStage& stage, Body* body, int* microcollisions);
  /// Each collider's inverse pose and bounds (computed once per body and substep).
  std::vector<ColliderFrame> FrameColliders() const;
  /// Replaces *contacts with the enabled colliders a node at x with this radius (m) touches.
  /// Precondition: frames from FrameColliders for the colliders' current poses.
  void DetectColliderContacts(const std::vector<ColliderFrame>& frames, const Eigen::Vector3d& x,
                              double radius, std::vector<NodeContact>* contacts) const;
  /// The impulse a node gave a collider in this substep (normal_impulse N s along -normal,
  /// tangential N s along the surface) into the collider's sum and, if recording, the contact
  /// points.
  void RecordColliderImpulse(ContactRecords* records, NodeIndex node, int collider,
                             const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                             double normal_impulse, const Eigen::Vector3d& tangential) const;

 private:
  /// Border nodes [k_begin, k_end) of CollideWithColliders; `frictions`: Friction(*body, c) per
  /// collider c.
  void CollideBorderNodes(const std::vector<ColliderFrame>& frames,
                          const std::vector<double>& frictions, Body* body, std::size_t k_begin,
                          std::size_t k_end, ContactRecords* records) const;
  /// Flags in body->near_collider the border nodes [k_begin, k_end) that pass
  /// DetectColliderContacts' first tests (a plane's distance, a bounded collider's world box)
  /// for some enabled collider. Precondition: near_collider sized to the border.
  void FlagNodesNearColliders(const std::vector<ColliderFrame>& frames, Body* body,
                              std::size_t k_begin, std::size_t k_end) const;
  /// Up to contact_iterations Gauss-Seidel sweeps taking each contact's approach out of *v.
  void StopColliderApproaches(std::vector<NodeContact>* contacts, Eigen::Vector3d* v) const;
  /// Friction with coefficient `friction` into *v (0 for none: a node being recovered from a
  /// deep overlap), the rebound pending, the impulse recorded. Precondition: stopped > 0.
  void RespondToColliderContact(const Body& body, NodeIndex node, const NodeContact& contact,
                                double friction, Eigen::Vector3d* v, ContactRecords* records) const;
  /// Border node k's surface share into the patch of every collider in *contacts (detected with
  /// the patch's reach), then drops those its collision sphere does not overlap.
  void CountInPatches(const Body& body, std::size_t k, std::vector<NodeContact>* contacts,
                      ContactRecords* records) const;
  /// Moves a node with this collision radius out of the colliders it overlaps (contacts as
  /// CountInPatches leaves them), by the part of the recovery speed its velocity lacks, times h.
  void RecoverFromColliders(Body* body, NodeIndex node, double radius,
                            const std::vector<NodeContact>& contacts) const;

  WorldState& world_;
};

}  // namespace msm_sim::core::internal
