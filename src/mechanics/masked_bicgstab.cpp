#include <cmath>

#include "mechanics/node_array_krylov.h"

namespace msm_sim::core {
namespace {

double Dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return a.cwiseProduct(b).sum(); }

}  // namespace

MaskedPcgReport SolveMaskedBiCgStab(const NodeArrayOperator& apply, const Eigen::Matrix3Xd& b,
                                    const Eigen::Matrix3Xd& free,
                                    const Eigen::Matrix3Xd& inverse_diagonal,
                                    const MaskedPcgOptions& options, Eigen::Matrix3Xd* x) {
  MaskedPcgReport report;
  x->setZero(3, b.cols());
  // A restricted to the free DOFs: the product of a free-masked vector, masked.
  const auto free_product = [&](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    apply(v, out);
    *out = out->cwiseProduct(free);
  };
  Eigen::Matrix3Xd r = b.cwiseProduct(free);
  const Eigen::Matrix3Xd shadow = r;
  const double threshold = options.relative_tolerance * r.norm();
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Zero(3, b.cols()), v = p, y, z, s, t(3, b.cols());
  double rho = 1.0, alpha = 1.0, omega = 1.0;
  double r_norm = r.norm();
  while (r_norm > threshold && report.iterations < options.max_iterations) {
    const double rho_next = Dot(shadow, r);
    if (!(std::abs(rho_next) > 0.0)) break;  // breakdown: the shadow is orthogonal to r
    p = r + (rho_next / rho) * (alpha / omega) * (p - omega * v);
    rho = rho_next;
    y = inverse_diagonal.cwiseProduct(p);
    free_product(y, &v);
    alpha = rho / Dot(shadow, v);
    s = r - alpha * v;
    z = inverse_diagonal.cwiseProduct(s);
    free_product(z, &t);
    const double tt = Dot(t, t);
    omega = tt > 0.0 ? Dot(t, s) / tt : 0.0;
    *x += alpha * y + omega * z;
    r = s - omega * t;
    r_norm = r.norm();
    ++report.iterations;
    if (!std::isfinite(r_norm) || omega == 0.0) break;
  }
  report.converged = r_norm <= threshold;
  report.relative_residual =
      threshold > 0.0 ? r_norm * options.relative_tolerance / threshold : 0.0;
  return report;
}

}  // namespace msm_sim::core
