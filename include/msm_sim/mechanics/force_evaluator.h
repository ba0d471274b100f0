#pragma once

#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/mechanics/cache_line_allocator.h"
#include "msm_sim/mechanics/orientation_barrier.h"
#include "msm_sim/mechanics/spring_precision.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

struct ScheduledSpringData;
struct SinglePrecisionSprings;

namespace internal {
class SharePlan;
class SinglePasses;

/// An owned member of a type private to src/mechanics whose copies copy the pointee, so that
/// ForceEvaluator stays copyable (its special members are defined where T is complete).
template <typename T>
class Copied {
 public:
  explicit Copied(std::unique_ptr<T> value = nullptr) : value_(std::move(value)) {}
  Copied(const Copied& other) : value_(other ? std::make_unique<T>(*other) : nullptr) {}
  Copied(Copied&&) noexcept = default;
  Copied& operator=(const Copied& other) {
    if (this != &other) value_ = other ? std::make_unique<T>(*other) : nullptr;
    return *this;
  }
  Copied& operator=(Copied&&) noexcept = default;
  ~Copied() = default;
  explicit operator bool() const { return value_ != nullptr; }
  T& operator*() const { return *value_; }
  T* operator->() const { return value_.get(); }

 private:
  std::unique_ptr<T> value_;
};
}  // namespace internal

/// Which loops evaluate the springs' forces.
enum class SpringKernels {
  /// The vectorised run kernels where the model suits them (linear springs in rows, no Baudet
  /// elements), the per-spring loops otherwise.
  kAuto,
  /// Always the per-spring loops: the reference the run kernels are tested and timed against.
  kPerSpring,
};

/// Which geometric stiffness (T / L across each spring, T its total tension) Linearize keeps.
enum class GeometricStiffness {
  kExact,  ///< K is the exact derivative of the forces
  /// Compressed springs' (negative) geometric term is left out, which keeps K positive
  /// semi-definite for linear springs with or without dispersion: an implicit step's matrix
  /// M + c K then stays positive definite under strong compression, at any c.
  kDropCompression,
};

/// Internal forces of a Model: spring tensions under the model's spring law plus, for an eMSM,
/// the dispersed tensions t*_n = (J_a / b_a + J_b / b_b) / L0_n with J_x = q sum L0_i t_i over the
/// springs at node x (docs/physics.md §3). With the model's dispersion weights v (Model::
/// dispersion_weight_a) a node accumulates J = q sum v L0 t and spring n receives w_n J / W with
/// w = v k L0^2 and W = sum w, which makes the dispersion conservative; equal v and equal k L0^2
/// is the paper's algorithm. Baudet correction elements (Model::correction_edges) add their
/// coupled edge tensions after the springs.
///
/// Linear springs on a lattice whose springs line up in rows (cubic lattices) are evaluated by
/// vectorised kernels over a re-ordered copy of the springs; other models (random lattices,
/// carrier springs, Baudet elements) by per-spring loops. Both give the same forces up to
/// rounding.
///
/// Holds scratch buffers, so use one evaluator per simulated state. Precondition: the Model
/// outlives the evaluator; positions have model.num_nodes() columns and no spring has zero
/// length.
class ForceEvaluator {
 public:
  /// `max_threads` (>= 1, at most 4,095): the threads the spring passes may use, on the
  /// process's worker pool (internal::SharePlan: the double loops of models of 50,000 springs
  /// or more, the single loops of 1,000 nodes or more in exactly max_threads node shares, so
  /// that the sums depend on the thread count only). One by default: a robot shares the cores.
  explicit ForceEvaluator(const Model& model, SpringKernels kernels = SpringKernels::kAuto,
                          int max_threads = 1);
  ForceEvaluator(const ForceEvaluator& other);
  ForceEvaluator(ForceEvaluator&& other) noexcept;
  ForceEvaluator& operator=(const ForceEvaluator& other);
  ForceEvaluator& operator=(ForceEvaluator&& other) noexcept;
  ~ForceEvaluator();

  /// Adds `barrier`'s forces to every later evaluation (and its energy and stiffness to
  /// ElasticEnergy, Linearize, ApplyStiffness and StiffnessDiagonal); null removes it. They are
  /// not spring tensions, so total_tensions leaves them out. Precondition: built for model().
  void set_orientation_barrier(std::shared_ptr<const OrientationBarrier> barrier);

  /// Changes max_threads (>= 1, as in the constructor).
  void set_max_threads(int max_threads);

  /// The precision of later AccumulateForces calls and ApplyStiffness products (kDouble after
  /// construction; Linearize itself always evaluates in double).
  void set_precision(SpringPrecision precision);
  SpringPrecision precision() const { return precision_; }

