#include "msm_sim/mechanics/static_solver.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/IterativeLinearSolvers>

#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

// K restricted to the free DOFs, applied matrix-free through ForceEvaluator::ApplyStiffness.
class FreeStiffnessOperator;

}  // namespace
}  // namespace msm_sim::core

namespace Eigen::internal {
template <>
struct traits<msm_sim::core::FreeStiffnessOperator>
    : public Eigen::internal::traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace msm_sim::core {
namespace {

class FreeStiffnessOperator : public Eigen::EigenBase<FreeStiffnessOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum {
    ColsAtCompileTime = Eigen::Dynamic,
    MaxColsAtCompileTime = Eigen::Dynamic,
    IsRowMajor = false
  };

  FreeStiffnessOperator(const ForceEvaluator& evaluator, const std::vector<int>& free_dofs,
                        double shift)
      : evaluator_(evaluator),
        free_dofs_(free_dofs),
        shift_(shift),
        full_(3, evaluator.model().num_nodes()),
        product_(3, evaluator.model().num_nodes()) {}

  Eigen::Index rows() const { return static_cast<Eigen::Index>(free_dofs_.size()); }
  Eigen::Index cols() const { return rows(); }

  template <typename Rhs>
  Eigen::Product<FreeStiffnessOperator, Rhs, Eigen::AliasFreeProduct> operator*(
      const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<FreeStiffnessOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

  // y += alpha K x on free DOFs.
  template <typename Dest, typename Rhs>
  void ScaleAndAddTo(Dest& y, const Rhs& x, double alpha) const {
    full_.setZero();
    for (std::size_t i = 0; i < free_dofs_.size(); ++i) full_.data()[free_dofs_[i]] = x[i];
    evaluator_.ApplyStiffness(full_, &product_);
    for (std::size_t i = 0; i < free_dofs_.size(); ++i) {
      y[i] += alpha * (product_.data()[free_dofs_[i]] + shift_ * x[i]);
    }
  }

 private:
  const ForceEvaluator& evaluator_;
  const std::vector<int>& free_dofs_;
  double shift_;
  mutable Eigen::Matrix3Xd full_;
  mutable Eigen::Matrix3Xd product_;
};

// Jacobi preconditioner from the exact diagonal of K.
class JacobiPreconditioner {
 public:
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic };

  JacobiPreconditioner() = default;
  void SetInverseDiagonal(Eigen::VectorXd inverse) { inverse_ = std::move(inverse); }

  template <typename Matrix>
  JacobiPreconditioner& analyzePattern(const Matrix&) {
    return *this;
  }
  template <typename Matrix>
  JacobiPreconditioner& factorize(const Matrix&) {
    return *this;
  }
  template <typename Matrix>
  JacobiPreconditioner& compute(const Matrix&) {
    return *this;
  }
  template <typename Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    return inverse_.cwiseProduct(b);
  }
  Eigen::ComputationInfo info() { return Eigen::Success; }

 private:
  Eigen::VectorXd inverse_;
};

}  // namespace
}  // namespace msm_sim::core

namespace Eigen::internal {
template <typename Rhs>
struct generic_product_impl<msm_sim::core::FreeStiffnessOperator, Rhs, SparseShape, DenseShape,
                            GemvProduct>
    : generic_product_impl_base<msm_sim::core::FreeStiffnessOperator, Rhs,
                                generic_product_impl<msm_sim::core::FreeStiffnessOperator, Rhs>> {
  template <typename Dest>
  static void scaleAndAddTo(Dest& dst, const msm_sim::core::FreeStiffnessOperator& lhs,
                            const Rhs& rhs, const double& alpha) {
    lhs.ScaleAndAddTo(dst, rhs, alpha);
  }
};
}  // namespace Eigen::internal

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

template <typename Solver>
Eigen::VectorXd SolveLinear(const FreeStiffnessOperator& op, const Eigen::VectorXd& inverse_diag,
                            const Eigen::VectorXd& rhs, const StaticSolverOptions& options,
                            int* iterations) {
  Solver solver;
  solver.preconditioner().SetInverseDiagonal(inverse_diag);
  solver.setTolerance(options.linear_relative_tolerance);
  solver.setMaxIterations(options.max_linear_iterations);
  solver.compute(op);
  Eigen::VectorXd step = solver.solve(rhs);
  *iterations += static_cast<int>(solver.iterations());
  return step;
}

// The Jacobi preconditioner of the shifted free stiffness. A tiny shift keeps rigid or floppy
// modes the constraints leave free from stalling the Krylov solver; the residual is evaluated
// exactly, so it changes the path, not the answer.
struct ShiftedJacobi {
  double shift;
  Eigen::VectorXd inverse_diagonal;
};

// Precondition: evaluator was linearised at the current positions.
ShiftedJacobi ShiftedJacobiOf(const ForceEvaluator& evaluator, const std::vector<int>& free_dofs) {
  const int num_free = static_cast<int>(free_dofs.size());
  const Eigen::Matrix3Xd diagonal = evaluator.StiffnessDiagonal();
  Eigen::VectorXd free_diagonal(num_free);
  for (int i = 0; i < num_free; ++i) free_diagonal[i] = diagonal.data()[free_dofs[i]];
  const double mean_diagonal = free_diagonal.cwiseAbs().mean();
  ShiftedJacobi jacobi{1e-10 * mean_diagonal, Eigen::VectorXd(num_free)};
  for (int i = 0; i < num_free; ++i) {
    const double d = free_diagonal[i] + jacobi.shift;
    jacobi.inverse_diagonal[i] = d > 1e-12 * mean_diagonal ? 1.0 / d : 1.0 / mean_diagonal;
  }
  return jacobi;
}

// The Newton step: solves K dx = residual on the free DOFs at the current linearisation, with
// conjugate gradient when K is symmetric and BiCGSTAB when it is not. Adds the Krylov iterations
// to *linear_iterations.
Eigen::VectorXd NewtonStep(const ForceEvaluator& evaluator, const std::vector<int>& free_dofs,
                           const Eigen::VectorXd& residual, const StaticSolverOptions& options,
                           int* linear_iterations) {
  const ShiftedJacobi jacobi = ShiftedJacobiOf(evaluator, free_dofs);
  const FreeStiffnessOperator op(evaluator, free_dofs, jacobi.shift);
  if (evaluator.stiffness_is_symmetric()) {
    return SolveLinear<Eigen::ConjugateGradient<FreeStiffnessOperator, Eigen::Lower | Eigen::Upper,
                                                JacobiPreconditioner>>(
        op, jacobi.inverse_diagonal, residual, options, linear_iterations);
  }
  return SolveLinear<Eigen::BiCGSTAB<FreeStiffnessOperator, JacobiPreconditioner>>(
      op, jacobi.inverse_diagonal, residual, options, linear_iterations);
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
