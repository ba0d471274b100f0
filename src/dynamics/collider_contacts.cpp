// Stages 5-6 of the substep for the colliders: detect the nodes' contacts with them, stop every
// approach, leave the rebound pending for the next substep, recover overlaps (contacts between
// nodes: pair_contacts.cpp).
#include "dynamics/collider_contacts.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "dynamics/recovery_speed.h"
#include "mechanics/node_shares.h"

namespace msm_sim::core::internal {
namespace {

// A border node counts in a collider's contact patch while its collision sphere, enlarged by
// this factor, overlaps the collider. The collision radii (the mean half-length of a node's
// springs) differ by a few percent between the face, edge and corner nodes of a lattice: a block
// resting on the ground carries its weight on the face nodes, its base's edge and corner nodes
// hovering 0.02 and 0.04 radii above (node-centred cubic lattice), yet the base is all in contact.
constexpr double kPatchReach = 1.1;

// What a node near a collider costs the contact stage, in units of what a node costs the
// explicit substep's other stages and spring loops (internal::NodeShares::Cut), so that
// shares cut at the contacts carry equal work; how it was chosen: docs/design/threads-default.md.
constexpr double kContactWork = 2.0;

// Penetration recovery leaves this fraction of a node's collision radius overlapping: a node
// resting on a surface sinks by a few micrometres each substep before its approach is stopped,
// and pushing it all the way out lifted it clear of the surface for the next substep, without
// friction, so sliding bodies went too far (docs/physics.md §7.2,
// docs/design/penetration-recovery.md).
constexpr double kRecoverySlop = 0.01;

// A node overlapping a collider by more than this fraction of its collision radius is being
// recovered, not resting (a resting node sinks micrometres per substep): its contact is
// frictionless. An overlap has no sliding history for Coulomb friction to act on, and with it
// the nodes stuck wherever the normal push had moved them, short of the slowly pressed state
// (docs/physics.md §7.2, docs/design/penetration-recovery.md). The implicit kick's held contacts
// keep their friction: frictionless, a box teleported into the block burst with kinetic energy
// there (before the end-position kick) and read no closer to the pressed force (after it).
constexpr double kFrictionlessOverlap = 0.1;

}  // namespace

double ColliderContacts::Friction(const Body& body, int collider) const {
  const double pair = body.pair_friction[collider];
  return pair >= 0.0 ? pair
                     : std::sqrt(body.options.friction * world_.colliders[collider].friction);
}

void ColliderContacts::CollideWithColliders(Body* body, int* microcollisions) {
  if (world_.colliders.empty()) return;
  ContactStage stage = BeginContactStage(body);
  // Each node share takes the border nodes among its nodes (border nodes are in node order), on
  // its own thread, where the share's positions and velocities are in cache: the first share
  // records into the body's records, the others into their own, added after in share order,
  // so the pending rebounds and contact points keep the order one share gives. (Cutting the
  // border nodes into ranges of equal numbers of nodes near a collider instead, to share a
  // block's ground contacts, all in the first share, did not pay: the nodes' cache lines then
  // went to the other core and back; docs/design/threads-default.md.)
  internal::NodeShares::ForEach(&body->evaluator, [&](int share, int begin, int end) {
    CollideShare(&stage, body, share, begin, end, &body->pending);
  });
  EndContactStage(stage, body, microcollisions);
}

void ColliderContacts::CutNodeSharesAtContacts(Body* body, bool cut) const {
  // The nodes the last contact stage found near a collider: a resting block's ground contacts
  // all fall in its first node share, whose thread then runs longer than the other's
  // (docs/design/threads-default.md).
  std::vector<NodeIndex> busy;
  for (std::size_t k = 0; cut && k < body->near_collider.size(); ++k) {
    if (body->near_collider[k]) busy.push_back(body->border.nodes[k]);
  }
  internal::NodeShares::Cut(&body->evaluator, busy, kContactWork);
}

ContactStage ColliderContacts::BeginContactStage(Body* body) const {
  ContactStage stage;
  stage.frames = FrameColliders();
  stage.frictions.resize(world_.colliders.size());
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    stage.frictions[c] = Friction(*body, static_cast<int>(c));
  }
  body->near_collider.resize(body->border.nodes.size());
  const int shares = internal::NodeShares::Count(body->evaluator);
  body->share_records.resize(shares - 1);
  stage.counts.assign(shares, 0);
  return stage;
}

