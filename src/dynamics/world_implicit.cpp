// World's implicit kick (docs/physics.md §7.1): steps 3-4 of the substep as one linearly
// implicit velocity update, solved by masked conjugate gradient.
#include <cmath>
#include <string>

#include "dynamics/world_internal.h"
#include "mechanics/masked_pcg.h"
#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {
namespace {

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
  // however hard a contact squeezes (measured: at nu 0.49 under the realtime sphere, CG met
  // negative curvature and the step diverged); the right-hand side keeps the exact forces.
  body->evaluator.Linearize(body->state.positions, GeometricStiffness::kDropCompression);
  const double c = 0.5 * h * h + h * body->options.damping_beta;

  const Eigen::Matrix3Xd free = FreeDofMask(body->constrained);
  if (body->implicit_dv.cols() != n) body->implicit_dv = Eigen::Matrix3Xd::Zero(3, n);
  // Warm start from the last substep's dv; the kinematic nodes' dv is known.
  Eigen::Matrix3Xd& dv = body->implicit_dv;
  dv = free.cwiseProduct(dv) + PrescribedVelocityChanges(*body, h, t0);

  Eigen::Matrix3Xd stiffness_product(3, n);
  const NodeArrayOperator apply = [&](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    body->evaluator.ApplyStiffness(v, &stiffness_product);
    *out = c * stiffness_product;
    *out += v * m.asDiagonal();
  };
  MaskedPcgOptions solver;
  solver.relative_tolerance = options_.implicit_tolerance;
  solver.max_iterations = options_.implicit_max_iterations;
  solver.reference_norm =
      h * options_.gravity.norm() * free.row(0).cwiseProduct(m.transpose()).norm();
  Eigen::Matrix3Xd residual;
  const MaskedPcgReport report =
      SolveMaskedPcg(apply, h * body->forces, free, InverseSystemDiagonal(body->evaluator, m, c),
                     solver, &dv, &residual);
  // A free node takes dv. A kinematic node takes the velocity the forces alone would give it,
  // dv minus the constraint's impulse (-residual) over its mass, so that DriveKinematicGroups
  // records the group's reaction as in the explicit kick.
  body->state.velocities += dv;
  body->state.velocities +=
      (Eigen::Matrix3Xd::Ones(3, n) - free).cwiseProduct(residual) * m.cwiseInverse().asDiagonal();
  return report.iterations;
}

}  // namespace msm_sim::core
