#include "lattice/free_face_bending.h"

namespace msm_sim::core {

double FreeFaceBendingDeficit(int cells_across) {
  const double n = cells_across, n2 = n * n;
  return (2.0 / 3.0) / n2 + (1.0 / 3.0) * (10.0 / n2 - 12.0 / (n2 * n));
}

namespace lattice {

double DiagonalIncrementRatio(double poisson) { return poisson / (1.0 - poisson); }

std::optional<FreeFaceBending> FreeFaceBending::ForBox(const std::vector<Eigen::Vector3i>& coords,
                                                       double poisson) {
  if (coords.empty()) return std::nullopt;
  Eigen::Vector3i lo = coords.front(), hi = coords.front();
  for (const Eigen::Vector3i& c : coords) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  const Eigen::Vector3i layers = hi - lo + Eigen::Vector3i::Ones();
  if (static_cast<long long>(layers.x()) * layers.y() * layers.z() !=
      static_cast<long long>(coords.size())) {
    return std::nullopt;  // unique cells: as many as the box holds means they fill it
  }
  FreeFaceBending out;
  out.lo_ = lo;
  out.layers_ = layers;
  const double b_share = DiagonalIncrementRatio(poisson);
  for (int axis = 0; axis < 3; ++axis) {
    const int n = layers[axis];
    // Fewer than 4 layers: the interior (one layer at the axis, or none) cannot take the
    // compensation without its springs' stiffness turning negative.
    if (n < 4) continue;
    const double z_outer = 0.5 * (n - 1);  // cell centres at z_k = (k - (n - 1) / 2) a
    const double sum_all = n * (static_cast<double>(n) * n - 1.0) / 12.0;
    const double sum_interior = sum_all - 2.0 * z_outer * z_outer;
    const double s = 2.0 * z_outer * z_outer - (2.0 / (n - 2)) * sum_interior;
    // The outer layers' moment E alpha_A / 2 a S(n) a^2 per unit curvature and width puts back
    // deficit(n) E I = deficit(n) E (n a)^3 / 12.
    out.alpha_[axis] = FreeFaceBendingDeficit(n) * n * n * n / (6.0 * s);
    out.alpha_b_[axis] = b_share * out.alpha_[axis];
    // Every factor must stay positive (alpha_A = 1/2 at n = 4, 0.2 at n = 10; alpha_B lies
    // between -alpha_A / 2 and alpha_A for -1 < nu < 1/2).
    for (const double alpha : {out.alpha_[axis], out.alpha_b_[axis]}) {
      if (out.LayerFactor(axis, 0, alpha) <= 0.0 || out.LayerFactor(axis, 1, alpha) <= 0.0) {
        return std::nullopt;
      }
    }
  }
  if (out.alpha_.isZero()) return std::nullopt;
  return out;
}

double FreeFaceBending::Factor(const Eigen::Vector3i& from, const Eigen::Vector3i& d) const {
  // A spring lies in the layers of the axes along which it does not move: an A spring in two, a
  // B spring in one, a body diagonal in none.
  const bool b_spring = d.cwiseAbs().sum() == 2;
  double factor = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (alpha_[axis] == 0.0 || d[axis] != 0) continue;
    factor *= LayerFactor(axis, from[axis] - lo_[axis], b_spring ? alpha_b_[axis] : alpha_[axis]);
  }
  return factor;
}

double FreeFaceBending::LayerFactor(int axis, int layer, double alpha) const {
  const int n = layers_[axis];
  const bool outer = layer == 0 || layer == n - 1;
  return outer ? 1.0 + alpha : 1.0 - 2.0 * alpha / (n - 2);
}

}  // namespace lattice
}  // namespace msm_sim::core
