#include "mechanics/masked_pcg.h"

#include <algorithm>
#include <cmath>

namespace msm_sim::core {
namespace {

// Sum of the elementwise products (Frobenius inner product of two 3 x N arrays).
double Dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return a.cwiseProduct(b).sum(); }

}  // namespace

MaskedPcgReport SolveMaskedPcg(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                               const Eigen::Matrix3Xd& free,
                               const Eigen::Matrix3Xd& inverse_diagonal,
                               const MaskedPcgOptions& options, Eigen::Matrix3Xd* x,
                               Eigen::Matrix3Xd* residual) {
  MaskedPcgReport report;
  Eigen::Matrix3Xd product(3, x->cols());
  apply(*x, &product);
  *residual = b - product;
  Eigen::Matrix3Xd r = free.cwiseProduct(*residual);
  const double reference =
      std::max({free.cwiseProduct(b).norm(), r.norm(), options.reference_norm});
  const double threshold = options.relative_tolerance * reference;
  double r_norm = r.norm();
  Eigen::Matrix3Xd z = inverse_diagonal.cwiseProduct(r);
  Eigen::Matrix3Xd p = z;
  double rz = Dot(r, z);
  while (r_norm > threshold && report.iterations < options.max_iterations) {
    apply(p, &product);  // p is zero on the fixed DOFs, so this is A_free,free p on the free ones
    const double curvature = Dot(p, product);
    if (!(curvature > 0.0)) break;  // A not positive along p (or not finite): give up
    const double alpha = rz / curvature;
    *x += alpha * p;
    *residual -= alpha * product;
    r = free.cwiseProduct(*residual);
    r_norm = r.norm();
    ++report.iterations;
    z = inverse_diagonal.cwiseProduct(r);
    const double rz_next = Dot(r, z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  report.converged = r_norm <= threshold;
  report.relative_residual = reference > 0.0 ? r_norm / reference : 0.0;
  return report;
}

}  // namespace msm_sim::core
