// The implicit kick's held contacts (implicit_integrator.h, docs/physics.md §7.1): which collider
// contacts the solve holds, how their friction holds change between its passes, and what the
// held contacts record once it is done.
#include <algorithm>
#include <cmath>
#include <vector>

#include "dynamics/implicit_integrator.h"
#include "mechanics/node_array_krylov.h"

namespace msm_sim::core::internal {
namespace {

// The implicit kick also holds, speculatively, the nodes whose collision sphere is within this
// many radii of touching a collider: in one long substep a node can cover more than its gap (a
// pressed block whose indenter backs off a hair springs back through the indenter's face), and a
// contact detected only once the sphere overlaps comes a substep late (docs/physics.md §7.1
// "Speculative contacts"). Such a hold lets the node close its gap and no more; a node that
// would not reach the surface has its hold released (it pulls).
constexpr double kSpeculativeReach = 1.0;

// ... but only a node that would pass the surface by more than this fraction of its radius
// before the next detection: a resting node sinks g h^2 per substep, far less than this, which
// the contact stage stops as before; holding those too made the realtime block's every step
// solve twice (docs/design/integrator.md).
constexpr double kSpeculativeSlop = 0.05;

// A collision sphere whose gap to the collider is under this fraction of its radius touches (is
// held from the start of the kick): a held node ends its kick on the surface only to rounding,
// and a gap of rounding left it speculative, held again by a second solve in every kick
// (docs/design/integrator.md).
constexpr double kTouchingGap = 1e-9;

// A sliding contact starts a kick with the last kick's Coulomb impulse and is solved again when
// its normal impulse moves that limit by more than this fraction: a slide keeps a friction
// consistent with its current normal load (docs/physics.md §7.1) without a solve for every small
// change. The trade-off between stopping distance and solves: docs/design/integrator.md.
constexpr double kSlidingImpulseTolerance = 0.02;

}  // namespace

std::vector<ContactNormal> ImplicitIntegrator::DeepestColliderContacts(const Body& body,
                                                                       double h) const {
  std::vector<ContactNormal> deepest;
  if (world_.colliders.empty()) return deepest;
  const std::vector<ColliderFrame> frames = contacts_.FrameColliders();
  std::vector<NodeContact> contacts;
  for (std::size_t k = 0; k < body.border.nodes.size(); ++k) {
    const NodeIndex node = body.border.nodes[k];
    if (body.constrained[node]) continue;
    const Eigen::Vector3d x = body.state.positions.col(node);
    const double radius = body.border.radii[k];
    contacts_.DetectColliderContacts(frames, x, (1.0 + kSpeculativeReach) * radius, &contacts);
    if (contacts.empty()) continue;
    // The signed distance of x from the collider's surface along its normal: least is deepest.
    const auto depth = [&x](const NodeContact& a) { return (x - a.point).dot(a.normal); };
    const NodeContact& best = *std::min_element(
        contacts.begin(), contacts.end(),
        [&depth](const NodeContact& a, const NodeContact& b) { return depth(a) < depth(b); });
    const double gap = best.distance - radius;
    const double closing_speed = gap > kTouchingGap * radius ? gap / h : 0.0;
    const double approach =
        -(Eigen::Vector3d(body.state.velocities.col(node)) - best.velocity).dot(best.normal);
    const double friction = contacts_.Friction(body, best.collider);
    // A contact starts stuck unless its node slid in the last kick: then it starts sliding
    // with that Coulomb impulse, turned into the new tangent plane (the solve's passes correct
    // either guess; a good one saves a pass).
    FrictionHold hold = FrictionHold::kStuck;
    Eigen::Vector3d sliding_impulse = Eigen::Vector3d::Zero();
    if (!(friction > 0.0)) {
      hold = FrictionHold::kSliding;
    } else if (body.sliding_friction.cols() == body.model->num_nodes()) {
      const Eigen::Vector3d last = body.sliding_friction.col(node);
      const Eigen::Vector3d tangential = last - last.dot(best.normal) * best.normal;
      if (tangential.norm() > 0.0) {
        hold = FrictionHold::kSliding;
        sliding_impulse = last.norm() * tangential.normalized();
      }
    }
    deepest.push_back({node, best.normal, best.velocity, best.point, best.collider,
                       std::max(approach - closing_speed, 0.0), friction, closing_speed,
                       closing_speed + kSpeculativeSlop * radius / h, hold, sliding_impulse});
  }
  return deepest;
}

void ImplicitIntegrator::RespondToHeldContacts(Body* body, const std::vector<ContactNormal>& held,
                                               const Eigen::Matrix3Xd& residual) {
  ContactRecords records = body->Records();
  const int n = body->model->num_nodes();
  if (body->sliding_friction.cols() != n) body->sliding_friction.resize(3, n);
  body->sliding_friction.setZero();
  for (const ContactNormal& contact : held) {
    const Eigen::Vector3d impulse = -residual.col(contact.node);
    const double normal = impulse.dot(contact.normal);
    const double m = body->model->masses()[contact.node];
    if (normal <= 0.0) continue;  // the last solve's hold pulled (a substep's stickiness)
    const double e =
        std::min(world_.colliders[contact.collider].restitution, body->options.restitution);
    // The rebound is e times the approach the hold stopped, not the impulse over m: that also
    // pays for the stiffness coupling c K dv and would return elastic energy as speed.
    const double rebound = e * contact.approach;
    if (rebound > 0.0) body->pending.push_back({contact.node, rebound * contact.normal});
    // The solve applied the friction of the stick or the slide (already in v); the rebound's
    // friction, up to mu times it as in the contact stage, slows a sliding node further.
    Eigen::Vector3d friction_impulse = impulse - normal * contact.normal;  // stuck: the hold's
    if (contact.friction_hold == FrictionHold::kStuck) {
      // Held beyond the cone by the last solve (the passes ran out): the next kick starts it
      // sliding.
      body->sliding_friction.col(contact.node) = SlidingImpulseOfStick(contact, impulse);
    }
    if (contact.friction_hold == FrictionHold::kSliding) {
      auto v = body->state.velocities.col(contact.node);
      const Eigen::Vector3d relative = v - contact.velocity;
      const Eigen::Vector3d sliding = relative - relative.dot(contact.normal) * contact.normal;
      const Eigen::Vector3d rebound_friction = CoulombFriction(sliding, contact.friction * rebound);
      v += rebound_friction;
      friction_impulse = contact.sliding_impulse + m * rebound_friction;
      // The next kick starts from the Coulomb limit of this solve's normal impulse.
      if (contact.friction > 0.0) {
        body->sliding_friction.col(contact.node) =
            contact.friction * normal * contact.sliding_impulse.normalized();
      }
    }
    contacts_.RecordColliderImpulse(&records, contact.node, contact.collider, contact.point,
                                    contact.normal, normal + m * rebound, -friction_impulse);
    ++world_.microcollisions;
  }
}

bool ImplicitIntegrator::UpdateFrictionHolds(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
                                             const Eigen::Matrix3Xd& residual,
                                             std::vector<ContactNormal>* held) {
  // cos 45 degrees: a slide that turns further sticks for a pass, whose hold gives its friction
  // the new direction. Following the slip within the passes instead let the few nodes under an
  // indenter flip direction from pass to pass, so the force depended on the number of passes
  // (docs/design/integrator.md); from the stick impulse the passes settle.
  const double kTurnedCosine = std::sqrt(0.5);
  bool changed = false;
  for (ContactNormal& contact : *held) {
    if (!(contact.friction > 0.0)) continue;  // frictionless: slides with no impulse
    const Eigen::Vector3d impulse = -residual.col(contact.node);
    if (contact.friction_hold == FrictionHold::kStuck) {
      // Past the cone by more than the tolerance a slide's limit keeps: at the cone's edge the
      // exact test let a contact flip stick -> slide -> stick in every kick, a solve per flip.
      const Eigen::Vector3d sliding =
          SlidingImpulseOfStick(contact, impulse, kSlidingImpulseTolerance);
      if (!sliding.isZero(0.0)) {
        contact.friction_hold = FrictionHold::kSliding;
        contact.sliding_impulse = sliding;
        changed = true;
      }
      continue;
    }
    const double normal = impulse.dot(contact.normal);
    const Eigen::Vector3d relative = v.col(contact.node) + dv.col(contact.node) - contact.velocity;
    const Eigen::Vector3d slip = relative - relative.dot(contact.normal) * contact.normal;
    const double against = -slip.dot(contact.sliding_impulse);
    if (!(against > kTurnedCosine * slip.norm() * contact.sliding_impulse.norm())) {
      contact.friction_hold = FrictionHold::kStuck;
      contact.sliding_impulse.setZero();
      changed = true;
      continue;
    }
    // The Coulomb limit of this solve's normal impulse, solved again when it moved by more than
    // kSlidingImpulseTolerance of itself.
    const double limit = contact.friction * normal;
    if (std::abs(contact.sliding_impulse.norm() - limit) > kSlidingImpulseTolerance * limit) {
      contact.sliding_impulse = limit * contact.sliding_impulse.normalized();
      changed = true;
    }
  }
  return changed;
}

Eigen::Vector3d ImplicitIntegrator::SlidingImpulseOfStick(const ContactNormal& contact,
                                                          const Eigen::Vector3d& impulse,
                                                          double margin) {
  const double normal = impulse.dot(contact.normal);
  const Eigen::Vector3d tangential = impulse - normal * contact.normal;
  const double limit = contact.friction * normal;
  if (!(tangential.norm() > (1.0 + margin) * limit)) return Eigen::Vector3d::Zero();
  return limit * tangential.normalized();
}

bool ImplicitIntegrator::HoldReachingContacts(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
                                              std::vector<ContactNormal>* speculative,
                                              std::vector<ContactNormal>* held) {
  // A node passes the surface by the next substep's detection when it approaches faster than
  // its closing speed (gap / h); by more than the slop, faster than its holding speed.
  const auto reaches = [&](const ContactNormal& contact) {
    const Eigen::Vector3d relative = v.col(contact.node) + dv.col(contact.node) - contact.velocity;
    return relative.dot(contact.normal) < -contact.holding_speed;
  };
  const auto reaching = std::stable_partition(speculative->begin(), speculative->end(),
                                              [&](const ContactNormal& c) { return !reaches(c); });
  const bool any = reaching != speculative->end();
  held->insert(held->end(), reaching, speculative->end());
  speculative->erase(reaching, speculative->end());
  return any;
}

void ImplicitIntegrator::HoldContacts(const Eigen::Matrix3Xd& v,
                                      const std::vector<ContactNormal>& held,
                                      DofProjection* projection, Eigen::Matrix3Xd* dv) {
  if (projection != nullptr) {
    projection->normals.clear();
    for (const ContactNormal& contact : held) {
      if (contact.friction_hold == FrictionHold::kStuck) {
        projection->free.col(contact.node).setZero();
      } else {
        projection->normals.push_back({contact.node, contact.normal});
      }
    }
    return;
  }
  // The held part of dv (the projection zeroed it): (v + dv - v_collider) . n = -closing speed,
  // and stuck, no tangential part.
  for (const ContactNormal& contact : held) {
    const Eigen::Vector3d relative = v.col(contact.node) - contact.velocity;
    const Eigen::Vector3d held_part =
        contact.friction_hold == FrictionHold::kStuck
            ? relative
            : Eigen::Vector3d(relative.dot(contact.normal) * contact.normal);
    dv->col(contact.node) -= held_part + contact.closing_speed * contact.normal;
  }
}

bool ImplicitIntegrator::ReleasePullingContacts(const Eigen::Matrix3Xd& residual,
                                                std::vector<ContactNormal>* held) {
  // The hold's impulse on the node is -residual; along n it must push the node out.
  const auto pulls = [&residual](const ContactNormal& contact) {
    return contact.normal.dot(residual.col(contact.node)) >= 0.0;
  };
  const auto kept = std::remove_if(held->begin(), held->end(), pulls);
  const bool changed = kept != held->end();
  held->erase(kept, held->end());
  return changed;
}

}  // namespace msm_sim::core::internal
