#include "build/free_face_bending.h"

#include <algorithm>

#include <Eigen/Dense>

namespace msm_sim::core {

double FreeFaceBendingDeficit(int cells_across) {
  const double n = cells_across, n2 = n * n;
  return (2.0 / 3.0) / n2 + (1.0 / 3.0) * (10.0 / n2 - 12.0 / (n2 * n));
}

namespace lattice {

double InLayerModulusSensitivity(double poisson) {
  // In units of mu: the eMSM stiffness tensor's normal block, the direct springs' (C_1111 = 3,
  // C_1122 = 1) plus the dispersion's lambda - 1 on every entry.
  const double lambda = 2.0 * poisson / (1.0 - 2.0 * poisson);
  Eigen::Matrix3d bulk = Eigen::Matrix3d::Constant(lambda - 1.0);
  bulk += (Eigen::Matrix3d() << 3, 1, 1, 1, 3, 1, 1, 1, 3).finished();
  // A_x, A_y: mu each in C_1111, C_2222; B_xy: mu in C_1111, C_2222, C_1122.
  const Eigen::Matrix3d in_layer = (Eigen::Matrix3d() << 2, 1, 0, 1, 2, 0, 0, 0, 0).finished();
  // E_layer = 1 / S_11 with S = C^-1; dS = -S dC S, so dE / E = (S dC S)_11 / S_11.
  const Eigen::Matrix3d compliance = bulk.inverse();
  return (compliance * in_layer * compliance)(0, 0) / compliance(0, 0);
}

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
  const double c = InLayerModulusSensitivity(poisson);
  for (int axis = 0; axis < 3; ++axis) {
    const int n = layers[axis];
    // Fewer than 4 layers: the interior (one layer at the axis, or none) cannot take the
    // compensation without its springs' stiffness turning negative.
    if (n < 4) continue;
    const double z_outer = 0.5 * (n - 1);  // cell centres at z_k = (k - (n - 1) / 2) a
    const double sum_all = n * (static_cast<double>(n) * n - 1.0) / 12.0;
    const double sum_interior = sum_all - 2.0 * z_outer * z_outer;
    const double s = 2.0 * z_outer * z_outer - (2.0 / (n - 2)) * sum_interior;
    out.alpha_[axis] = FreeFaceBendingDeficit(n) * n * n * n / (12.0 * c * s);
  }
  if (out.alpha_.isZero()) return std::nullopt;
  // The softest spring lies in interior layers of two axes.
  Eigen::Vector3d decrement;
  for (int axis = 0; axis < 3; ++axis) decrement[axis] = out.InteriorDecrement(axis);
  std::sort(decrement.data(), decrement.data() + 3);
  if (1.0 - decrement[1] - decrement[2] <= 0.0) return std::nullopt;
  return out;
}

double FreeFaceBending::Factor(const Eigen::Vector3i& from, const Eigen::Vector3i& d) const {
  double factor = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (alpha_[axis] == 0.0 || d[axis] != 0) continue;  // not lying in a layer of this axis
    const int layer = from[axis] - lo_[axis];
    const bool outer = layer == 0 || layer == layers_[axis] - 1;
    factor += outer ? alpha_[axis] : -InteriorDecrement(axis);
  }
  return factor;
}

double FreeFaceBending::InteriorDecrement(int axis) const {
  return alpha_[axis] == 0.0 ? 0.0 : 2.0 * alpha_[axis] / (layers_[axis] - 2);
}

}  // namespace lattice
}  // namespace msm_sim::core
