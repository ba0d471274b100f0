// The orientation barrier's skip test (docs/physics.md §4 "Orientation barrier"): a corner is
// evaluated only when a node of it has moved, net of a common translation, farther from the last
// full check's positions than a bound that provably keeps its J at or above the threshold.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mechanics/barrier_corner.h"
#include "mechanics/simd_clones.h"
#include "msm_sim/mechanics/orientation_barrier.h"

namespace msm_sim::core {
namespace {

// Of J, left below a skipped corner's bound for the rounding of J and of the positions in
// double (about 1e-12 of J for a body within 100 m of the origin at 1 mm spacing).
constexpr double kMargin = 1e-3;

// The squared distance each node of `corner` may move, net of a translation common to its four
// nodes, while its J stays above threshold + kMargin; negative where it is not above it now.
// The triple product is linear in each edge and |det(a, b, c)| <= |a| |b| |c|, so edges that
// change by at most 2 d each move det(e) by at most (L + 2 d)^3 - L^3, L the longest edge.
double SquaredAllowance(const internal::BarrierCorner& corner, double inverse_rest_det,
                        double threshold) {
  const double slack = corner.ratio - threshold - kMargin;
  if (!(slack > 0.0)) return -1.0;
  double longest = 0.0;
  for (const Eigen::Vector3d& e : corner.e) longest = std::max(longest, e.norm());
  const double cube = longest * longest * longest;
  const double d = 0.5 * (std::cbrt(cube + slack / std::abs(inverse_rest_det)) - longest);
  return d > 0.0 ? d * d : 0.0;
}

// Whether node i of x (3 x N) has moved from r by more than its allowance net of `shift`; NaN
// counts as moved. Its displacement goes to u.
inline bool Moved(const double* x, const double* r, const double* allowance, const double* shift,
                  long i, double u[3]) {
  for (int d = 0; d < 3; ++d) u[d] = x[3 * i + d] - r[3 * i + d];
  const double dx = u[0] - shift[0], dy = u[1] - shift[1], dz = u[2] - shift[2];
  return !(dx * dx + dy * dy + dz * dz <= allowance[i]);
}

// The number of the n nodes that Moved, and the sum of their displacements into sum[3]: one
// vectorised pass (Moved's arithmetic written out, in its order, so that it vectorises; no FP
// contraction in this file, so every clone decides as Moved does).
MSM_SIM_SIMD_CLONES
long CountMoved(const double* x, const double* r, const double* allowance, long n,
                const double* shift, double* sum) {
  const double s0 = shift[0], s1 = shift[1], s2 = shift[2];
  double sx = 0.0, sy = 0.0, sz = 0.0;
  long moved = 0;
#pragma omp simd reduction(+ : sx, sy, sz, moved)
  for (long i = 0; i < n; ++i) {
    const double ux = x[3 * i] - r[3 * i], uy = x[3 * i + 1] - r[3 * i + 1],
                 uz = x[3 * i + 2] - r[3 * i + 2];
    sx += ux;
    sy += uy;
    sz += uz;
    const double dx = ux - s0, dy = uy - s1, dz = uz - s2;
    moved += dx * dx + dy * dy + dz * dz <= allowance[i] ? 0 : 1;  // NaN: moved
  }
  sum[0] = sx;
  sum[1] = sy;
  sum[2] = sz;
  return moved;
}

}  // namespace

void OrientationBarrier::IndexCornersByNode(NodeIndex num_nodes) {
  node_corner_offsets_.assign(num_nodes + 1, 0);
  for (const auto& corner : corners_) {
    for (const NodeIndex node : corner) ++node_corner_offsets_[node + 1];
  }
  for (NodeIndex i = 0; i < num_nodes; ++i) node_corner_offsets_[i + 1] += node_corner_offsets_[i];
  node_corners_.resize(node_corner_offsets_.back());
  std::vector<int> next(node_corner_offsets_.begin(), node_corner_offsets_.end() - 1);
  for (int c = 0; c < num_corners(); ++c) {
    for (const NodeIndex node : corners_[c]) node_corners_[next[node]++] = c;
  }
}

template <typename Visit>
void OrientationBarrier::FullCheck(const Eigen::Matrix3Xd& positions, BarrierReference* reference,
                                   Visit&& visit) const {
  const Eigen::Index n = positions.cols();
  reference->positions = positions;
  reference->allowance.setConstant(n, std::numeric_limits<double>::infinity());
  reference->marked.assign((corners_.size() + 63) / 64, 0);
  reference->moved_corners = 0;
  reference->shift.setZero();
  double* allowance = reference->allowance.data();
  for (int c = 0; c < num_corners(); ++c) {
    const internal::BarrierCorner corner =
        internal::EvaluateBarrierCorner(positions, corners_[c], inverse_rest_det_[c]);
    const double own = SquaredAllowance(corner, inverse_rest_det_[c], threshold_);
    for (const NodeIndex node : corners_[c]) {
      // A negative allowance (none) wins over every distance.
      allowance[node] = own < 0.0 || allowance[node] < 0.0 ? -1.0 : std::min(allowance[node], own);
    }
    if (corner.ratio < threshold_) visit(c, corner);
  }
}

void OrientationBarrier::MarkMovedCorners(const Eigen::Matrix3Xd& positions,
                                          BarrierReference* reference) const {
  const long n = positions.cols();
  const double* x = positions.data();
  const double* r = reference->positions.data();
  const double* allowance = reference->allowance.data();
  // Moves are taken net of the last call's mean displacement: any translation common to all
  // nodes keeps the bound (J does not change under it), and this one follows a carried body.
  const Eigen::Vector3d shift = reference->shift;
  double sum[3];
  const long moved = CountMoved(x, r, allowance, n, shift.data(), sum);
  reference->shift = Eigen::Vector3d(sum[0], sum[1], sum[2]) / static_cast<double>(n);
  if (moved == 0) return;
  std::uint64_t* marked = reference->marked.data();
  for (long i = 0; i < n; ++i) {
    double u[3];
    if (!Moved(x, r, allowance, shift.data(), i, u)) continue;
    const int begin = node_corner_offsets_[i], end = node_corner_offsets_[i + 1];
    for (int k = begin; k < end; ++k) {
      const int c = node_corners_[k];
      marked[c / 64] |= std::uint64_t{1} << (c % 64);
    }
    if (allowance[i] >= 0.0) reference->moved_corners += end - begin;
  }
}

template <typename Visit>
void OrientationBarrier::ForEachBelowThreshold(const Eigen::Matrix3Xd& positions,
                                               BarrierReference* reference, Visit&& visit) const {
  if (corners_.empty()) return;
  // A new full check once the corners evaluated for moved nodes add up to one: the reference
  // then follows the body's shape, and the test never costs more than twice the full checks.
  if (reference->positions.cols() != positions.cols() ||
      reference->moved_corners >= num_corners()) {
    FullCheck(positions, reference, visit);
    return;
  }
  MarkMovedCorners(positions, reference);
  // In corner order, as the full evaluation visits them, so that the forces sum alike.
  std::vector<std::uint64_t>& marked = reference->marked;
  for (std::size_t w = 0; w < marked.size(); ++w) {
    for (std::uint64_t bits = marked[w]; bits != 0; bits &= bits - 1) {
      const int c = static_cast<int>(64 * w) + __builtin_ctzll(bits);
      const internal::BarrierCorner corner =
          internal::EvaluateBarrierCorner(positions, corners_[c], inverse_rest_det_[c]);
      if (corner.ratio < threshold_) visit(c, corner);
    }
    marked[w] = 0;
  }
}

int OrientationBarrier::AccumulateForces(const Eigen::Matrix3Xd& positions,
                                         Eigen::Matrix3Xd* forces,
                                         BarrierReference* reference) const {
  int added = 0;
  ForEachBelowThreshold(positions, reference, [&](int c, const internal::BarrierCorner& corner) {
    // f = -dW/dx = c (threshold - J) dJ/dx, as the full evaluation adds it.
    const double push = coefficient_[c] * (threshold_ - corner.ratio);
    for (int i = 0; i < 4; ++i) forces->col(corners_[c][i]) += push * corner.gradient[i];
    ++added;
  });
  return added;
}

std::vector<int> OrientationBarrier::ActiveCorners(const Eigen::Matrix3Xd& positions,
                                                   BarrierReference* reference) const {
  std::vector<int> active;
  ForEachBelowThreshold(positions, reference,
                        [&](int c, const internal::BarrierCorner&) { active.push_back(c); });
  return active;
}

}  // namespace msm_sim::core
