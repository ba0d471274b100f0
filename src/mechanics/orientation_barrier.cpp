#include "msm_sim/mechanics/orientation_barrier.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include <Eigen/Geometry>

#include "mechanics/barrier_corner.h"
#include "mechanics/simd_clones.h"

namespace msm_sim::core {
namespace {

using Corner = internal::BarrierCorner;

Corner Evaluate(const Eigen::Matrix3Xd& x, const std::array<NodeIndex, 4>& nodes,
                double inverse_rest_det) {
  return internal::EvaluateBarrierCorner(x, nodes, inverse_rest_det);
}

// J of `count` corners whose apexes are consecutive nodes from `apex` and whose ends are at
// fixed index offsets, from positions as x, y, z float arrays (relative to node 0: J to about
// 1e-7 of the body's extent over the spacing, ample for a threshold test; the forces are
// computed in double): unit-stride loads, so it vectorises
// (AVX2 + FMA clone where the CPU has it; the file is built without FP contraction, so both
// clones compute the same J). Returns the smallest, so that a run of healthy corners (nearly
// all of them) needs no second look.
MSM_SIM_SIMD_CLONES
float RunRatios(const float* xs, const float* ys, const float* zs, NodeIndex apex,
                const std::array<NodeIndex, 3>& offset, const float* inverse_rest_det, int count,
                float* ratio) {
  const float *px = xs + apex, *py = ys + apex, *pz = zs + apex;
  const float *ax = px + offset[0], *ay = py + offset[0], *az = pz + offset[0];
  const float *bx = px + offset[1], *by = py + offset[1], *bz = pz + offset[1];
  const float *cx = px + offset[2], *cy = py + offset[2], *cz = pz + offset[2];
  float smallest = std::numeric_limits<float>::infinity();
#pragma omp simd reduction(min : smallest)
  for (int t = 0; t < count; ++t) {
    const float e0x = ax[t] - px[t], e0y = ay[t] - py[t], e0z = az[t] - pz[t];
    const float e1x = bx[t] - px[t], e1y = by[t] - py[t], e1z = bz[t] - pz[t];
    const float e2x = cx[t] - px[t], e2y = cy[t] - py[t], e2z = cz[t] - pz[t];
    ratio[t] =
        inverse_rest_det[t] * (e0x * (e1y * e2z - e1z * e2y) + e0y * (e1z * e2x - e1x * e2z) +
                               e0z * (e1x * e2y - e1y * e2x));
    smallest = ratio[t] < smallest ? ratio[t] : smallest;
  }
  return smallest;
}

}  // namespace

OrientationBarrier::OrientationBarrier(const Model& model, double modulus, double threshold)
    : threshold_(threshold) {
  if (!(modulus >= 0.0) || !std::isfinite(modulus)) {
    throw std::invalid_argument("the orientation barrier's modulus must be finite and >= 0");
  }
  if (!(threshold > 0.0 && threshold < 1.0)) {
    throw std::invalid_argument("the orientation barrier's threshold must be in (0, 1)");
  }
  const double edge = model.characteristic_length();
  const double tolerance = 1e-6;
  const auto& rest = model.rest_positions();
  const auto& offsets = model.incidence_offsets();
  const auto& incident = model.incident_springs();
  std::vector<NodeIndex> neighbours;
  std::vector<Eigen::Vector3d> directions;
  for (NodeIndex p = 0; p < model.num_nodes(); ++p) {
    neighbours.clear();
    directions.clear();
    for (int k = offsets[p]; k < offsets[p + 1]; ++k) {
      const SpringIndex s = incident[k];
      const NodeIndex other =
          model.spring_node_a()[s] == p ? model.spring_node_b()[s] : model.spring_node_a()[s];
      const Eigen::Vector3d d = rest.col(other) - rest.col(p);
      if (std::abs(d.norm() - edge) > tolerance * edge) continue;
      neighbours.push_back(other);
      directions.push_back(d / edge);
    }
    const int count = static_cast<int>(neighbours.size());
    for (int i = 0; i < count; ++i) {
      for (int j = i + 1; j < count; ++j) {
        if (std::abs(directions[i].dot(directions[j])) > tolerance) continue;
        for (int k = j + 1; k < count; ++k) {
          if (std::abs(directions[i].dot(directions[k])) > tolerance ||
              std::abs(directions[j].dot(directions[k])) > tolerance) {
            continue;
          }
          // Ends in index order, whatever the order of the node's springs, so that a lattice
          // row's corners share their offsets; the sign of the rest triple product then goes
          // into 1 / det0 instead of the order.
          std::array<NodeIndex, 4> nodes = {p, neighbours[i], neighbours[j], neighbours[k]};
          std::sort(nodes.begin() + 1, nodes.end());
          Eigen::Matrix3d edges;
          for (int e = 0; e < 3; ++e) edges.col(e) = rest.col(nodes[e + 1]) - rest.col(p);
          const double rest_det = edges.determinant();
          corners_.push_back(nodes);
          inverse_rest_det_.push_back(1.0 / rest_det);
          coefficient_.push_back(modulus * std::abs(rest_det) / 8.0);
        }
      }
    }
  }
  SortIntoRuns();
  IndexCornersByNode(model.num_nodes());
}

void OrientationBarrier::SortIntoRuns() {
  // Corners with the same neighbour offsets at consecutive apexes (a lattice row) form a run
  // whose loads are unit-stride: the screen below then vectorises.
  const auto key = [&](int c) {
    const auto& n = corners_[c];
    return std::make_tuple(n[1] - n[0], n[2] - n[0], n[3] - n[0], n[0]);
  };
  std::vector<int> order(corners_.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  std::vector<std::array<NodeIndex, 4>> corners(order.size());
  std::vector<double> inverse_rest_det(order.size()), coefficient(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    corners[i] = corners_[order[i]];
    inverse_rest_det[i] = inverse_rest_det_[order[i]];
    coefficient[i] = coefficient_[order[i]];
  }
  corners_ = std::move(corners);
  inverse_rest_det_ = std::move(inverse_rest_det);
  coefficient_ = std::move(coefficient);
  // The screen's runs: a run goes on across a gap of up to kMaxGap apexes without a corner of
  // its offsets (the end of a lattice row), padded with slots whose 1 / det0 is NaN, which no
  // comparison selects. The apexes in a gap lie between two valid ones, and so do their
  // neighbours' indices. Long runs keep the vector loop out of its scalar remainder.
  constexpr int kMaxGap = 16;
  runs_.clear();
  screen_inverse_rest_det_.clear();
  screen_corner_.clear();
  for (int c = 0; c < num_corners(); ++c) {
    const auto& n = corners_[c];
    const std::array<NodeIndex, 3> offset = {n[1] - n[0], n[2] - n[0], n[3] - n[0]};
    if (!runs_.empty()) {
      CornerRun& run = runs_.back();
      const NodeIndex next = run.apex + run.length;  // the apex the run would take next
      if (offset == run.offset && n[0] >= next && n[0] - next <= kMaxGap) {
        for (; run.length < n[0] - run.apex; ++run.length) {
          screen_inverse_rest_det_.push_back(std::numeric_limits<float>::quiet_NaN());
          screen_corner_.push_back(-1);
        }
        ++run.length;
        screen_inverse_rest_det_.push_back(static_cast<float>(inverse_rest_det_[c]));
        screen_corner_.push_back(c);
        continue;
      }
    }
    runs_.push_back({static_cast<int>(screen_corner_.size()), n[0], 1, offset});
    screen_inverse_rest_det_.push_back(static_cast<float>(inverse_rest_det_[c]));
    screen_corner_.push_back(c);
  }
}

template <typename Visit>
void OrientationBarrier::ForEachBelowThreshold(const Eigen::Matrix3Xd& positions,
                                               Visit&& visit) const {
  // The positions as x, y, z arrays relative to node 0, in a buffer each thread keeps (the
  // barrier may be shared).
  thread_local std::vector<float> arrays;
  const Eigen::Index n = positions.cols();
  if (n == 0) return;
  arrays.resize(3 * n);
  float* xs = arrays.data();
  const Eigen::Vector3d origin = positions.col(0);
  for (Eigen::Index i = 0; i < n; ++i) {
    xs[i] = static_cast<float>(positions(0, i) - origin.x());
    xs[n + i] = static_cast<float>(positions(1, i) - origin.y());
    xs[2 * n + i] = static_cast<float>(positions(2, i) - origin.z());
  }
  constexpr int kChunk = 256;
  float ratio[kChunk];
  // The float J is within about 1e-5 of the double one for bodies up to a few hundred
  // spacings across: screening 1e-3 above the threshold misses no corner the double J puts
  // below it, and the decision itself is taken in double.
  const auto threshold = static_cast<float>(threshold_ + 1e-3);
  for (const CornerRun& run : runs_) {
    for (int begin = 0; begin < run.length; begin += kChunk) {
      const int count = std::min(kChunk, run.length - begin);
      const int slot = run.slot + begin;
      const float smallest = RunRatios(xs, xs + n, xs + 2 * n, run.apex + begin, run.offset,
                                       screen_inverse_rest_det_.data() + slot, count, ratio);
      if (!(smallest < threshold)) continue;
      for (int t = 0; t < count; ++t) {
        if (!(ratio[t] < threshold)) continue;
        const int c = screen_corner_[slot + t];
        // Decided in double, so that the barrier acts exactly below its threshold.
        const Corner corner = Evaluate(positions, corners_[c], inverse_rest_det_[c]);
        if (corner.ratio < threshold_) visit(c, corner);
      }
    }
  }
}

Eigen::VectorXd OrientationBarrier::VolumeRatios(const Eigen::Matrix3Xd& positions) const {
  Eigen::VectorXd ratios(num_corners());
  for (int c = 0; c < num_corners(); ++c) {
    ratios[c] = Evaluate(positions, corners_[c], inverse_rest_det_[c]).ratio;
  }
  return ratios;
}

void OrientationBarrier::AccumulateForces(const Eigen::Matrix3Xd& positions,
                                          Eigen::Matrix3Xd* forces) const {
  ForEachBelowThreshold(positions, [&](int c, const Corner& corner) {
    // f = -dW/dx = c (threshold - J) dJ/dx: pushes J back up.
    const double push = coefficient_[c] * (threshold_ - corner.ratio);
    for (int i = 0; i < 4; ++i) forces->col(corners_[c][i]) += push * corner.gradient[i];
  });
}

double OrientationBarrier::Energy(const Eigen::Matrix3Xd& positions) const {
  double energy = 0.0;
  ForEachBelowThreshold(positions, [&](int c, const Corner& corner) {
    energy += 0.5 * coefficient_[c] * std::pow(threshold_ - corner.ratio, 2);
  });
  return energy;
}

std::vector<int> OrientationBarrier::ActiveCorners(const Eigen::Matrix3Xd& positions) const {
  std::vector<int> active;
  ForEachBelowThreshold(positions, [&](int c, const Corner&) { active.push_back(c); });
  return active;
}

void OrientationBarrier::AddStiffnessProduct(const Eigen::Matrix3Xd& positions,
                                             const std::vector<int>& active, bool with_curvature,
                                             const Eigen::Matrix3Xd& v,
                                             Eigen::Matrix3Xd* out) const {
  for (const int c : active) {
    const auto& nodes = corners_[c];
    const Corner corner = Evaluate(positions, nodes, inverse_rest_det_[c]);
    double rate = 0.0;  // dJ = grad J . v
    for (int i = 0; i < 4; ++i) rate += corner.gradient[i].dot(v.col(nodes[i]));
    for (int i = 0; i < 4; ++i) out->col(nodes[i]) += coefficient_[c] * rate * corner.gradient[i];
    if (!with_curvature) continue;
    // d(grad J) along v: the triple product is linear in each edge, so only mixed terms.
    Eigen::Vector3d de[3];
    for (int i = 0; i < 3; ++i) de[i] = v.col(nodes[i + 1]) - v.col(nodes[0]);
    const double h = inverse_rest_det_[c];
    Eigen::Vector3d dgrad[4];
    dgrad[1] = h * (de[1].cross(corner.e[2]) + corner.e[1].cross(de[2]));
    dgrad[2] = h * (de[2].cross(corner.e[0]) + corner.e[2].cross(de[0]));
    dgrad[3] = h * (de[0].cross(corner.e[1]) + corner.e[0].cross(de[1]));
    dgrad[0] = -(dgrad[1] + dgrad[2] + dgrad[3]);
    // K = c grad J grad J^T - c (threshold - J) d^2 J / dx^2.
    const double bend = coefficient_[c] * (threshold_ - corner.ratio);
    for (int i = 0; i < 4; ++i) out->col(nodes[i]) -= bend * dgrad[i];
  }
}

void OrientationBarrier::AddStiffnessDiagonal(const Eigen::Matrix3Xd& positions,
                                              const std::vector<int>& active,
                                              Eigen::Matrix3Xd* diagonal) const {
  for (const int c : active) {
    const Corner corner = Evaluate(positions, corners_[c], inverse_rest_det_[c]);
    for (int i = 0; i < 4; ++i) {
      diagonal->col(corners_[c][i]) += coefficient_[c] * corner.gradient[i].cwiseAbs2();
    }
  }
}

}  // namespace msm_sim::core