void ColliderContacts::CollideShare(ContactStage* stage, Body* body, int share, int begin, int end,
                                    std::vector<PendingResponse>* first_pending) const {
  const std::vector<NodeIndex>& border = body->border.nodes;
  const auto k_begin = static_cast<std::size_t>(
      std::lower_bound(border.begin(), border.end(), begin) - border.begin());
  const auto k_end = static_cast<std::size_t>(std::lower_bound(border.begin(), border.end(), end) -
                                              border.begin());
  ContactRecords records{&body->impulses, first_pending, &body->contact_points};
  if (share > 0) {
    ShareRecords& own = body->share_records[share - 1];
    own.impulses.assign(body->impulses.size(), ImpulseSum{});
    own.pending.clear();
    own.points.clear();
    records = {&own.impulses, &own.pending, &own.points};
  }
  CollideBorderNodes(stage->frames, stage->frictions, body, k_begin, k_end, &records);
  stage->counts[share] = records.microcollisions;
}

void ColliderContacts::EndContactStage(const ContactStage& stage, Body* body,
                                       int* microcollisions) {
  for (std::size_t share = 1; share < stage.counts.size(); ++share) {
    const ShareRecords& own = body->share_records[share - 1];
    for (std::size_t w = 0; w < own.impulses.size(); ++w) body->impulses[w].Merge(own.impulses[w]);
    body->pending.insert(body->pending.end(), own.pending.begin(), own.pending.end());
    body->contact_points.insert(body->contact_points.end(), own.points.begin(), own.points.end());
  }
  for (const int count : stage.counts) *microcollisions += count;
}

// Flattened: the per-contact helpers it calls are inlined into the per-node loop, which GCC did
// not do on its own (with the library's -fno-semantic-interposition); the gain:
// docs/design/threads-default.md.
__attribute__((flatten)) void ColliderContacts::CollideBorderNodes(
    const std::vector<ColliderFrame>& frames, const std::vector<double>& frictions, Body* body,
    std::size_t k_begin, std::size_t k_end, ContactRecords* records) const {
  FlagNodesNearColliders(frames, body, k_begin, k_end);
  std::vector<NodeContact> contacts;
  for (std::size_t k = k_begin; k < k_end; ++k) {
    const NodeIndex node = body->border.nodes[k];
    if (!body->near_collider[k] || body->constrained[node]) continue;
    DetectColliderContacts(frames, body->state.positions.col(node),
                           kPatchReach * body->border.radii[k], &contacts);
    if (contacts.empty()) continue;
    CountInPatches(*body, k, &contacts, records);
    if (contacts.empty()) continue;
    Eigen::Vector3d v = body->state.velocities.col(node);
    StopColliderApproaches(&contacts, &v);
    for (const NodeContact& contact : contacts) {
      if (contact.stopped <= 0.0) continue;
      const bool recovering =
          contact.distance < body->border.radii[k] * (1.0 - kFrictionlessOverlap);
      RespondToColliderContact(*body, node, contact, recovering ? 0.0 : frictions[contact.collider],
                               &v, records);
      ++records->microcollisions;
    }
    body->state.velocities.col(node) = v;
    RecoverFromColliders(body, node, body->border.radii[k], contacts);
  }
}

