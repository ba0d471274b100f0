#pragma once
// Private to msm_sim's lattice builders: the free faces' bending correction of a node-centred
// cubic lattice that fills a box (docs/physics.md §2.1 "Free faces in bending").

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core::lattice {

/// The B springs' share of a layer's correction, alpha_B / alpha_A = nu / (1 - nu): the ratio
/// at which the springs added to a layer carry a uniaxial stress along the layer without any
/// lateral stress of their own when the layer contracts as the body does (lateral strain -nu
/// times the axial). A layer's A springs add alpha_A mu to C_1111 and C_2222, its B springs
/// alpha_B mu to C_1111, C_2222 and C_1122; then the added lateral stress mu eps (alpha_B (1 - nu)
/// - nu alpha_A) vanishes and the added axial one is mu eps alpha_A (1 + nu) = alpha_A E eps / 2.
/// Precondition: -1 < nu < 1/2.
double DiagonalIncrementRatio(double poisson);

/// Per-spring stiffness factors that restore the bending stiffness of a box's free faces without
/// changing the box's stiffness tensor. Along each axis with n >= 4 layers of cells, the A
/// springs lying in an outer layer (both ends in it) are scaled by 1 + alpha_A and those lying in
/// an interior layer by 1 - 2 alpha_A / (n - 2), the B springs likewise with alpha_B =
/// alpha_A nu / (1 - nu) (DiagonalIncrementRatio): every layer keeps its summed stiffness, hence
/// the block's stiffness tensor, and the added springs carry no lateral stress of their own under a
/// uniaxial stress (a compressed block stays uniformly strained). The outer layers, at the
/// largest lever arm, gain E alpha_A / 2 with alpha_A = deficit(n) n^3 / (6 S(n)), S(n) = sum over
/// layers of the weights times (z_k / a)^2, which puts back the deficit. A spring lying in layers
/// of two axes (an A spring) takes the product of their factors, which keeps every layer's sum
/// (the factors of the other axis sum to its layer count) and every factor positive.
class FreeFaceBending {
 public:
  /// The correction for `coords` (integer cell coordinates, unique), or none if the cells do not
  /// fill their bounding box (a mesh, a rotated lattice), no axis has 4 layers, or a layer's
  /// factor would not stay positive (which no -1 < nu < 1/2 gives with n >= 4).
  static std::optional<FreeFaceBending> ForBox(const std::vector<Eigen::Vector3i>& coords,
                                               double poisson);

  /// The factor of a spring from the cell at `from` along `d` (its other end, or a missing
  /// neighbour replaced by a face anchor, at from + d).
  double Factor(const Eigen::Vector3i& from, const Eigen::Vector3i& d) const;

  /// alpha_A per axis, the A springs' increment (0 where the axis has fewer than 4 layers).
  const Eigen::Vector3d& alpha() const { return alpha_; }
  /// alpha_B per axis, the B springs' increment: alpha_A nu / (1 - nu).
  const Eigen::Vector3d& alpha_b() const { return alpha_b_; }

 private:
  // The factor of a spring lying in `layer` of `axis` whose outer layers gain `alpha`: 1 + alpha
  // in an outer layer, 1 - 2 alpha / (n - 2) in an interior one, so that the layers' sum is
  // unchanged.
  double LayerFactor(int axis, int layer, double alpha) const;

  Eigen::Vector3i lo_ = Eigen::Vector3i::Zero();
  Eigen::Vector3i layers_ = Eigen::Vector3i::Zero();
  Eigen::Vector3d alpha_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d alpha_b_ = Eigen::Vector3d::Zero();
};

}  // namespace msm_sim::core::lattice
