#pragma once

#include <string>

#include <Eigen/Core>

#include "msm_sim/mechanics/dof_constraints.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

struct StaticSolverOptions {
  /// Converged when every free DOF's net force (springs + external) is at most this (N).
  double force_tolerance = 1e-9;
  int max_newton_iterations = 30;
  /// Relative residual asked of each Krylov solve of the Newton system (inexact Newton: a loose
  /// solve costs a Newton iteration or two more but avoids Krylov stagnation on stiff systems,
  /// e.g. nu -> 1/2; the converged answer is set by force_tolerance alone).
  double linear_relative_tolerance = 1e-3;
  int max_linear_iterations = 50000;
};

struct StaticSolverReport {
  bool converged = false;
  int newton_iterations = 0;
  int linear_iterations = 0;        ///< summed over Newton iterations
  double max_residual_force = 0.0;  ///< N, largest |net force| over free DOFs at the end
  std::string message;              ///< why it stopped, in words
};

/// Finds positions where the internal forces (springs, eMSM dispersion) plus `external_forces`
/// vanish on every free DOF.
///
/// Newton's method: each iteration solves K dx = f for the free DOFs, K the exact linearisation
/// of the forces applied matrix-free (ForceEvaluator::ApplyStiffness, exact two-pass dispersion),
/// with conjugate gradient (K is the energy's Hessian, symmetric for every spring law) and a
/// Jacobi preconditioner from the exact diagonal. K gets a tiny diagonal shift (1e-10 of its mean
/// diagonal) so that rigid or floppy modes left free by the constraints do not stall the Krylov
/// solver; because the residual is always evaluated exactly, the shift changes the path, not the
/// equilibrium found. Steps that do not reduce the residual are halved.
///
/// Preconditions: positions has model.num_nodes() columns and holds the initial guess, with the
/// fixed DOFs at their prescribed values (they are not changed); external_forces is 3 x N;
/// constraints cover the model's nodes.
StaticSolverReport SolveStaticEquilibrium(const Model& model, const DofConstraints& constraints,
                                          const Eigen::Matrix3Xd& external_forces,
                                          const StaticSolverOptions& options,
                                          Eigen::Matrix3Xd* positions);

}  // namespace msm_sim::core
