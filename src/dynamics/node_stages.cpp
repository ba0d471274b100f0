// The per-node stages both integrators share (node_stages.h). Compiled without contraction into
// FMAs (CMakeLists.txt): the AVX2 clones then compute exactly what the baseline build does.
#include "dynamics/node_stages.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mechanics/node_shares.h"
#include "mechanics/simd_clones.h"

namespace msm_sim::core::internal {
namespace {

// The per-node loops of the drifts, with AVX2 clones as the spring loops: compiled for baseline
// x86-64 alone they were a tenth of a substep.

// x += tau v over `count` coordinates.
MSM_SIM_SIMD_CLONES
void Drift(long count, double tau, const double* v, double* x) {
  const double* __restrict from = v;
  double* __restrict to = x;
  for (long j = 0; j < count; ++j) to[j] += tau * from[j];
}

// The same, first copying x and v into saved_x and saved_v: the step's first drift saves the
// state for a rejected step as it reads it, saving a pass over the nodes
// (docs/design/threads-default.md).
MSM_SIM_SIMD_CLONES
void SaveAndDrift(long count, double tau, const double* v, double* x, double* saved_v,
                  double* saved_x) {
  const double* __restrict from = v;
  double* __restrict to = x;
  double* __restrict v_copy = saved_v;
  double* __restrict x_copy = saved_x;
  for (long j = 0; j < count; ++j) {
    x_copy[j] = to[j];
    v_copy[j] = from[j];
    to[j] += tau * from[j];
  }
}

// The same as Drift, also returning the largest |velocity component| and x - x summed (0 while
// every x is finite, NaN once one is not; a NaN velocity makes x NaN too). kTwice: then Drift
// again with the same v, x = (x + tau v) + tau v in one pass, each sum rounded as two passes
// round it (the file is compiled without contraction), the extremes those of the first.
template <bool kTwice>
inline __attribute__((always_inline)) void DriftNoting(long count, double tau, const double* v,
                                                       double* x, double* fastest_component,
                                                       double* nonfinite) {
  const double* __restrict from = v;
  double* __restrict to = x;
  double fastest = 0.0, sum = 0.0;
#pragma omp simd reduction(max : fastest) reduction(+ : sum)
  for (long j = 0; j < count; ++j) {
    const double once = to[j] + tau * from[j];
    fastest = std::max(fastest, std::abs(from[j]));
    sum += once - once;
    to[j] = kTwice ? once + tau * from[j] : once;
  }
  *fastest_component = fastest;
  *nonfinite = sum;
}

MSM_SIM_SIMD_CLONES
void DriftNotingExtremes(long count, double tau, const double* v, double* x,
                         double* fastest_component, double* nonfinite) {
  DriftNoting<false>(count, tau, v, x, fastest_component, nonfinite);
}

MSM_SIM_SIMD_CLONES
void DriftTwiceNotingExtremes(long count, double tau, const double* v, double* x,
                              double* fastest_component, double* nonfinite) {
  DriftNoting<true>(count, tau, v, x, fastest_component, nonfinite);
}

}  // namespace

void DriftHalf(Body* body, double h, const std::vector<Eigen::Isometry3d>& poses, int begin,
               int end, bool save) {
  const long count = 3L * (end - begin);
  const double* v = body->state.velocities.data() + 3L * begin;
  double* x = body->state.positions.data() + 3L * begin;
  if (save) {
    SaveAndDrift(count, 0.5 * h, v, x, body->saved_velocities.data() + 3L * begin,
                 body->saved_positions.data() + 3L * begin);
  } else {
    Drift(count, 0.5 * h, v, x);
  }
  PlaceGroupNodes(body, poses, begin, end);
}

void ApplyPendingRestitution(Body* body) {
  ApplyPendingRestitution(body, body->pending, 0, body->model->num_nodes());
  body->pending.clear();
}

void ApplyPendingRestitution(Body* body, const std::vector<PendingResponse>& rebounds, int begin,
                             int end) {
  for (const PendingResponse& response : rebounds) {
    if (response.node >= begin && response.node < end) {
      body->state.velocities.col(response.node) += response.delta_v;
    }
  }
}

void ComputeForces(Body* body) {
  body->evaluator.SetForces(body->state.positions, body->state.velocities,
                            body->options.damping_beta, &body->forces);
  AddPushes(body, 0, body->model->num_nodes());
}

void AddPushes(Body* body, int begin, int end) {
  for (const Push& push : body->pushes) {
    for (std::size_t k = 0; k < push.nodes.size(); ++k) {
      const NodeIndex node = push.nodes[k];
      if (node >= begin && node < end) body->forces.col(node) += push.forces[k];
    }
  }
}

void DriveKinematicGroups(Body* body, std::size_t num_colliders, double h, double t0) {
  const Eigen::VectorXd& m = body->model->masses();
  for (std::size_t g = 0; g < body->groups.size(); ++g) {
    const Group& group = body->groups[g];
    const Eigen::Isometry3d from = GroupPose(group, t0);
    const Eigen::Isometry3d to = GroupPose(group, t0 + h);
    const Eigen::Isometry3d mid = GroupPose(group, t0 + 0.5 * h);
    ImpulseSum& reaction = body->impulses[num_colliders + g];
    for (std::size_t k = 0; k < group.spec.nodes.size(); ++k) {
      const NodeIndex node = group.spec.nodes[k];
      const Eigen::Vector3d local = group.local.col(k);
      const Eigen::Vector3d prescribed = (to * local - from * local) / h;
      // The group gave the node m (v_prescribed - v_free); the node pushed back.
      const Eigen::Vector3d on_group =
          -m[node] * (prescribed - Eigen::Vector3d(body->state.velocities.col(node)));
      reaction.Add(body->state.positions.col(node), mid.translation(), on_group);
      body->state.velocities.col(node) = prescribed;
    }
  }
}

void DriftHalfNotingFastest(Body* body, double h, double t0, double max_speed) {
  // The drift also flags what the sanity check after the substep must look at: a velocity
  // component above max_speed / sqrt(3) (every node faster than max_speed has one) and any
  // non-finite value. One flat loop of reductions vectorises (tracking the fastest node in it
  // would not; docs/design/speed-against-bullet.md); the rare flagged substep finds the node in a
  // second pass.
  // Each node share on its own thread, as in DriftForceAndKick.
  std::vector<double> fastest(internal::NodeShares::Count(body->evaluator)),
      nonfinite(fastest.size());
  internal::NodeShares::ForEach(&body->evaluator, [&](int share, int begin, int end) {
    DriftShare(body, h, false, share, begin, end, &fastest, &nonfinite);
  });
  NoteDriftExtremes(body, fastest, nonfinite, t0 + h, max_speed);
}

void DriftShare(Body* body, double h, bool twice, int share, int begin, int end,
                std::vector<double>* fastest, std::vector<double>* nonfinite) {
  const auto drift = twice ? DriftTwiceNotingExtremes : DriftNotingExtremes;
  drift(3L * (end - begin), 0.5 * h, body->state.velocities.data() + 3L * begin,
        body->state.positions.data() + 3L * begin, &(*fastest)[share], &(*nonfinite)[share]);
}

void NoteDriftExtremes(Body* body, const std::vector<double>& fastest,
                       const std::vector<double>& nonfinite, double t, double max_speed) {
  const double component_limit = max_speed / std::sqrt(3.0);
  for (std::size_t share = 0; share < fastest.size(); ++share) {
    if (!(fastest[share] <= component_limit) || nonfinite[share] != 0.0) {
      NoteFastest(body);
      break;
    }
  }
  PlaceGroups(body, t);
}

void NoteFastest(Body* body) {
  const Eigen::Matrix3Xd& x = body->state.positions;
  const Eigen::Matrix3Xd& v = body->state.velocities;
  for (int i = 0; i < body->model->num_nodes(); ++i) {
    const double speed_sq = v.col(i).squaredNorm();
    const bool finite = std::isfinite(speed_sq) && x.col(i).allFinite();
    const double fastest = finite ? speed_sq : std::numeric_limits<double>::infinity();
    if (fastest > body->fastest_speed_sq) {
      body->fastest_speed_sq = fastest;
      body->fastest_node = i;
    }
  }
}

}  // namespace msm_sim::core::internal
