// World's implicit kick (docs/physics.md §7.1): steps 3-4 of the substep as one linearly
// implicit velocity update, solved by masked conjugate gradient.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/world_internal.h"
#include "mechanics/masked_pcg.h"
#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {
namespace {

// Solves of one implicit kick at most: each after the first releases the holds that pulled in
// the one before, holds the speculative contacts it took past their surface and changes the
// friction holds that broke Coulomb's law (an active set), until none changes.
constexpr int kImplicitContactPasses = 4;

// A sliding contact starts a kick with the last kick's Coulomb impulse and is solved again when
// its normal impulse moves that limit by more than this fraction: a slide keeps a friction
// consistent with its current normal load (docs/physics.md §7.1) without a solve for every small
// change. The trade-off between stopping distance and solves: docs/design/integrator.md.
constexpr double kSlidingImpulseTolerance = 0.02;

// 1 on the DOFs of free nodes, 0 on kinematic ones.
Eigen::Matrix3Xd FreeDofMask(const std::vector<char>& constrained) {
  Eigen::Matrix3Xd free(3, static_cast<Eigen::Index>(constrained.size()));
  for (std::size_t i = 0; i < constrained.size(); ++i) {
    free.col(static_cast<Eigen::Index>(i)).setConstant(constrained[i] ? 0.0 : 1.0);
  }
  return free;
}

// 1 / (m + c diag K) per DOF. A compressed spring's geometric stiffness can make a diagonal
// entry of K negative; the mass alone then keeps the preconditioner positive.
Eigen::Matrix3Xd InverseSystemDiagonal(const ForceEvaluator& evaluator,
                                       const Eigen::VectorXd& masses, double c) {
  Eigen::Matrix3Xd diagonal = c * evaluator.StiffnessDiagonal().cwiseMax(0.0);
  diagonal.rowwise() += masses.transpose();
  return diagonal.cwiseInverse();
}

}  // namespace

void World::RequireIntegrable(const Body& body) const {
  internal::Require(
      options_.integrator != Integrator::kImplicit || body.evaluator.stiffness_is_symmetric(),
      "body '" + body.name +
          "': the implicit integrator needs a symmetric stiffness (conjugate "
          "gradient), and carrier springs with eMSM dispersion have none; use "
          "linear springs, no dispersion, or the explicit integrator");
}

Eigen::Matrix3Xd World::PrescribedVelocityChanges(const Body& body, double h, double t0) const {
  Eigen::Matrix3Xd changes = Eigen::Matrix3Xd::Zero(3, body.model->num_nodes());
  for (const Group& group : body.groups) {
    const Eigen::Isometry3d from = GroupPose(group, t0);
    const Eigen::Isometry3d to = GroupPose(group, t0 + h);
    for (std::size_t k = 0; k < group.spec.nodes.size(); ++k) {
      const NodeIndex node = group.spec.nodes[k];
      const Eigen::Vector3d local = group.local.col(k);
      // The same velocity DriveKinematicGroups will set.
      changes.col(node) = (to * local - from * local) / h - body.state.velocities.col(node);
    }
  }
  return changes;
}

int World::ImplicitKick(Body* body, double h, double t0) {
  const Eigen::VectorXd& m = body->model->masses();
  const int n = body->model->num_nodes();
  ComputeForces(body);  // springs, dampers and pushes at (x_mid, v)
  body->forces += options_.gravity * m.transpose();
  // Without the compressed springs' negative geometric stiffness, M + c K stays positive definite
  // however hard a contact squeezes, as conjugate gradient requires (with the exact K it can meet
  // negative curvature, docs/physics.md §7.1); the right-hand side keeps the exact forces.
  body->evaluator.Linearize(body->state.positions, GeometricStiffness::kDropCompression);
  const double c = 0.5 * h * h + h * body->options.damping_beta;
  // Colliders are at their mid-substep poses (Substep placed them), as in the contact stage.
  // The touching contacts are held from the start, and so are the speculative ones whose node
  // already approaches faster than its holding speed; the others once the solve would take
  // their node that far.
  std::vector<ContactNormal> held = DeepestColliderContacts(*body, h);
  const Eigen::Matrix3Xd& v = body->state.velocities;
  const auto touching =
      std::stable_partition(held.begin(), held.end(), [&v](const ContactNormal& c) {
        return c.closing_speed == 0.0 ||
               (c.velocity - v.col(c.node)).dot(c.normal) > c.holding_speed;
      });
  std::vector<ContactNormal> speculative(touching, held.end());
  held.erase(touching, held.end());
  Eigen::Matrix3Xd residual;
  const int iterations = SolveImplicitKick(body, h, t0, c, &held, &speculative, &residual);
  // A free node takes dv, a held contact too (approaching its collider at its closing speed).
  // A kinematic node takes the velocity the forces (with dv) would give it: dv minus the
  // constraint's impulse (-residual) over its mass, for DriveKinematicGroups to record the
  // group's reaction as in the explicit kick.
  const Eigen::Matrix3Xd free = FreeDofMask(body->constrained);
  body->state.velocities += body->implicit_dv;
  body->state.velocities +=
      (Eigen::Matrix3Xd::Ones(3, n) - free).cwiseProduct(residual) * m.cwiseInverse().asDiagonal();
  RespondToHeldContacts(body, held, residual);
  return iterations;
}

