#pragma once
// Private to msm_sim_core: the conjugate-gradient solver of World's implicit substep
// (docs/physics.md §7.1), on 3 x N node arrays with some DOFs held fixed.

#include <functional>

#include <Eigen/Core>

namespace msm_sim::core {

/// out = A v for 3 x N arrays (out is sized by the caller).
using NodeArrayOperator = std::function<void(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out)>;

struct MaskedPcgOptions {
  double relative_tolerance = 1e-4;  ///< stop at |r_free| <= this times the reference, in (0, 1)
  int max_iterations = 200;          ///< >= 0
  /// The reference is the largest of |b_free|, the initial |r_free| and this (>= 0): a floor for
  /// systems whose right-hand side can vanish (a body at rest).
  double reference_norm = 0.0;
};

struct MaskedPcgReport {
  int iterations = 0;  ///< one product with A each
  double relative_residual = 0.0;
  bool converged = false;  ///< false: max_iterations reached, or A was not positive on a direction
};

/// Solves A x = b on the free DOFs (free(d, i) == 1; 0 where fixed) by conjugate gradient with
/// the diagonal preconditioner `inverse_diagonal` (an approximation of 1 / diag A), holding the
/// fixed entries of *x at the values they come in with: their known part moves to the right-hand
/// side because the residual includes A x for the full x, and the residual and search directions
/// are masked to the free DOFs. The free entries of *x are the starting guess (a warm start).
/// On return *residual holds b - A x on every DOF, the fixed ones included (there, minus the
/// impulse a constraint must supply).
///
/// Preconditions: A symmetric, positive definite on the free DOFs (an indefinite direction ends
/// the solve unconverged); all arrays 3 x N; inverse_diagonal > 0 on the free DOFs.
MaskedPcgReport SolveMaskedPcg(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                               const Eigen::Matrix3Xd& free,
                               const Eigen::Matrix3Xd& inverse_diagonal,
                               const MaskedPcgOptions& options, Eigen::Matrix3Xd* x,
                               Eigen::Matrix3Xd* residual);

}  // namespace msm_sim::core
