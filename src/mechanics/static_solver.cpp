#include "msm_sim/mechanics/static_solver.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "mechanics/node_array_krylov.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

// Net force on every free DOF.
Eigen::VectorXd FreeResidual(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& positions,
                             const Eigen::Matrix3Xd& external_forces,
                             const std::vector<int>& free_dofs) {
  Eigen::Matrix3Xd forces = external_forces;
  evaluator->AccumulateForces(positions, &forces);
  Eigen::VectorXd residual(free_dofs.size());
  for (std::size_t i = 0; i < free_dofs.size(); ++i) residual[i] = forces.data()[free_dofs[i]];
  return residual;
}

double MaxAbs(const Eigen::VectorXd& v) { return v.size() == 0 ? 0.0 : v.cwiseAbs().maxCoeff(); }

// The Newton step: solves K dx = residual on the free DOFs at the current linearisation, with
// conjugate gradient (K is symmetric for every spring law, docs/physics.md §3), preconditioned
// by the exact diagonal. A tiny shift of K keeps rigid or floppy modes the constraints leave free
// from stalling the Krylov solver; the residual is evaluated exactly, so it changes the path, not
// the answer. Adds the Krylov iterations to *linear_iterations.
Eigen::VectorXd NewtonStep(const ForceEvaluator& evaluator, const std::vector<int>& free_dofs,
                           const Eigen::VectorXd& residual, const StaticSolverOptions& options,
                           int* linear_iterations) {
  const int n = evaluator.model().num_nodes();
  Eigen::Matrix3Xd free = Eigen::Matrix3Xd::Zero(3, n), b = free;
  for (std::size_t i = 0; i < free_dofs.size(); ++i) {
    free.data()[free_dofs[i]] = 1.0;
    b.data()[free_dofs[i]] = residual[i];
  }
  const Eigen::Matrix3Xd diagonal = evaluator.StiffnessDiagonal().cwiseProduct(free);
  const double mean_diagonal = diagonal.cwiseAbs().sum() / static_cast<double>(free_dofs.size());
  const double shift = 1e-10 * mean_diagonal;
  const Eigen::Matrix3Xd inverse_diagonal = (diagonal.array() + shift).unaryExpr([&](double d) {
    return d > 1e-12 * mean_diagonal ? 1.0 / d : 1.0 / mean_diagonal;
  });
  const NodeArrayOperator apply = [&](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    evaluator.ApplyStiffness(v, out);
    *out += shift * v;
  };
  MaskedPcgOptions krylov;
  krylov.relative_tolerance = options.linear_relative_tolerance;
  krylov.max_iterations = options.max_linear_iterations;
  Eigen::Matrix3Xd step = Eigen::Matrix3Xd::Zero(3, n), unused;
  const MaskedPcgReport report =
      SolveMaskedPcg(apply, b, free, inverse_diagonal, krylov, &step, &unused);
  *linear_iterations += report.iterations;
  Eigen::VectorXd free_step(free_dofs.size());
  for (std::size_t i = 0; i < free_dofs.size(); ++i) free_step[i] = step.data()[free_dofs[i]];
  return free_step;
}

// Backtracking on the residual norm keeps Newton safe far from equilibrium: tries the step and
// up to 11 halvings of it, and takes the first that gives a finite residual of smaller norm.
// Returns false, leaving *positions and *residual as they were, if none does.
bool TakeBacktrackingStep(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& external_forces,
                          const std::vector<int>& free_dofs, const Eigen::VectorXd& step,
                          Eigen::Matrix3Xd* positions, Eigen::VectorXd* residual) {
  const int num_free = static_cast<int>(free_dofs.size());
  const double old_norm = residual->norm();
  double scale = 1.0;
  Eigen::Matrix3Xd trial;
  Eigen::VectorXd trial_residual;
  bool accepted = false;
  for (int halving = 0; halving < 12 && !accepted; ++halving, scale *= 0.5) {
    trial = *positions;
    for (int i = 0; i < num_free; ++i) trial.data()[free_dofs[i]] += scale * step[i];
    trial_residual = FreeResidual(evaluator, trial, external_forces, free_dofs);
    accepted = trial_residual.allFinite() && trial_residual.norm() < old_norm;
  }
  if (!accepted) return false;
  *positions = trial;
  *residual = trial_residual;
  return true;
}

std::string SummaryOf(const StaticSolverReport& report) {
  std::ostringstream message;
  message << (report.converged ? "converged" : "did not converge") << " after "
          << report.newton_iterations << " Newton iterations (" << report.linear_iterations
          << " Krylov iterations), max residual force " << report.max_residual_force << " N";
  return message.str();
}

}  // namespace

StaticSolverReport SolveStaticEquilibrium(const Model& model, const DofConstraints& constraints,
                                          const Eigen::Matrix3Xd& external_forces,
                                          const StaticSolverOptions& options,
                                          Eigen::Matrix3Xd* positions) {
  StaticSolverReport report;
  const std::vector<int> free_dofs = constraints.FreeDofs();
  ForceEvaluator evaluator(model);  // exact (two-pass) dispersion
  Eigen::VectorXd residual = FreeResidual(&evaluator, *positions, external_forces, free_dofs);
  report.max_residual_force = MaxAbs(residual);
  if (!std::isfinite(report.max_residual_force)) {
    report.message = "the initial positions give non-finite forces";
    return report;
  }

  for (int iteration = 0; iteration < options.max_newton_iterations; ++iteration) {
    if (report.max_residual_force <= options.force_tolerance) break;
    ++report.newton_iterations;
    evaluator.Linearize(*positions);
    const Eigen::VectorXd step =
        NewtonStep(evaluator, free_dofs, residual, options, &report.linear_iterations);
    if (!TakeBacktrackingStep(&evaluator, external_forces, free_dofs, step, positions, &residual)) {
      report.message = "no Newton step reduces the residual force (max " +
                       std::to_string(report.max_residual_force) + " N)";
      return report;
    }
    report.max_residual_force = MaxAbs(residual);
  }
  report.converged = report.max_residual_force <= options.force_tolerance;
  report.message = SummaryOf(report);
  return report;
}

}  // namespace msm_sim::core
