#pragma once

#include <Eigen/Core>

#include "mechanics/node_shares.h"
#include "mechanics/share_plan.h"
#include "mechanics/single_precision_kernels.h"
#include "msm_sim/mechanics/cache_line_allocator.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/orientation_barrier.h"

namespace msm_sim::core::internal {

/// What a single-precision evaluation reads: the model's springs as the single loops take them
/// (docs/physics.md §9), the state, the caller's stages and the evaluator's settings.
struct SingleInputs {
  const Model* model;
  const SinglePrecisionSprings* springs;
  const Eigen::Matrix3Xd* positions;
  const double* velocities;           // 3 x N column-major; null: no dampers
  double beta;                        // the dampers' beta (s)
  const NodeStages* stages;           // null: none
  const OrientationBarrier* barrier;  // null: none
  const double* inverse_star_weight;  // 1 / W per node (docs/physics.md §3)
  bool overwrite;                     // store the forces (SetForces) rather than add them
};

/// Where it writes besides the forces: the barrier's forces and its skip test's state (scratch).
struct SingleOutputs {
  Eigen::Matrix3Xd* forces;
  Eigen::Matrix3Xd* barrier_forces;
  BarrierReference* barrier_reference;
};

/// The stage pipeline of the single-precision loops: which pass runs on which node share in
/// which order, and what one evaluation takes ahead of the next (NodeStages::rounds_ahead).
/// Holds the float node arrays and what was taken ahead, so use one per evaluator.
class SinglePasses {
 public:
  /// One evaluation on the shares of `plan`. Its sums depend on the plan's shares only.
  void Evaluate(const SharePlan& plan, const SingleInputs& in, const SingleOutputs& out);
  /// ForceEvaluator::RoundNodes for `springs`' node arrays (velocities null: no dampers).
  void Round(const SinglePrecisionSprings& springs, const double* positions,
             const double* velocities, int begin, int end, const double origin[3]);
  /// Forgets what the last evaluation took ahead: the shares, the barrier or the precision
  /// changed, so the next evaluation computes everything itself.
  void ForgetAhead() { ahead_ = TakenAhead{}; }

 private:
  friend class SingleEvaluation;
  // What the last evaluation took ahead of the next (NodeStages::rounds_ahead), for one with
  // NodeStages::rounded: the eMSM first pass (J's accumulators), and on two shares or more the
  // last share's part of the passes after it from node early_from on (-1: none), with dampers
  // of that beta (0: none).
  struct TakenAhead {
    bool taken = false;
    int early_from = -1;
    float beta = 0.0f;
  };
  TakenAhead ahead_;
  bool barrier_added_ = false;  // the last evaluation's barrier forces, not yet zeroed
  // Positions, velocities, the a ends' and the b ends' forces as x, y, z blocks of N each, at
  // Stride() floats apart; the accumulators of the a and b ends and g = J / W the same; from the
  // start of a cache line (SinglePrecisionSprings::kAlignment). Past N: zeros (the blocks'
  // phantoms reach there).
  CacheLineFloats nodes_, accumulators_, dispersion_;
  // Per share: its overflow of the b ends' forces (x, y, z) and of J_b, max_offset each, at
  // max_offset rounded up to a cache line apart.
  CacheLineFloats overflows_;
};

/// Floats from one x, y or z block of the single loops' node arrays to the next: the nodes the
/// loops reach (SinglePrecisionSprings::PaddedNodes), rounded up so that each block starts a
/// cache line.
inline long SingleStride(const SinglePrecisionSprings& springs) {
  return WholeCacheLinesOfFloats(springs.PaddedNodes());
}

}  // namespace msm_sim::core::internal
