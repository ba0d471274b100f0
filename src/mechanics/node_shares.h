#pragma once
// Private to msm_sim_core: the node shares of ForceEvaluator's single-precision loops and the
// per-node stages a caller (the explicit integrator, src/dynamics) runs on them, so that a
// share's nodes stay in its core's cache from one step to the next ("owner computes",
// docs/physics.md §9).

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core::internal {

/// Per-node work a caller does around SetForces on each node share's own thread.
/// `before(share, begin, end)` may change the positions and velocities of share `share`'s nodes
/// [begin, end) before SetForces reads them; `after(share, begin, end)` runs once their forces
/// are set and may read or change those forces and velocities. Neither may touch other nodes.
/// Shares are numbered 0 .. NodeShares::Count() - 1 in node order, as NodeShares::ForEach
/// numbers them. Where the loops have no shares (double precision, models below 1,000 nodes,
/// one thread) they are called once, with (0, 0, N), before and after the evaluation.
///
/// `after_unstored(share, begin, end, end_forces, stride)`, optional, replaces storing the
/// forces of nodes [begin, end) and `after` where the single-precision loops add no
/// barrier forces: it gets the springs' forces unsummed, node i's being the sum over d of
/// the float end_forces[d * stride + i] (its a ends) and end_forces[(3 + d) * stride + i] (its
/// b ends; stride >= N, where each block starts a cache line), each taken to double before
/// adding (as *forces would hold it), for d = x, y, z, and must do what `after` would with them.
/// *forces is then left unset for those nodes. (The explicit kick fused with the sums: the
/// forces are not written to memory and read back.)
struct NodeStages {
  std::function<void(int, int, int)> before;
  std::function<void(int, int, int)> after;
  std::function<void(int, int, int, const float*, long)> after_unstored;
  /// Optional: the point (x, y, z, m) the single loops round positions relative to; a float
  /// then resolves 6e-8 of a node's distance from it. Null: node 0's position at the call,
  /// before `before` moves it.
  const double* origin = nullptr;
  /// The caller has already done what `before` would and rounded every node with
  /// NodeShares::Round (relative to `origin`): the single loops skip `before` and their own
  /// rounding, one hand-over between threads fewer. Precondition: NodeShares::Rounds().
  bool rounded = false;
  /// The `after` stages round every node with NodeShares::Round (relative to `origin`) for the
  /// next SetForces, which will then have `rounded`: the single loops take that evaluation's
  /// first pass ahead, on each share once its `after` stage and those of the shares its springs
  /// reach have run (one hand-over between threads fewer).
  bool rounds_ahead = false;
};

/// The node shares of an evaluator's single loops (ForceEvaluator's friend).
class NodeShares {
 public:
  /// ForceEvaluator::SetForces with `stages` run on each share.
  static void SetForces(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& positions,
                        const Eigen::Matrix3Xd& velocities, double damping_beta,
                        Eigen::Matrix3Xd* forces, const NodeStages& stages);
  /// Runs task(share, begin, end) for each node share of SetForces' stages on its thread (one
  /// share (0, 0, N) where there are none). Preconditions as for the stages.
  static void ForEach(ForceEvaluator* evaluator, const std::function<void(int, int, int)>& task);
  /// The number of shares ForEach runs.
  static int Count(const ForceEvaluator& evaluator);
  /// Cuts the node shares of the single loops at equal work, a node counting 1 and each node
  /// of `busy` (sorted, distinct, each < the model's nodes) 1 + `busy_work` (>= 0): a share's
  /// thread also runs its nodes' stages, and a node in contact costs the contact stage about as
  /// much again as its springs and stages. Without busy nodes the shares are equal. Either way
  /// the shares' bounds are multiples of SinglePrecisionSprings::kAlignment (where the runs'
  /// aligned loads start), within that of equal work. The cut moves where the float sums meet
  /// at share boundaries (their rounding; still a function of the shares only); call it between
  /// evaluations, not from a stage.
  static void Cut(ForceEvaluator* evaluator, const std::vector<NodeIndex>& busy, double busy_work);
  /// Whether the next SetForces takes the single-precision loops, whose node arrays Round fills.
  static bool Rounds(const ForceEvaluator& evaluator);
  /// Rounds nodes [begin, end) of `positions` (relative to `origin`) and of `velocities` (null
  /// for no dampers) into the single loops' node arrays, for the next SetForces with
  /// NodeStages::rounded. Concurrent calls for disjoint ranges are safe, also from a stage of
  /// the SetForces that runs now (its `after` stages read only the force arrays).
  /// Precondition: Rounds(), and a SetForces in single precision has run on this model.
  static void Round(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& positions,
                    const Eigen::Matrix3Xd* velocities, int begin, int end, const double origin[3]);
};

}  // namespace msm_sim::core::internal
