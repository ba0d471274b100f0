#pragma once
// Private to msm_sim_core: a geometric multigrid V-cycle that preconditions the implicit step's
// conjugate gradient on M + c K (docs/physics.md §7.1 "Multigrid"), so that its iteration count
// does not grow as the lattice is refined.

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "mechanics/masked_pcg.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core::internal {

struct MultigridOptions {
  int smoothing_degree = 2;  ///< Chebyshev polynomial degree of each smoothing, >= 1
  int coarsest_nodes = 300;  ///< coarsen until a level has at most this many nodes, >= 1
};

/// One coarse level: its grid's prolongation from it to the level above, and its Galerkin mass
/// and stiffness (P^T M P, P^T K P), assembled at set-up.
struct MultigridLevel {
  Eigen::Matrix3Xd vertices;                 ///< m, the grid vertices (rest frame)
  Eigen::SparseMatrix<double> prolongation;  ///< (3 n_above) x (3 n), DOF 3 i + d
  Eigen::SparseMatrix<double> mass;          ///< 3 n x 3 n
  Eigen::SparseMatrix<double> stiffness;     ///< 3 n x 3 n
  // For the current step factor c (SetStepFactor):
  Eigen::SparseMatrix<double, Eigen::RowMajor> system;  ///< mass + c stiffness
  Eigen::VectorXd inverse_diagonal;
  double largest_eigenvalue = 0.0;  ///< of diag(system)^-1 system
};

/// The V-cycle. Coarse grids have 2, 4, 8 ... times the model's characteristic length, over the
/// nodes' rest positions (so any lattice, cubic or random, has one); a node's value is the
/// trilinear interpolation of its coarse cell's corners. The fine level is the caller's own
/// operator (the current K, matrix-free, with its held DOFs); the coarse levels are the rest
/// state's, which makes the set-up a cost once per model and set of kinematic nodes. Not for
/// concurrent Apply calls (it caches the fine level's eigenvalue estimate).
class MultigridPreconditioner {
 public:
  /// `held` (per node, empty for none): the nodes whose three DOFs the solves hold (kinematic
  /// nodes); the coarse levels see them clamped. Contacts' held normals are not seen there (they
  /// change every step), only by the fine level. Preconditions: rest_stiffness is K at the
  /// model's rest positions (3N x 3N, symmetric positive semi-definite), masses > 0, held empty
  /// or of N entries.
  MultigridPreconditioner(const Model& model, const Eigen::SparseMatrix<double>& rest_stiffness,
                          const std::vector<char>& held = {}, const MultigridOptions& options = {});
  /// The V-cycle of the model's rest stiffness (ForceEvaluator::StiffnessMatrix at rest, without
  /// an orientation barrier) with these nodes held, and the default options.
  static std::shared_ptr<MultigridPreconditioner> ForRestState(const Model& model,
                                                               const std::vector<char>& held);
  /// The nodes it was built holding (as given).
  const std::vector<char>& held() const { return held_; }

  /// Prepares the coarse systems M + c K (c > 0); nothing when c is the last one's.
  void SetStepFactor(double c);
  /// Makes the next Apply estimate the fine level's largest eigenvalue again (after a solve
  /// that did not converge: the linearised system may have stiffened past the estimate).
  void ForgetFineEigenvalue() { fine_largest_eigenvalue_ = 0.0; }

  /// *z = B r with B one V-cycle for S A S, where A (3 x N) is `apply` (the fine system, the
  /// whole of it: M + c K at the current state), inverse_diagonal 1 / diag(A) and S the
  /// projection. The coarse levels, built at rest, see the residual turned back by `rotation`
  /// (the body's, rest to current: BodyFrame) and their correction turned forward by it, so that
  /// a body turned as a whole is preconditioned as well as at rest. The smoothing before and
  /// after is the same Chebyshev polynomial, so B is symmetric and positive on the range of S,
  /// as conjugate gradient requires, as long as the fine level's largest eigenvalue is not
  /// underestimated (it is estimated on the first call after SetStepFactor, with a margin).
  /// Precondition: SetStepFactor called; r in the range of S; rotation orthonormal.
  void Apply(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& inverse_diagonal,
             const DofProjection& projection, const Eigen::Matrix3d& rotation,
             const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd* z) const;

  /// The levels below the fine one, finest first (level l's prolongation maps it to level
  /// l - 1, level 0's to the model's nodes).
  const std::vector<MultigridLevel>& coarse_levels() const { return levels_; }

 private:
  void CoarseCycle(int level, const Eigen::VectorXd& b, Eigen::VectorXd* x) const;

  MultigridOptions options_;
  std::vector<char> held_;
  std::vector<MultigridLevel> levels_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> coarsest_;
  double step_factor_ = 0.0;
  mutable double fine_largest_eigenvalue_ = 0.0;  // 0: to estimate on the next Apply
};

}  // namespace msm_sim::core::internal
