#include "msm_sim/core/static_solver.h"

#include <cmath>
#include <sstream>
#include <vector>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include "msm_sim/core/spring_forces.h"

namespace msm_sim::core {
namespace {

// Net force on every free DOF, gathered into a vector in free-DOF numbering.
Eigen::VectorXd FreeResidual(const Model& model, const Eigen::Matrix3Xd& positions,
                             const Eigen::Matrix3Xd& external_forces,
                             const std::vector<int>& numbering, int num_free) {
  Eigen::Matrix3Xd forces = external_forces;
  AccumulateSpringForces(model, positions, &forces);
  Eigen::VectorXd residual(num_free);
  for (int dof = 0; dof < static_cast<int>(numbering.size()); ++dof) {
    if (numbering[dof] >= 0) residual[numbering[dof]] = forces(dof % 3, dof / 3);
  }
  return residual;
}

double MaxAbs(const Eigen::VectorXd& v) { return v.size() == 0 ? 0.0 : v.cwiseAbs().maxCoeff(); }

}  // namespace

StaticSolverReport SolveStaticEquilibrium(const Model& model, const DofConstraints& constraints,
                                          const Eigen::Matrix3Xd& external_forces,
                                          const StaticSolverOptions& options,
                                          Eigen::Matrix3Xd* positions) {
  StaticSolverReport report;
  int num_free = 0;
  const std::vector<int> numbering = constraints.FreeDofNumbering(&num_free);
  Eigen::VectorXd residual = FreeResidual(model, *positions, external_forces, numbering, num_free);
  report.max_residual_force = MaxAbs(residual);
  if (!std::isfinite(report.max_residual_force)) {
    report.message = "the initial positions give non-finite forces";
    return report;
  }

  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::SparseMatrix<double> tangent(num_free, num_free);
  for (int iteration = 0; iteration < options.max_newton_iterations; ++iteration) {
    if (report.max_residual_force <= options.force_tolerance) {
      report.converged = true;
      break;
    }
    ++report.newton_iterations;
    triplets.clear();
    AppendTangentStiffness(model, *positions, numbering, &triplets);
    tangent.setFromTriplets(triplets.begin(), triplets.end());
    const double shift = 1e-10 * tangent.diagonal().cwiseAbs().mean();
    for (int i = 0; i < num_free; ++i) tangent.coeffRef(i, i) += shift;

    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
    cg.setTolerance(options.linear_relative_tolerance);
    cg.setMaxIterations(options.max_linear_iterations);
    cg.compute(tangent);
    const Eigen::VectorXd step = cg.solve(residual);
    report.linear_iterations += static_cast<int>(cg.iterations());

    // Backtracking on the residual norm keeps Newton safe far from equilibrium.
    const double old_norm = residual.norm();
    double scale = 1.0;
    Eigen::Matrix3Xd trial = *positions;
    Eigen::VectorXd trial_residual;
    for (int halving = 0; halving < 8; ++halving, scale *= 0.5) {
      trial = *positions;
      for (int dof = 0; dof < static_cast<int>(numbering.size()); ++dof) {
        if (numbering[dof] >= 0) trial(dof % 3, dof / 3) += scale * step[numbering[dof]];
      }
      trial_residual = FreeResidual(model, trial, external_forces, numbering, num_free);
      if (trial_residual.allFinite() && trial_residual.norm() < old_norm) break;
    }
    if (!trial_residual.allFinite() || !(trial_residual.norm() < old_norm)) {
      report.message = "no Newton step reduces the residual force";
      return report;
    }
    *positions = trial;
    residual = trial_residual;
    report.max_residual_force = MaxAbs(residual);
  }
  if (!report.converged && report.max_residual_force <= options.force_tolerance) {
    report.converged = true;
  }
  std::ostringstream message;
  message << (report.converged ? "converged" : "did not converge") << " after "
          << report.newton_iterations << " Newton iterations (" << report.linear_iterations
          << " CG iterations), max residual force " << report.max_residual_force << " N";
  report.message = message.str();
  return report;
}

}  // namespace msm_sim::core