  /// Adds the internal forces at `positions` to *forces (3 x N, N).
  void AccumulateForces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces);
  /// The same plus spring dampers (docs/physics.md §7): every spring also carries the tension
  /// c (v_b - v_a) . u with c = damping_beta k (s), u the unit vector a -> b; it is part of
  /// total_tensions. Precondition: velocities is 3 x N, damping_beta >= 0.
  void AccumulateForces(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities,
                        double damping_beta, Eigen::Matrix3Xd* forces);

  /// The same, but sets *forces (resized to 3 x N) to the internal forces instead of adding them:
  /// the single-precision loops then write their sums directly (no zeroing, no read).
  void SetForces(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities,
                 double damping_beta, Eigen::Matrix3Xd* forces);

  /// Per-node work a caller does around SetForces on each node share's own thread ("owner
  /// computes": a share's nodes stay in its core's cache from one step to the next).
  /// `before(share, begin, end)` may change the positions and velocities of share `share`'s nodes
  /// [begin, end) before SetForces reads them; `after(share, begin, end)` runs once their forces
  /// are set and may read or change those forces and velocities. Neither may touch other nodes.
  /// Shares are numbered 0 .. NumNodeShares() - 1 in node order, as ForEachNodeShare numbers
  /// them. Where the loops have no shares (double precision, models below 1,000 nodes,
  /// one thread) they are called once, with (0, 0, N), before and after the evaluation.
  ///
  /// `after_unstored(share, begin, end, end_forces, stride)`, optional, replaces storing the
  /// forces of nodes [begin, end) and `after` where the single-precision loops have no
  /// orientation barrier: it gets the springs' forces unsummed, node i's being the sum over d of
  /// the float end_forces[d * stride + i] (its a ends) and end_forces[(3 + d) * stride + i] (its
  /// b ends; stride >= N, where each block starts a cache line), each taken
  /// to double before adding (as *forces would hold it), for d = x, y, z, and must do what `after`
  /// would with them. *forces is then left unset for those nodes. (The explicit kick fused with
  /// the sums: the forces are not written to memory and read back.)
  struct NodeStages {
    std::function<void(int, int, int)> before;
    std::function<void(int, int, int)> after;
    std::function<void(int, int, int, const float*, long)> after_unstored;
    /// Optional: the point (x, y, z, m) the single loops round positions relative to; a float
    /// then resolves 6e-8 of a node's distance from it. Null: node 0's position at the call,
    /// before `before` moves it.
    const double* origin = nullptr;
    /// The caller has already done what `before` would and rounded every node with RoundNodes
    /// (relative to `origin`): the single loops skip `before` and their own rounding, one
    /// hand-over between threads fewer. Precondition: RoundsNodes().
    bool rounded = false;
    /// The `after` stages round every node with RoundNodes (relative to `origin`) for the next
    /// SetForces, which will then have `rounded`: the single loops take that evaluation's first
    /// pass ahead, on each share once its `after` stage and those of the shares its springs
    /// reach have run (one hand-over between threads fewer).
    bool rounds_ahead = false;
  };
  /// SetForces with `stages` (both set) run on each share.
  void SetForces(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& velocities,
                 double damping_beta, Eigen::Matrix3Xd* forces, const NodeStages& stages);
  /// Runs task(share, begin, end) for each node share of SetForces' stages on its thread (one
  /// share (0, 0, N) where there are none). Preconditions as for the stages.
  void ForEachNodeShare(const std::function<void(int, int, int)>& task);
  /// The number of shares ForEachNodeShare runs.
  int NumNodeShares() const;
  /// Cuts the node shares of the single loops at equal work, a node counting 1 and each node
  /// of `busy` (sorted, distinct, each < the model's nodes) 1 + `busy_work` (>= 0): a share's
  /// thread also runs its nodes' stages (NodeStages), and a node in contact costs the contact
  /// stage about as much again as its springs and stages. Without busy nodes the shares are
  /// equal. Either way the shares' bounds are multiples of SinglePrecisionSprings::kAlignment
  /// (where the runs' aligned loads start), within that of equal work. The cut moves where the
  /// float sums meet at share boundaries (their rounding; still a function of the shares only);
  /// call it between evaluations, not from a stage.
  void CutNodeShares(const std::vector<NodeIndex>& busy, double busy_work);
  /// Whether the next SetForces takes the single-precision loops, whose node arrays RoundNodes
  /// fills.
  bool RoundsNodes() const { return UsesSingleLoops(); }
  /// Rounds nodes [begin, end) of `positions` (relative to `origin`) and of `velocities` (null
  /// for no dampers) into the single loops' node arrays, for the next SetForces with
  /// NodeStages::rounded. Concurrent calls for disjoint ranges are safe, also from a stage of
  /// the SetForces that runs now (its `after` stages read only the force arrays).
  /// Precondition: RoundsNodes(), and a SetForces in single precision has run on this model.
  void RoundNodes(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd* velocities, int begin,
                  int end, const double origin[3]);

  /// Elastic energy at `positions` (J): the springs' energy plus the dispersion's potential
  /// Phi = sum_x J_x^2 / (2 q W_x) (plus the orientation barrier's, if set). Phi is exact for
  /// linear springs; with the carrier law the dispersion follows the small-strain stiffness, so Phi
  /// is its potential to second order in the strain. Kept out of AccumulateForces because the
  /// carrier law's logarithm would double the cost of a step.
  double ElasticEnergy(const Eigen::Matrix3Xd& positions) const;

  /// Total tension of every spring at the last AccumulateForces (N, > 0 stretched): direct plus
  /// dispersed plus Baudet correction, what measurements such as momentum flow and Hardy stress
  /// must sum. Throws std::logic_error after a single-precision evaluation, which records none.
  const Eigen::VectorXd& total_tensions() const;

  /// Caches the linearisation of the two-pass forces at `positions` for ApplyStiffness and
  /// StiffnessDiagonal (with the geometric stiffness `geometric` asks for).
  void Linearize(const Eigen::Matrix3Xd& positions,
                 GeometricStiffness geometric = GeometricStiffness::kExact);
  /// out = K v with K = -d(forces)/d(positions) at the last Linearize. K is symmetric except
  /// for carrier or power-law springs with dispersion (stiffness_is_symmetric). Precondition:
  /// Linearize was called; v and out are 3 x N. Uses the evaluator's scratch: not for concurrent
  /// calls.
  void ApplyStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// The diagonal of K (3 x N) at the last Linearize, exact.
  Eigen::Matrix3Xd StiffnessDiagonal() const;
  /// K is symmetric without dispersion, and with it for linear springs (the dispersion then has
  /// a potential); with carrier or power-law springs the inflow follows the tangent k' and the
  /// outflow k.
  bool stiffness_is_symmetric() const {
    return model_->dispersion_fraction() == 0.0 || model_->spring_law() == SpringLaw::kLinear;
  }

  const Model& model() const { return *model_; }

  /// Dashpot parameters handed to the force loops (internal).
  struct Damping {
    const double* velocities = nullptr;  // 3 x N, column-major
    double beta = 0.0;                   // s
  };

 private:
  /// Takes the loops that suit the model and the precision (the run kernels, else the
  /// per-spring loops).
  void Accumulate(const Eigen::Matrix3Xd& positions, const Damping& damping,
                  Eigen::Matrix3Xd* forces);
  /// The double run kernels (plain or two-pass eMSM) over the spring schedule.
  void AccumulateRuns(const Eigen::Matrix3Xd& positions, const Damping& damping,
                      Eigen::Matrix3Xd* forces);
  /// The double run kernels' eMSM first pass over the spring schedule: J per node into
  /// accumulator_, from the positions as x, y, z blocks of N (`x_arrays`).
  void InflowRunsToAccumulator(const double* x_arrays);
  /// The single-precision loops (SpringPrecision::kSingle): internal::SinglePasses on the share
  /// plan's node shares.
  void AccumulateSingle(const Eigen::Matrix3Xd& positions, const Damping& damping,
                        Eigen::Matrix3Xd* forces);
  /// Whether an evaluation now takes the single-precision loops.
  bool UsesSingleLoops() const;

  /// The per-spring reference loops (any model; force_evaluator_reference.cpp): plain or two-pass
  /// eMSM (docs/physics.md §3), then the Baudet elements.
  void AccumulatePerSpring(const Eigen::Matrix3Xd& positions, const Damping& damping,
                           Eigen::Matrix3Xd* forces);
  template <bool Damped>
  void AccumulatePerSpringImpl(const Eigen::Matrix3Xd& positions, const Damping& damping,
                               Eigen::Matrix3Xd* forces);
  // The per-spring loops are templated on a law type (spring_law.h, internal::VisitSpringLaw).
  template <bool Damped, class Law>
  void PlainPass(const Law& law, const Eigen::Matrix3Xd& positions, const Damping& damping,
                 Eigen::Matrix3Xd* forces);
  template <class Law>
  void InflowPass(const Law& law, const Eigen::Matrix3Xd& positions);
  template <bool Damped>
  void OutflowPass(const Eigen::Matrix3Xd& positions, const Damping& damping,
                   Eigen::Matrix3Xd* forces);
  void CorrectionPass(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces);
  void ApplyCorrectionStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// ApplyStiffness without the orientation barrier.
  void ApplySpringStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// StiffnessDiagonal without the orientation barrier.
  Eigen::Matrix3Xd SpringStiffnessDiagonal() const;
  /// ApplyStiffness through the run kernels (linear springs, no Baudet elements).
  void ApplyStiffnessRuns(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// The same in single precision (SpringPrecision::kSingle): v rounded to float, the products
  /// summed in float.
  void ApplySingleStiffnessRuns(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// Rounds the springs' data and the last linearisation to float for ApplySingleStiffnessRuns.
  void RoundLinearization();
  template <class Law>
  double EnergyImpl(const Law& law, const Eigen::Matrix3Xd& positions) const;
  template <class Law>
  void LinearizeImpl(const Law& law, const Eigen::Matrix3Xd& positions);
  /// Linearize's per-spring path (models without the run kernels): a double two-pass
  /// evaluation, then each spring's u, L and tangent stiffness in model order.
  void LinearizePerSpring(const Eigen::Matrix3Xd& positions, GeometricStiffness geometric);
  /// Linearize through the run kernels (force_evaluator_runs_stiffness.cpp): the two-pass total
  /// tensions in double and the linearisation in schedule order, without the forces.
  void LinearizeScheduled(const Eigen::Matrix3Xd& positions, bool drop_compression);
  /// SpringStiffnessDiagonal from the scheduled linearisation, over the runs.
  Eigen::Matrix3Xd ScheduledStiffnessDiagonal() const;

  const Model* model_;  // a pointer, so that evaluators (and their history) can be copied
  // The share plan (threads, shares) and the single loops' stage pipeline with its node arrays.
  internal::Copied<internal::SharePlan> plan_;
  internal::Copied<internal::SinglePasses> single_passes_;
  // Per spring, precomputed: inflow q v L0 at each end and outflow w / L0 = v k L0 at each end,
  // so that t*_s = outflow_a g_a + outflow_b g_b with g = J / W per node.
  Eigen::VectorXd inflow_a_, inflow_b_, outflow_a_, outflow_b_;
  Eigen::VectorXd inverse_star_weight_;  // 1 / W per node
  Eigen::VectorXd tensions_;             // direct tensions (per-spring two-pass), model order
  Eigen::VectorXd inverse_lengths_;      // 1 / L (per-spring two-pass), model order
  // Direct + dispersed, in model order. After a vectorised evaluation they are in
  // scheduled_totals_ and copied here when first asked for.
  mutable Eigen::VectorXd total_tensions_;
  mutable bool totals_scheduled_ = false;
  Eigen::VectorXd scheduled_totals_;
  // Null unless the model suits the run kernels.
  std::shared_ptr<const ScheduledSpringData> scheduled_;
  Eigen::VectorXd node_arrays_;  // positions, velocities, forces as x, y, z blocks of N each
  Eigen::VectorXd scheduled_linearization_;   // u and T / L in schedule order (Linearize)
  mutable Eigen::VectorXd stiffness_arrays_;  // dv and K dv as x, y, z blocks of N each
  mutable Eigen::VectorXd accumulator_change_;
  Eigen::VectorXd geometric_tensions_;  // T of the geometric stiffness (per-spring path)
  Eigen::VectorXd accumulator_;         // J per node
  // The double run kernels' first pass: J / q at the springs' a ends (N), then at the b ends.
  Eigen::VectorXd end_sums_;
  Eigen::VectorXd dispersion_per_weight_;  // g = J / W of the last evaluation
  // The per-spring linearisation (model order), filled only where there is no schedule.
  Eigen::Matrix3Xd directions_;  // unit vectors a -> b
  Eigen::VectorXd lengths_;
  Eigen::VectorXd tangent_stiffness_;        // dt / dL per spring
  mutable Eigen::VectorXd diagonal_arrays_;  // ScheduledStiffnessDiagonal's sums, 9 blocks of N
  SpringPrecision precision_ = SpringPrecision::kDouble;
  bool totals_recorded_ = true;         // false after a single-precision evaluation
  bool overwrite_forces_ = false;       // during SetForces
  const NodeStages* stages_ = nullptr;  // during SetForces with stages, on the single loops
  // Set while precision_ is kSingle and the model suits the run kernels.
  std::shared_ptr<const SinglePrecisionSprings> single_;
  // The stiffness product in single precision, per spring in schedule order: k, inflow a and b,
  // outflow a and b, then the linearisation's ux, uy, uz and T / L (RoundLinearization); and
  // its scratch: dv and K dv as x, y, z blocks of N, then dJ (N).
  Eigen::VectorXf single_stiffness_;
  mutable Eigen::VectorXf single_stiffness_arrays_;
  std::shared_ptr<const OrientationBarrier> barrier_;  // null: none
  Eigen::Matrix3Xd barrier_forces_;     // the single loops' barrier forces, added per share
  Eigen::Matrix3Xd barrier_positions_;  // at the last Linearize
  std::vector<int> barrier_active_;     // its corners below the threshold then
  bool barrier_curvature_ = true;       // false under GeometricStiffness::kDropCompression
};

}  // namespace msm_sim::core
