#include "mechanics/node_array_krylov.h"

#include <algorithm>
#include <cmath>

namespace msm_sim::core {
namespace {

// Sum of the elementwise products (Frobenius inner product of two 3 x N arrays).
double Dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return a.cwiseProduct(b).sum(); }

// What a CG iteration's update leaves for the next: |r|^2 and r . z.
struct Advanced {
  double r_squared;
  double rz;
};

// The update after the product A p, in one sweep over the DOFs: x += alpha p, residual -=
// alpha A p, r = S residual, z = S D^-1 S r, with |r|^2 and r . z. The few nodes S projects onto
// a contact's plane are corrected after the sweep and only then summed: `summed` is `free` with
// their DOFs zero (a held normal's residual is the contact's force, which the sum must never see,
// or taking it out again would cancel the small rest).
Advanced Advance(double alpha, const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& product,
                 const DofProjection& projection, const Eigen::Matrix3Xd& summed,
                 const Eigen::Matrix3Xd& inverse_diagonal, Eigen::Matrix3Xd* x,
                 Eigen::Matrix3Xd* residual, Eigen::Matrix3Xd* r, Eigen::Matrix3Xd* z) {
  const Eigen::Index size = p.size();
  const double* __restrict free = projection.free.data();
  const double* __restrict counted = summed.data();
  const double* __restrict inverse = inverse_diagonal.data();
  const double* __restrict direction = p.data();
  const double* __restrict change = product.data();
  double* __restrict solution = x->data();
  double* __restrict full = residual->data();
  double* __restrict projected = r->data();
  double* __restrict preconditioned = z->data();
  double r_squared = 0.0, rz = 0.0;
#pragma omp simd reduction(+ : r_squared, rz)
  for (Eigen::Index j = 0; j < size; ++j) {
    solution[j] += alpha * direction[j];
    full[j] -= alpha * change[j];
    const double masked = free[j] * full[j];
    const double scaled = inverse[j] * masked;
    projected[j] = masked;
    preconditioned[j] = scaled;
    r_squared += counted[j] * masked * masked;
    rz += counted[j] * masked * scaled;
  }
  for (const DofProjection::NodeNormal& constraint : projection.normals) {
    auto r_node = r->col(constraint.node);
    auto z_node = z->col(constraint.node);
    r_node -= constraint.normal.dot(r_node) * constraint.normal;
    z_node = inverse_diagonal.col(constraint.node).cwiseProduct(r_node);
    z_node -= constraint.normal.dot(z_node) * constraint.normal;
    r_squared += r_node.squaredNorm();
    rz += r_node.dot(z_node);
  }
  return {r_squared, rz};
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
  // z = S D^-1 S r: symmetric, positive on the range of S, so CG stays in that range. r is in
  // that range, which D^-1 keeps free-masked: only the normals remain to apply.
  Eigen::Matrix3Xd z = inverse_diagonal.cwiseProduct(r);
  projection.ApplyNormals(&z);
  Eigen::Matrix3Xd p = z;
  Eigen::Matrix3Xd summed = projection.free;
  for (const DofProjection::NodeNormal& constraint : projection.normals) {
    summed.col(constraint.node).setZero();
  }
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
    const Advanced next =
        Advance(alpha, p, product, projection, summed, inverse_diagonal, x, residual, &r, &z);
    r_norm = std::sqrt(next.r_squared);
    ++report.iterations;
    // A preconditioner that is not positive on r (or not finite) would mislead CG: give up.
    if (!(next.rz > 0.0)) break;
    p = z + (next.rz / rz) * p;
    rz = next.rz;
  }
  report.converged = r_norm <= threshold || accepted_early;
  report.relative_residual = reference > 0.0 ? r_norm / reference : 0.0;
  return report;
}

}  // namespace msm_sim::core
