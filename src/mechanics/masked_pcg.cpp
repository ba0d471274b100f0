#include "mechanics/node_array_krylov.h"

#include <algorithm>
#include <cmath>

namespace msm_sim::core {
namespace {

// Sum of the elementwise products (Frobenius inner product of two 3 x N arrays).
double Dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return a.cwiseProduct(b).sum(); }

// One CG update in one sweep: x += alpha p, residual -= alpha A p, and r = S residual.
void Advance(double alpha, const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& product,
             const DofProjection& projection, Eigen::Matrix3Xd* x, Eigen::Matrix3Xd* residual,
             Eigen::Matrix3Xd* r) {
  const Eigen::Index size = p.size();
  const double* __restrict free = projection.free.data();
  const double* __restrict direction = p.data();
  const double* __restrict change = product.data();
  double* __restrict solution = x->data();
  double* __restrict full = residual->data();
  double* __restrict projected = r->data();
  for (Eigen::Index j = 0; j < size; ++j) {
    solution[j] += alpha * direction[j];
    full[j] -= alpha * change[j];
    projected[j] = free[j] * full[j];
  }
  projection.ApplyNormals(r);
}

}  // namespace

void DofProjection::Apply(Eigen::Matrix3Xd* a) const {
  *a = free.cwiseProduct(*a);
  ApplyNormals(a);
}

void DofProjection::ApplyNormals(Eigen::Matrix3Xd* a) const {
  for (const NodeNormal& constraint : normals) {
    auto column = a->col(constraint.node);
    column -= constraint.normal.dot(column) * constraint.normal;
  }
}

MaskedPcgReport SolveMaskedPcg(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                               const Eigen::Matrix3Xd& free,
                               const Eigen::Matrix3Xd& inverse_diagonal,
                               const MaskedPcgOptions& options, Eigen::Matrix3Xd* x,
                               Eigen::Matrix3Xd* residual) {
  DofProjection projection;
  projection.free = free;
  return SolveMaskedPcg(apply, b, projection, inverse_diagonal, options, x, residual);
}

MaskedPcgReport SolveMaskedPcg(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                               const DofProjection& projection,
                               const Eigen::Matrix3Xd& inverse_diagonal,
                               const MaskedPcgOptions& options, Eigen::Matrix3Xd* x,
                               Eigen::Matrix3Xd* residual) {
  // z = S D^-1 S r: symmetric, positive on the range of S, so CG stays in that range. The solve
  // passes an r in that range, which D^-1 keeps free-masked: only the normals remain to apply.
  const NodeArrayPreconditioner diagonal = [&](const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd* z) {
    *z = inverse_diagonal.cwiseProduct(r);
    projection.ApplyNormals(z);
  };
  return SolveMaskedPcg(apply, b, projection, diagonal, options, x, residual);
}

MaskedPcgReport SolveMaskedPcg(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                               const DofProjection& projection,
                               const NodeArrayPreconditioner& precondition,
                               const MaskedPcgOptions& options, Eigen::Matrix3Xd* x,
                               Eigen::Matrix3Xd* residual) {
  MaskedPcgReport report;
  Eigen::Matrix3Xd product(3, x->cols());
  apply(*x, &product);
  *residual = b - product;
  Eigen::Matrix3Xd r = *residual;
  projection.Apply(&r);
  Eigen::Matrix3Xd free_b = b;
  projection.Apply(&free_b);
  const double reference = std::max({free_b.norm(), r.norm(), options.reference_norm});
  const double threshold = options.relative_tolerance * reference;
  double r_norm = r.norm();
  Eigen::Matrix3Xd z;
  precondition(r, &z);
  Eigen::Matrix3Xd p = z;
  double rz = Dot(r, z);
  const double early_threshold = options.early_relative_tolerance * reference;
  bool accepted_early = false;
  const auto done = [&] {
    if (r_norm <= threshold) return true;
    accepted_early =
        options.accept_early && r_norm <= early_threshold && options.accept_early(*x, r);
    return accepted_early;
  };
  while (!done() && report.iterations < options.max_iterations) {
    apply(p, &product);  // p is in the range of S, so S A p is A restricted to it
    const double curvature = Dot(p, product);
    if (!(curvature > 0.0)) break;  // A not positive along p (or not finite): give up
    const double alpha = rz / curvature;
    Advance(alpha, p, product, projection, x, residual, &r);
    r_norm = r.norm();
    ++report.iterations;
    precondition(r, &z);
    const double rz_next = Dot(r, z);
    // A preconditioner that is not positive on r (or not finite) would mislead CG: give up.
    if (!(rz_next > 0.0)) break;
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  report.converged = r_norm <= threshold || accepted_early;
  report.relative_residual = reference > 0.0 ? r_norm / reference : 0.0;
  return report;
}

}  // namespace msm_sim::core
