#pragma once
// Private to msm_sim_core: the Krylov solver on 3 x N node arrays with some DOFs held fixed:
// conjugate gradient for World's implicit substep (docs/physics.md §7.1) and the static solver's
// Newton systems, and the operator type both and the stable time step's eigenvalue search take.

#include <functional>
#include <vector>

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
  /// The solve also stops once |r_free| <= early_relative_tolerance times the reference
  /// (>= relative_tolerance; 0 never) and accept_early(x, r_free) holds: a caller's own
  /// criterion of a solution good enough, checked only there. Empty: never.
  double early_relative_tolerance = 0.0;
  std::function<bool(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& r_free)> accept_early;
};

struct MaskedPcgReport {
  int iterations = 0;  ///< one product with A each
  double relative_residual = 0.0;
  /// false: max_iterations reached, or A was not positive on a direction (true when stopped
  /// early by accept_early).
  bool converged = false;
};

/// The DOFs a solve may change, as a projection S applied node by node: element-wise by `free`
/// (1 free, 0 fixed: a kinematic node has S_i = 0), then, for each entry of `normals`, S_i =
/// I - n n^T on that node (its velocity change along the unit n is held; a contact).
struct DofProjection {
  struct NodeNormal {
    Eigen::Index node;       ///< in [0, N), a node with free == 1 on all three DOFs
    Eigen::Vector3d normal;  ///< unit
  };
  Eigen::Matrix3Xd free;            ///< 3 x N, entries 0 or 1
  std::vector<NodeNormal> normals;  ///< at most one per node

  /// *a = S *a (3 x N).
  void Apply(Eigen::Matrix3Xd* a) const;
  /// The normals' part of S alone: equal to Apply on an *a that `free` leaves unchanged.
  void ApplyNormals(Eigen::Matrix3Xd* a) const;
};

/// SolveMaskedPcg below with a per-node projection: the fixed part of *x (its component outside
/// the range of S) is held at the value it comes in with, and *residual is b - A x on every DOF
/// (its component outside the range of S is minus the constraint's impulse). Preconditions as
/// below, with "free DOFs" read as "the range of S".
MaskedPcgReport SolveMaskedPcg(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                               const DofProjection& projection,
                               const Eigen::Matrix3Xd& inverse_diagonal,
                               const MaskedPcgOptions& options, Eigen::Matrix3Xd* x,
                               Eigen::Matrix3Xd* residual);

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
