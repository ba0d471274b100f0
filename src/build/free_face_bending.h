#pragma once
// Private to msm_sim's lattice builders: the free faces' bending correction of a node-centred
// cubic lattice that fills a box (docs/physics.md §2.1 "Free faces in bending").

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/build/cubic_lattice_builder.h"

namespace msm_sim::core::lattice {

/// How much a layer's uniaxial-stress modulus E_layer / E rises per unit alpha when its in-layer
/// springs (A and B springs lying in the layer) are scaled by 1 + alpha: the layer's stiffness
/// tensor (direct springs lambda = mu, plus the eMSM dispersion's lambda - mu) gains alpha mu in
/// C_1111 and C_2222 from the A springs and alpha mu in C_1111, C_2222 and C_1122 from the B
/// springs, and E_layer = 1 / S_1111 (the layer free to contract laterally). 1 at nu = 0, 0.65 at
/// nu = 1/4, 0.503 at nu = 0.49. Precondition: -1 < nu < 1/2.
double InLayerModulusSensitivity(double poisson);

/// Per-spring stiffness factors that restore the bending stiffness of a box's free faces without
/// changing the box's stiffness tensor. Along each axis with n >= 4 layers of cells,
/// springs lying in an outer layer (both ends in it) are scaled by 1 + alpha and springs lying in
/// an interior layer by 1 - 2 alpha / (n - 2): every layer keeps its summed stiffness (hence the
/// block's stiffness tensor and an interior node's balance under any uniform strain; the free
/// edges move a compression test by a few tenths of a percent), while the outer layers, at the
/// largest lever arm, gain alpha = deficit(n) n^3 / (12 c S(n)), S(n) = sum over layers of the
/// weights times (z_k / a)^2, which puts back the deficit. A spring lying in layers of several axes
/// takes the sum of their increments.
class FreeFaceBending {
 public:
  /// The correction for `coords` (integer cell coordinates, unique), or none if the cells do not
  /// fill their bounding box (a mesh, a rotated lattice), no axis has 4 layers, or a spring in
  /// the interior layers of two axes would not keep a positive stiffness.
  static std::optional<FreeFaceBending> ForBox(const std::vector<Eigen::Vector3i>& coords,
                                               double poisson);

  /// The factor of a spring from the cell at `from` along `d` (its other end, or a missing
  /// neighbour replaced by a face anchor, at from + d).
  double Factor(const Eigen::Vector3i& from, const Eigen::Vector3i& d) const;

  /// alpha per axis (0 where the axis has fewer than 4 layers).
  const Eigen::Vector3d& alpha() const { return alpha_; }

 private:
  // What a spring lying in an interior layer of `axis` loses: 2 alpha / (n - 2), so that the
  // layers' sum is unchanged (0 for an axis left alone).
  double InteriorDecrement(int axis) const;

  Eigen::Vector3i lo_ = Eigen::Vector3i::Zero();
  Eigen::Vector3i layers_ = Eigen::Vector3i::Zero();
  Eigen::Vector3d alpha_ = Eigen::Vector3d::Zero();
};

}  // namespace msm_sim::core::lattice