void ColliderContacts::FlagNodesNearColliders(const std::vector<ColliderFrame>& frames, Body* body,
                                              std::size_t k_begin, std::size_t k_end) const {
  // One tight pass per collider over the border nodes: most of them are far from every
  // collider (a resting block's sides and top), and rejecting them node by node inside
  // DetectColliderContacts was most of the detection's cost.
  std::fill(body->near_collider.begin() + k_begin, body->near_collider.begin() + k_end, 0);
  char* __restrict near = body->near_collider.data();
  const NodeIndex* nodes = body->border.nodes.data();
  const double* radii = body->border.radii.data();
  const double* x = body->state.positions.data();
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    if (!world_.colliders[c].enabled) continue;
    const ColliderFrame& frame = frames[c];
    // The frame's values in locals: read through the frame in the loop, GCC loaded them again
    // for every node (a char store may alias anything).
    if (!frame.bounded) {
      const double nx = frame.plane_normal.x(), ny = frame.plane_normal.y();
      const double nz = frame.plane_normal.z(), offset = frame.plane_offset;
      for (std::size_t k = k_begin; k < k_end; ++k) {
        const double* p = x + 3 * static_cast<std::ptrdiff_t>(nodes[k]);
        const double distance = nx * p[0] + ny * p[1] + nz * p[2] - offset;
        near[k] |= static_cast<char>(distance < kPatchReach * radii[k]);
      }
      continue;
    }
    const double lo_x = frame.world_box.min().x(), lo_y = frame.world_box.min().y();
    const double lo_z = frame.world_box.min().z(), hi_x = frame.world_box.max().x();
    const double hi_y = frame.world_box.max().y(), hi_z = frame.world_box.max().z();
    for (std::size_t k = k_begin; k < k_end; ++k) {
      const double* p = x + 3 * static_cast<std::ptrdiff_t>(nodes[k]);
      const double reach = kPatchReach * radii[k];
      near[k] |=
          static_cast<char>(p[0] >= lo_x - reach && p[0] <= hi_x + reach && p[1] >= lo_y - reach &&
                            p[1] <= hi_y + reach && p[2] >= lo_z - reach && p[2] <= hi_z + reach);
    }
  }
}

void ColliderContacts::CountInPatches(const Body& body, std::size_t k,
                                      std::vector<NodeContact>* contacts,
                                      ContactRecords* records) const {
  const double radius = body.border.radii[k];
  for (const NodeContact& contact : *contacts) {
    (*records->impulses)[contact.collider].area_time +=
        body.border.surface_shares[k] * world_.substep;
  }
  // Only the spheres that overlap collide.
  contacts->erase(std::remove_if(contacts->begin(), contacts->end(),
                                 [radius](const NodeContact& c) { return c.distance >= radius; }),
                  contacts->end());
}

void ColliderContacts::RecordColliderImpulse(ContactRecords* records, NodeIndex node, int collider,
                                             const Eigen::Vector3d& point,
                                             const Eigen::Vector3d& normal, double normal_impulse,
                                             const Eigen::Vector3d& tangential) const {
  const Eigen::Vector3d on_collider = tangential - normal_impulse * normal;
  ImpulseSum& sum = (*records->impulses)[collider];
  sum.Add(point, world_.colliders[collider].pose.translation(), on_collider);
  sum.normal_impulses += normal_impulse * normal;
  sum.normal_impulse += normal_impulse;
  if (world_.options.record_contact_points) {
    records->points->push_back(
        {collider, node, world_.substep_index, point, normal, normal_impulse, tangential});
  }
}

std::vector<ColliderFrame> ColliderContacts::FrameColliders() const {
  std::vector<ColliderFrame> frames(world_.colliders.size());
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    ColliderFrame& frame = frames[c];
    frame.bounded = world_.colliders[c].shape.Bounds(&frame.lo, &frame.hi);
    frame.inverse = world_.colliders[c].pose.inverse();
    frame.moving = !world_.colliders[c].linear_velocity.isZero(0.0) ||
                   !world_.colliders[c].angular_velocity.isZero(0.0);
    if (!frame.bounded) {
      frame.plane_normal = world_.colliders[c].pose.linear().col(2);
      frame.plane_offset = frame.plane_normal.dot(world_.colliders[c].pose.translation());
      continue;
    }
    const Eigen::AlignedBox3d local(frame.lo, frame.hi);
    for (int corner = 0; corner < 8; ++corner) {
      frame.world_box.extend(world_.colliders[c].pose *
                             local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
    }
  }
  return frames;
}