int World::SolveImplicitKick(Body* body, double h, double t0, double c,
                             std::vector<ContactNormal>* held,
                             std::vector<ContactNormal>* speculative, Eigen::Matrix3Xd* residual) {
  const Eigen::VectorXd& m = body->model->masses();
  const int n = body->model->num_nodes();
  const Eigen::Matrix3Xd& v = body->state.velocities;
  if (body->implicit_dv.cols() != n) body->implicit_dv = Eigen::Matrix3Xd::Zero(3, n);
  Eigen::Matrix3Xd& dv = body->implicit_dv;  // warm start: the last substep's dv
  DofProjection projection;
  projection.free = FreeDofMask(body->constrained);
  const Eigen::Matrix3Xd prescribed = PrescribedVelocityChanges(*body, h, t0);
  Eigen::Matrix3Xd stiffness_product(3, n);
  const NodeArrayOperator apply = [&](const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* out) {
    body->evaluator.ApplyStiffness(x, &stiffness_product);
    *out = c * stiffness_product;
    *out += x * m.asDiagonal();
  };
  MaskedPcgOptions solver;
  solver.relative_tolerance = options_.implicit_tolerance;
  solver.max_iterations = options_.implicit_max_iterations;
  solver.reference_norm =
      h * options_.gravity.norm() * projection.free.row(0).cwiseProduct(m.transpose()).norm();
  const Eigen::Matrix3Xd inverse_diagonal = InverseSystemDiagonal(body->evaluator, m, c);
  // The elastic force at the substep's end position x' = x_mid + h/2 (v + dv), to first order:
  // F(x_mid) - K h/2 (v + dv). Its h/2 K dv part is c's h^2/2; the known h/2 K v part goes to
  // the right-hand side. Taken there (not at x_mid + h/2 dv, which conserved only a modified
  // energy and let the held contacts' rebound feed a bouncing body), the kick never adds
  // energy: dKE = F(x') . (x' - x) <= U(x) - U(x') for a convex potential (docs/physics.md §7.1).
  body->evaluator.ApplyStiffness(v, &stiffness_product);
  const Eigen::Matrix3Xd b = h * body->forces - (0.5 * h * h) * stiffness_product;
  int iterations = 0;
  Eigen::Matrix3Xd b_pass;
  for (int pass = 0; pass < kImplicitContactPasses; ++pass) {
    // The start: the warm start's free part, plus the held parts, known.
    projection.free = FreeDofMask(body->constrained);
    HoldContacts(v, *held, &projection, &dv);
    projection.Apply(&dv);
    dv += prescribed;
    HoldContacts(v, *held, nullptr, &dv);
    b_pass = b;
    for (const ContactNormal& contact : *held) {
      if (contact.friction_hold == FrictionHold::kSliding)
        b_pass.col(contact.node) += contact.sliding_impulse;
    }
    iterations += SolveMaskedPcg(apply, b_pass, projection, inverse_diagonal, solver, &dv, residual)
                      .iterations;
    // A hold that pulls the node into the collider is released, a stick that leaves Coulomb's
    // cone slides and a slide that turns sticks, a node that would pass its speculative
    // contact's surface is held, and the system solved again. After the last solve the friction
    // holds stay as it applied them (a stick beyond the cone holds for that substep).
    bool changed = ReleasePullingContacts(*residual, held);
    if (pass + 1 < kImplicitContactPasses) {
      changed |= UpdateFrictionHolds(v, dv, *residual, held);
      changed |= HoldReachingContacts(v, dv, speculative, held);
    }
    if (!changed) break;
  }
  return iterations;
}

bool World::UpdateFrictionHolds(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
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
      const Eigen::Vector3d sliding = SlidingImpulseOfStick(contact, impulse);
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

Eigen::Vector3d World::SlidingImpulseOfStick(const ContactNormal& contact,
                                             const Eigen::Vector3d& impulse) {
  const double normal = impulse.dot(contact.normal);
  const Eigen::Vector3d tangential = impulse - normal * contact.normal;
  const double limit = contact.friction * normal;
  if (!(tangential.norm() > limit)) return Eigen::Vector3d::Zero();
  return limit * tangential.normalized();
}

bool World::HoldReachingContacts(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
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

void World::HoldContacts(const Eigen::Matrix3Xd& v, const std::vector<ContactNormal>& held,
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

bool World::ReleasePullingContacts(const Eigen::Matrix3Xd& residual,
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

}  // namespace msm_sim::core
