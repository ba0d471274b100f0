#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// What the orientation barrier's skip test keeps between evaluations of one simulated state
/// (docs/physics.md §4): the positions of the last full check and how far each node may move
/// from them, net of a common translation, before a corner of it could reach the threshold.
/// Held per evaluator, not by the barrier, which evaluators share. Empty: the next tracked
/// evaluation makes a full check.
struct BarrierReference {
  Eigen::Matrix3Xd positions;  // at the last full check
  Eigen::VectorXd allowance;   // per node: the squared distance; negative: none
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();  // the translation moves are taken net of
  std::vector<std::uint64_t> marked;  // scratch: the corners to evaluate, one bit each
  long moved_corners = 0;             // evaluated since the full check for a node that moved
};

/// An energy that knows which way a lattice cell faces (docs/physics.md §4 "Orientation
/// barrier"). A spring network has none: a cubic lattice folded so that a node layer has passed
/// its neighbour has the same spring lengths as the unfolded one, so nothing drives it back.
///
/// Each corner of a cubic lattice's cells (a node and its three lattice neighbours along
/// orthogonal edges) measures its volume ratio J = det(e1, e2, e3) / det(E1, E2, E3) of the
/// current edges e over the rest edges E: 1 at rest, negative once turned inside out. Below
/// `threshold` the corner stores W = 1/2 c (threshold - J)^2 with c = modulus * (rest cell volume /
/// 8), and nothing above: the small-strain calibration is untouched as long as no corner is
/// squeezed below the threshold. Only lattices with orthogonal edge springs have corners
/// (cubic node-centred, element-corner, Baudet, meshes built on them); random lattices have none.
class OrientationBarrier {
 public:
  /// The corners of every node of `model` whose springs of the characteristic length include
  /// three mutually orthogonal ones (within 1e-6), one per such triple.
  /// Preconditions: modulus >= 0 (Pa), threshold in (0, 1).
  OrientationBarrier(const Model& model, double modulus, double threshold);

  int num_corners() const { return static_cast<int>(corners_.size()); }
  /// The number of runs the corner screen takes (corners with equal offsets at nearby apexes).
  int num_runs() const { return static_cast<int>(runs_.size()); }
  double threshold() const { return threshold_; }
  const std::vector<std::array<NodeIndex, 4>>& corners() const { return corners_; }

  /// J of each corner at `positions` (3 x N).
  Eigen::VectorXd VolumeRatios(const Eigen::Matrix3Xd& positions) const;
  /// Adds the barrier's forces at `positions` to *forces (3 x N).
  void AccumulateForces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces) const;
  /// The same forces, bit for bit, evaluating only the corners of nodes that moved past their
  /// allowance since `reference`'s full check (and making one when the corners evaluated so add
  /// up to the barrier's): a skipped corner is provably at or above the threshold, where its
  /// force is zero (docs/physics.md §4). `reference` must be used with this barrier only.
  /// Returns the number of corners that added forces (those below the threshold).
  int AccumulateForces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces,
                       BarrierReference* reference) const;
  /// The barrier's energy at `positions` (J).
  double Energy(const Eigen::Matrix3Xd& positions) const;
  /// The corners below the threshold at `positions`: the ones the stiffness below involves.
  std::vector<int> ActiveCorners(const Eigen::Matrix3Xd& positions) const;
  /// The same list through `reference`'s skip test (as AccumulateForces above).
  std::vector<int> ActiveCorners(const Eigen::Matrix3Xd& positions,
                                 BarrierReference* reference) const;
  /// Adds K v to *out, K = d^2 W / dx^2 at `positions` over the `active` corners. With
  /// `with_curvature` false only the Gauss-Newton part c grad J grad J^T is kept (positive
  /// semi-definite); the left-out c (threshold - J) d^2 J / dx^2 has a zero diagonal.
  void AddStiffnessProduct(const Eigen::Matrix3Xd& positions, const std::vector<int>& active,
                           bool with_curvature, const Eigen::Matrix3Xd& v,
                           Eigen::Matrix3Xd* out) const;
  /// Adds the diagonal of K (exact: the curvature part has none) to *diagonal (3 x N).
  void AddStiffnessDiagonal(const Eigen::Matrix3Xd& positions, const std::vector<int>& active,
                            Eigen::Matrix3Xd* diagonal) const;

 private:
  /// Screen slots at consecutive apexes with the same neighbour offsets.
  struct CornerRun {
    int slot;        // its first slot in screen_inverse_rest_det_ and screen_corner_
    NodeIndex apex;  // the first slot's apex
    int length;      // slots, padding included
    std::array<NodeIndex, 3> offset;  // neighbour index minus apex index
  };
  /// Orders the corners by offsets and apex, and lays out the screen's runs.
  void SortIntoRuns();
  /// Calls visit(c, corner) for each corner c below the threshold at `positions`, in corner
  /// order, with its edges, J and gradient there (evaluated once, in double).
  template <typename Visit>
  void ForEachBelowThreshold(const Eigen::Matrix3Xd& positions, Visit&& visit) const;
  /// The same through `reference`'s skip test (orientation_barrier_tracking.cpp).
  template <typename Visit>
  void ForEachBelowThreshold(const Eigen::Matrix3Xd& positions, BarrierReference* reference,
                             Visit&& visit) const;
  /// Evaluates every corner, visiting those below the threshold, and makes `reference` anew.
  template <typename Visit>
  void FullCheck(const Eigen::Matrix3Xd& positions, BarrierReference* reference,
                 Visit&& visit) const;
  /// Marks the corners of the nodes that moved past their allowance in reference->marked.
  void MarkMovedCorners(const Eigen::Matrix3Xd& positions, BarrierReference* reference) const;
  /// Lists each node's corners (node_corner_offsets_, node_corners_).
  void IndexCornersByNode(NodeIndex num_nodes);

  std::vector<CornerRun> runs_;
  std::vector<std::array<NodeIndex, 4>> corners_;
  std::vector<double> inverse_rest_det_;  // 1 / det(E1, E2, E3), of either sign
  // Per screen slot: 1 / det0 in float (NaN for padding) and the corner (-1 for padding).
  std::vector<float> screen_inverse_rest_det_;
  std::vector<int> screen_corner_;
  std::vector<double> coefficient_;  // c (J)
  // The corners of node i: node_corners_[node_corner_offsets_[i] .. node_corner_offsets_[i + 1]).
  std::vector<int> node_corner_offsets_, node_corners_;
  double threshold_;
};

}  // namespace msm_sim::core