void ColliderContacts::DetectColliderContacts(const std::vector<ColliderFrame>& frames,
                                              const Eigen::Vector3d& x, double radius,
                                              std::vector<NodeContact>* contacts) const {
  contacts->clear();
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    if (!world_.colliders[c].enabled) continue;
    const ColliderFrame& frame = frames[c];
    if (!frame.bounded) {
      // A plane in the world frame directly: the general path below (into the plane's frame,
      // its SignedDistance, back out) gives the same contact and was most of the detection's
      // cost for a body resting on the ground.
      const double distance = frame.plane_normal.dot(x) - frame.plane_offset;
      if (distance >= radius) continue;
      const Eigen::Vector3d point = x - distance * frame.plane_normal;
      contacts->push_back({static_cast<int>(c), frame.plane_normal, point,
                           frame.VelocityAt(world_.colliders[c], point), distance});
      continue;
    }
    if ((x.array() < frame.world_box.min().array() - radius).any() ||
        (x.array() > frame.world_box.max().array() + radius).any()) {
      continue;
    }
    const Eigen::Vector3d local = frame.inverse * x;
    if ((local.array() < frame.lo.array() - radius).any() ||
        (local.array() > frame.hi.array() + radius).any()) {
      continue;
    }
    Eigen::Vector3d normal, closest;
    const double distance = world_.colliders[c].shape.SignedDistance(local, &normal, &closest);
    if (distance >= radius) continue;
    const Eigen::Vector3d point = world_.colliders[c].pose * closest;
    contacts->push_back({static_cast<int>(c), world_.colliders[c].pose.linear() * normal, point,
                         frame.VelocityAt(world_.colliders[c], point), distance});
  }
}

void ColliderContacts::StopColliderApproaches(std::vector<NodeContact>* contacts,
                                              Eigen::Vector3d* v) const {
  // Gauss-Seidel: a node touching several surfaces at once (a wedge, a gripper) must end
  // approaching none of them.
  for (int sweep = 0; sweep < world_.options.contact_iterations; ++sweep) {
    bool approaching = false;
    for (NodeContact& contact : *contacts) {
      const double vn = (*v - contact.velocity).dot(contact.normal);
      if (vn < 0.0) {
        *v -= vn * contact.normal;
        contact.stopped -= vn;
        approaching = true;
      }
    }
    if (!approaching) break;
  }
}

void ColliderContacts::RespondToColliderContact(const Body& body, NodeIndex node,
                                                const NodeContact& contact, double friction,
                                                Eigen::Vector3d* v, ContactRecords* records) const {
  const Collider& collider = world_.colliders[contact.collider];
  const double e = std::min(collider.restitution, body.options.restitution);
  // Friction: up to mu times this contact's normal velocity change, against the sliding
  // velocity, never reversing it.
  Eigen::Vector3d slowing = Eigen::Vector3d::Zero();
  if (friction > 0.0) {
    const Eigen::Vector3d relative = *v - contact.velocity;
    const Eigen::Vector3d sliding = relative - relative.dot(contact.normal) * contact.normal;
    slowing = CoulombFriction(sliding, friction * (1.0 + e) * contact.stopped);
    *v += slowing;
  }
  if (e > 0.0) records->pending->push_back({node, e * contact.stopped * contact.normal});
  const double m = body.model->masses()[node];
  RecordColliderImpulse(records, node, contact.collider, contact.point, contact.normal,
                        m * (1.0 + e) * contact.stopped, -m * slowing);
}

// Penetration recovery (docs/physics.md §7.2): a position-level correction after the contact
// stage, for nodes found deeper than their collision spheres allow.
void ColliderContacts::RecoverFromColliders(Body* body, NodeIndex node, double radius,
                                            const std::vector<NodeContact>& contacts) const {
  // A pseudo-velocity: the part of the target separation speed the node's real velocity (after
  // the contact response) does not already give moves its position and nothing else, so the
  // correction never becomes kinetic energy. The springs it compresses push back in the next
  // substeps, and the contact stage records their push as the collider's wrench.
  const Eigen::Vector3d v = body->state.velocities.col(node);
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (const NodeContact& contact : contacts) {
    const double target =
        RecoverySpeed(world_.options, radius * (1.0 - kRecoverySlop) - contact.distance);
    const double separating = (v - contact.velocity).dot(contact.normal);
    if (target > separating) shift += (target - separating) * world_.substep * contact.normal;
  }
  body->state.positions.col(node) += shift;
}

}  // namespace msm_sim::core::internal
