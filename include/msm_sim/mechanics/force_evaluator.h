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
class NodeShares;
struct NodeStages;
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
  /// out = K v with K = -d(forces)/d(positions) at the last Linearize: the Hessian of
  /// ElasticEnergy, symmetric for every spring law (docs/physics.md §3). Precondition: Linearize
  /// was called; v and out are 3 x N. Uses the evaluator's scratch: not for concurrent calls.
  void ApplyStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// The diagonal of K (3 x N) at the last Linearize, exact.
  Eigen::Matrix3Xd StiffnessDiagonal() const;

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
  /// dispersion_.accumulator, from the positions as x, y, z blocks of N (`x_arrays`).
  void InflowRunsToAccumulator(const double* x_arrays);
  /// The single-precision loops (SpringPrecision::kSingle): internal::SinglePasses on the share
  /// plan's node shares.
  void AccumulateSingle(const Eigen::Matrix3Xd& positions, const Damping& damping,
                        Eigen::Matrix3Xd* forces);
  /// Whether an evaluation now takes the single-precision loops.
  bool UsesSingleLoops() const;
  // The node shares of the single loops and the stages run on them (src/mechanics/node_shares.h:
  // the explicit integrator's, private to the library).
  friend class internal::NodeShares;

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
  template <bool Damped, bool Weighted>
  void OutflowPass(const Eigen::Matrix3Xd& positions, const Damping& damping,
                   Eigen::Matrix3Xd* forces);
  void CorrectionPass(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces);
  void ApplyCorrectionStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// ApplyStiffness without the orientation barrier.
  void ApplySpringStiffness(const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) const;
  /// StiffnessDiagonal without the orientation barrier.
  Eigen::Matrix3Xd SpringStiffnessDiagonal() const;
  /// Adds the Baudet correction's part of the diagonal.
  void AddCorrectionStiffnessDiagonal(Eigen::Matrix3Xd* diagonal) const;
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
  void LinearizeImpl(const Law& law, const Eigen::Matrix3Xd& positions, bool exact);
  /// Linearize's per-spring path (models without the run kernels): a double two-pass
  /// evaluation, then each spring's u, L and tangent stiffness in model order.
  void LinearizePerSpring(const Eigen::Matrix3Xd& positions, GeometricStiffness geometric);
  /// Linearize through the run kernels (force_evaluator_runs_stiffness.cpp): the two-pass total
  /// tensions in double and the linearisation in schedule order, without the forces.
  void LinearizeScheduled(const Eigen::Matrix3Xd& positions, bool drop_compression);
  /// SpringStiffnessDiagonal from the scheduled linearisation, over the runs.
  Eigen::Matrix3Xd ScheduledStiffnessDiagonal() const;

  // The eMSM dispersion (docs/physics.md §3), whatever the loops: per spring, inflow q v L0 and
  // outflow w / L0 = v k L0 at each end, so that t*_s = (t'_s / k_s) (outflow_a g_a + outflow_b
  // g_b), t'_s / k_s = 1 for linear springs; per node 1 / W and the last evaluation's J and
  // g = J / W.
  struct Dispersion {
    Eigen::VectorXd inflow_a, inflow_b, outflow_a, outflow_b;
    Eigen::VectorXd inverse_star_weight;
    Eigen::VectorXd accumulator;  // J
    Eigen::VectorXd per_weight;   // g = J / W
  };
  // The per-spring reference loops' arrays, in model order (models without a schedule).
  struct PerSpringArrays {
    Eigen::VectorXd tensions;         // direct tensions of the two-pass evaluation
    Eigen::VectorXd inverse_lengths;  // 1 / L
    Eigen::VectorXd tangent_ratios;   // t' / k of the two-pass evaluation (non-linear laws)
    // The linearisation: unit vectors a -> b, L, dt / dL and the geometric term's T; with a
    // non-linear law and dispersion, the dispersed tension's change with L at fixed g,
    // (t'' / k) (outflow_a g_a + outflow_b g_b).
    Eigen::Matrix3Xd directions;
    Eigen::VectorXd lengths, tangent_stiffness, geometric_tensions, dispersed_slopes;
  };
  // The double run kernels (models with a schedule): the springs in schedule order and scratch.
  struct DoubleRuns {
    std::shared_ptr<const ScheduledSpringData> springs;  // null: no schedule
    Eigen::VectorXd node_arrays;    // positions, velocities, forces as x, y, z blocks of N each
    Eigen::VectorXd end_sums;       // the first pass: J / q at the a ends (N), then the b ends
    Eigen::VectorXd totals;         // direct + dispersed tensions, schedule order
    Eigen::VectorXd linearization;  // u and T / L, schedule order (Linearize)
    mutable Eigen::VectorXd stiffness_arrays;  // dv and K dv as x, y, z blocks of N each
    mutable Eigen::VectorXd accumulator_change;
    mutable Eigen::VectorXd diagonal_arrays;  // ScheduledStiffnessDiagonal's sums, 9 blocks of N
  };
  // The single-precision loops (SpringPrecision::kSingle on a model with a schedule).
  struct SingleLoops {
    std::shared_ptr<const SinglePrecisionSprings> springs;  // null: not in single precision
    // The stage pipeline with its float node arrays (single_pipeline.h).
    internal::Copied<internal::SinglePasses> passes;
    const internal::NodeStages* stages = nullptr;  // during NodeShares::SetForces
    // The stiffness product, per slot of `springs` (phantoms zero): k, inflow a and b, outflow a
    // and b, then the linearisation's ux, uy, uz and T / L (RoundLinearization); and its scratch:
    // dv and K dv as x, y, z blocks of N, then dJ (N).
    Eigen::VectorXf stiffness;
    mutable Eigen::VectorXf stiffness_arrays;
  };
  // The springs' total tensions (direct + dispersed) that total_tensions() returns, in model
  // order; after a vectorised evaluation in DoubleRuns::totals until first asked for.
  struct Totals {
    mutable Eigen::VectorXd model_order;
    mutable bool scheduled = false;
    bool recorded = true;  // false after a single-precision evaluation
  };

  const Model* model_;  // a pointer, so that evaluators (and their history) can be copied
  internal::Copied<internal::SharePlan> plan_;  // threads and shares
  Dispersion dispersion_;
  PerSpringArrays per_spring_;
  DoubleRuns runs_;
  SingleLoops single_loops_;
  Totals totals_;
  SpringPrecision precision_ = SpringPrecision::kDouble;
  bool overwrite_forces_ = false;                      // during SetForces
  std::shared_ptr<const OrientationBarrier> barrier_;  // null: none
  Eigen::Matrix3Xd barrier_forces_;     // the single loops' barrier forces, added per share
  BarrierReference barrier_reference_;  // the barrier's skip test for this state's evaluations
  Eigen::Matrix3Xd barrier_positions_;  // at the last Linearize
  std::vector<int> barrier_active_;     // its corners below the threshold then
  bool barrier_curvature_ = true;       // false under GeometricStiffness::kDropCompression
};

}  // namespace msm_sim::core
