// The implicit integrator's kick (implicit_integrator.h, docs/physics.md §7.1): steps 3-4 of the
// substep as one linearly implicit velocity update, solved by masked conjugate gradient.
#include "dynamics/implicit_integrator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/node_stages.h"
#include "dynamics/world_internal.h"
#include "mechanics/node_array_krylov.h"

namespace msm_sim::core::internal {
namespace {

// Solves of one implicit kick at most: each after the first releases the holds that pulled in
// the one before, holds the speculative contacts it took past their surface and changes the
// friction holds that broke Coulomb's law (an active set), until none changes.
constexpr int kImplicitContactPasses = 4;

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

Eigen::Matrix3Xd ImplicitIntegrator::PrescribedVelocityChanges(const Body& body, double h,
                                                               double t0) {
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

int ImplicitIntegrator::Kick(Body* body, double h, double t0) {
  const Eigen::VectorXd& m = body->model->masses();
  const int n = body->model->num_nodes();
  ComputeForces(body);  // springs, dampers and pushes at (x_mid, v)
  body->forces += world_.options.gravity * m.transpose();
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
  const int iterations = SolveKick(body, h, t0, c, &held, &speculative, &residual);
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

MaskedPcgOptions ImplicitIntegrator::SolverOptions(const WorldOptions& options, const Body& body,
                                                   double h, const Eigen::Matrix3Xd& free) {
  const Eigen::VectorXd& m = body.model->masses();
  MaskedPcgOptions solver;
  solver.relative_tolerance = options.implicit_tolerance;
  solver.max_iterations = options.implicit_max_iterations;
  solver.reference_norm =
      h * options.gravity.norm() * free.row(0).cwiseProduct(m.transpose()).norm();
  if (options.implicit_energy_tolerance > 0.0) {
    solver.early_relative_tolerance = options.implicit_early_tolerance;
    // |dKE| <= |v + dv|_M |A^-1 r|_M <= |v + dv|_M |r|_(M^-1), since A = M + c K >= M; the
    // kinetic energy is the free nodes' (a kinematic node's velocity is prescribed).
    const double bound = options.implicit_energy_tolerance;
    const Eigen::Matrix3Xd& v = body.state.velocities;
    const Eigen::VectorXd free_masses = m.cwiseProduct(free.row(0).transpose());
    solver.accept_early = [&m, &v, free_masses, bound](const Eigen::Matrix3Xd& dv,
                                                       const Eigen::Matrix3Xd& r) {
      const double residual = (r.colwise().squaredNorm() * m.cwiseInverse()).value();
      const double momentum = ((v + dv).colwise().squaredNorm() * free_masses).value();
      return residual <= bound * bound * momentum;
    };
  }
  return solver;
}

int ImplicitIntegrator::SolveKick(Body* body, double h, double t0, double c,
                                  std::vector<ContactNormal>* held,
                                  std::vector<ContactNormal>* speculative,
                                  Eigen::Matrix3Xd* residual) {
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
    *out = c * stiffness_product + x * m.asDiagonal();
  };
  const MaskedPcgOptions solver = SolverOptions(world_.options, *body, h, projection.free);
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

}  // namespace msm_sim::core::internal
