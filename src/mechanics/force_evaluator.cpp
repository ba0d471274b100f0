// ForceEvaluator's construction and force passes, the hot loop of every step. Its elastic energy
// and linearisation are in force_evaluator_stiffness.cpp.

#include "msm_sim/mechanics/force_evaluator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "mechanics/force_kernels.h"
#include "mechanics/single_precision_kernels.h"
#include "mechanics/worker_pool.h"

namespace msm_sim::core {

ForceEvaluator::ForceEvaluator(const Model& model, DispersionPasses passes, SpringKernels kernels,
                               int max_threads)
    : model_(&model),
      passes_(passes),
      max_threads_(std::clamp(max_threads, 1, WorkerPool::kMaxShares)) {
  const int n = model.num_nodes();
  const int num_springs = model.num_springs();
  const double q = model.dispersion_fraction();
  // Star weight W of every node: the sum of its springs' outflow weights w = v k L0^2 (the
  // spring count b, up to a common factor, for the paper's equal shares).
  Eigen::VectorXd star_weight = Eigen::VectorXd::Zero(n);
  inflow_a_.resize(num_springs);
  inflow_b_.resize(num_springs);
  outflow_a_.resize(num_springs);
  outflow_b_.resize(num_springs);
  for (int s = 0; s < num_springs; ++s) {
    const double rest = model.spring_rest_length()[s];
    const double k_l2 = model.spring_stiffness()[s] * rest * rest;
    const double va = model.dispersion_weight_a()[s];
    const double vb = model.dispersion_weight_b()[s];
    // w = v k L0^2 makes the dispersion conservative (see Model::dispersion_weight_a).
    star_weight[model.spring_node_a()[s]] += va * k_l2;
    star_weight[model.spring_node_b()[s]] += vb * k_l2;
    inflow_a_[s] = q * rest * va;
    inflow_b_[s] = q * rest * vb;
    outflow_a_[s] = va * k_l2 / rest;
    outflow_b_[s] = vb * k_l2 / rest;
  }
  inverse_star_weight_.resize(n);
  for (int i = 0; i < n; ++i) {
    inverse_star_weight_[i] = star_weight[i] > 0.0 ? 1.0 / star_weight[i] : 0.0;
  }
  tensions_.setZero(num_springs);
  inverse_lengths_.setZero(num_springs);
  total_tensions_.setZero(num_springs);
  accumulator_.setZero(n);
  dispersion_per_weight_.setZero(n);
  directions_.setZero(3, num_springs);
  lengths_.setZero(num_springs);
  tangent_stiffness_.setZero(num_springs);
  // The run kernels know linear springs only, and the Baudet pass adds to model-order tensions.
  if (kernels == SpringKernels::kAuto && model.spring_law() == SpringLaw::kLinear &&
      model.correction_edges().empty()) {
    SpringSchedule schedule = ScheduleSprings(model);
    if (schedule.vectorisable()) {
      auto data = std::make_shared<ScheduledSpringData>();
      data->rest = schedule.ToSchedule(model.spring_rest_length().data());
      data->stiffness = schedule.ToSchedule(model.spring_stiffness().data());
      data->inflow_a = schedule.ToScheduleEnd(inflow_a_.data(), inflow_b_.data());
      data->inflow_b = schedule.ToScheduleEnd(inflow_b_.data(), inflow_a_.data());
      data->outflow_a = schedule.ToScheduleEnd(outflow_a_.data(), outflow_b_.data());
      data->outflow_b = schedule.ToScheduleEnd(outflow_b_.data(), outflow_a_.data());
      data->schedule = std::move(schedule);
      scheduled_ = std::move(data);
      scheduled_totals_.setZero(num_springs);
    }
  }
}

void ForceEvaluator::set_orientation_barrier(std::shared_ptr<const OrientationBarrier> barrier) {
  barrier_ = std::move(barrier);
  ahead_ = TakenAhead{};
}

void ForceEvaluator::set_max_threads(int max_threads) {
  max_threads_ = std::clamp(max_threads, 1, WorkerPool::kMaxShares);
  ahead_ = TakenAhead{};  // the shares' overflows move
  share_bounds_.clear();
}

void ForceEvaluator::set_precision(SpringPrecision precision) {
  precision_ = precision;
  ahead_ = TakenAhead{};
  if (precision == SpringPrecision::kDouble || !scheduled_) {
    single_.reset();
  } else if (!single_) {
    single_ = SinglePrecisionSprings::Schedule(*model_);
    // A linearisation from before takes the single-precision products from now on.
    if (scheduled_linearization_.size() == 4 * static_cast<Eigen::Index>(model_->num_springs())) {
      RoundLinearization();
    }
  }
}

const Eigen::VectorXd& ForceEvaluator::total_tensions() const {
  if (!totals_recorded_) {
    throw std::logic_error(
        "ForceEvaluator::total_tensions: the last evaluation was single precision, which records "
        "no tensions; evaluate in double (set_precision(SpringPrecision::kDouble)) first");
  }
  if (totals_scheduled_) {
    const std::vector<SpringIndex>& model_index = scheduled_->schedule.model_index;
    for (std::size_t p = 0; p < model_index.size(); ++p) {
      total_tensions_[model_index[p]] = scheduled_totals_[static_cast<Eigen::Index>(p)];
    }
    totals_scheduled_ = false;
  }
  return total_tensions_;
}

// The hot loops below work on raw, non-aliasing pointers: through Eigen column blocks of a
// matrix passed by pointer the compiler must assume every force store may change the positions
// or the model arrays, and reloads them (docs/design/speed-against-bullet.md).
namespace {

struct SpringArrays {
  const NodeIndex* __restrict a;
  const NodeIndex* __restrict b;
  const double* __restrict rest;
  const double* __restrict k;
};

SpringArrays Arrays(const Model& model) {
  return {model.spring_node_a().data(), model.spring_node_b().data(),
          model.spring_rest_length().data(), model.spring_stiffness().data()};
}

// Adds f * (x_b - x_a) to node a and subtracts it from node b.
inline void ApplyPair(double* __restrict forces, int a, int b, double f, const double r[3]) {
  for (int i = 0; i < 3; ++i) {
    forces[3 * a + i] += f * r[i];
    forces[3 * b + i] -= f * r[i];
  }
}

inline double Separation(const double* __restrict x, int a, int b, double r[3]) {
  for (int i = 0; i < 3; ++i) r[i] = x[3 * b + i] - x[3 * a + i];
  return std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

// The dashpot's tension beta k (v_b - v_a) . r / L (positive when the spring lengthens).
inline double DampingTension(const ForceEvaluator::Damping& damping, const SpringArrays& springs,
                             int s, const double r[3], double length) {
  const double* __restrict v = damping.velocities;
  const int a = springs.a[s], b = springs.b[s];
  double rate = 0.0;
  for (int i = 0; i < 3; ++i) rate += (v[3 * b + i] - v[3 * a + i]) * r[i];
  return damping.beta * springs.k[s] * rate / length;
}

}  // namespace

template <typename Body>
void ForceEvaluator::ForSprings(double* target, Eigen::Index target_size, Body&& body) {
  ForShares(model_->num_springs(), target, target_size, std::forward<Body>(body));
}

template <typename Body>
void ForceEvaluator::ForShares(int count, double* target, Eigen::Index target_size, Body&& body) {
  // The pool's thread starts only when a model may use it: a one-thread world starts none.
  const bool parallel = model_->num_springs() >= kParallelSprings && max_threads_ > 1;
  WorkerPool* pool = parallel ? &WorkerPool::Shared() : nullptr;
  const int threads = parallel ? std::min(max_threads_, pool->workers() + 1) : 1;
  if (threads <= 1) {
    body(0, count, target);
    return;
  }
  // Each thread takes a fixed, contiguous share of the springs or runs (both ordered by node, so
  // the shares touch mostly different nodes) and scatters into its own buffer; the buffers
  // are added in share order, so a given thread count always gives the same sums, whichever
  // thread runs a share.
  auto& scratch = scratch_;
  scratch.resize(threads - 1);
  for (auto& buffer : scratch) buffer.setZero(target_size);
  const std::function<void(int)> share = [&](int t) {
    const int begin = static_cast<int>(static_cast<long long>(count) * t / threads);
    const int end = static_cast<int>(static_cast<long long>(count) * (t + 1) / threads);
    body(begin, end, t == 0 ? target : scratch[t - 1].data());
  };
  std::unique_lock<std::mutex> lock(pool->busy(), std::try_to_lock);
  if (lock.owns_lock()) {
    pool->Run(threads, share);
  } else {  // another evaluator (another World's thread) has the pool: the same shares, here
    for (int t = 0; t < threads; ++t) share(t);
  }
  Eigen::Map<Eigen::VectorXd> sum(target, target_size);
  for (const auto& buffer : scratch) sum += buffer;
}

template <SpringLaw Law, bool Damped>
void ForceEvaluator::PlainPass(const Eigen::Matrix3Xd& positions, const Damping& damping,
                               Eigen::Matrix3Xd* forces) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  double* __restrict total = total_tensions_.data();
  ForSprings(forces->data(), forces->size(), [&](int begin, int end, double* __restrict f) {
    for (int s = begin; s < end; ++s) {
      double r[3];
      const double length = Separation(x, springs.a[s], springs.b[s], r);
      double t = SpringTension<Law>(springs.k[s], springs.rest[s], length);
      if constexpr (Damped) t += DampingTension(damping, springs, s, r, length);
      total[s] = t;
      ApplyPair(f, springs.a[s], springs.b[s], t / length, r);
    }
  });
}

template <SpringLaw Law>
void ForceEvaluator::InflowPass(const Eigen::Matrix3Xd& positions) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  const double* __restrict inflow_a = inflow_a_.data();
  const double* __restrict inflow_b = inflow_b_.data();
  double* __restrict tensions = tensions_.data();
  double* __restrict inverse_lengths = inverse_lengths_.data();
  accumulator_.setZero();
  ForSprings(accumulator_.data(), accumulator_.size(),
             [&](int begin, int end, double* __restrict accumulator) {
               for (int s = begin; s < end; ++s) {
                 double r[3];
                 const double length = Separation(x, springs.a[s], springs.b[s], r);
                 const double t = SpringTension<Law>(springs.k[s], springs.rest[s], length);
                 tensions[s] = t;
                 inverse_lengths[s] = 1.0 / length;
                 accumulator[springs.a[s]] += inflow_a[s] * t;
                 accumulator[springs.b[s]] += inflow_b[s] * t;
               }
             });
}

template <bool Damped>
void ForceEvaluator::OutflowPass(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                 Eigen::Matrix3Xd* forces) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  const double* __restrict g = dispersion_per_weight_.data();
  const double* __restrict outflow_a = outflow_a_.data();
  const double* __restrict outflow_b = outflow_b_.data();
  const double* __restrict tensions = tensions_.data();
  const double* __restrict inverse_lengths = inverse_lengths_.data();
  double* __restrict total = total_tensions_.data();
  ForSprings(forces->data(), forces->size(), [&](int begin, int end, double* __restrict f) {
    for (int s = begin; s < end; ++s) {
      const int a = springs.a[s];
      const int b = springs.b[s];
      double t = tensions[s] + outflow_a[s] * g[a] + outflow_b[s] * g[b];
      // Recomputing r from positions still in cache is cheaper than streaming stored directions.
      double r[3];
      for (int i = 0; i < 3; ++i) r[i] = x[3 * b + i] - x[3 * a + i];
      if constexpr (Damped) t += DampingTension(damping, springs, s, r, 1.0 / inverse_lengths[s]);
      total[s] = t;
      ApplyPair(f, a, b, t * inverse_lengths[s], r);
    }
  });
}

template <SpringLaw Law, bool Damped>
void ForceEvaluator::LaggedPass(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                Eigen::Matrix3Xd* forces) {
  const SpringArrays springs = Arrays(*model_);
  const double* __restrict x = positions.data();
  const double* __restrict g = dispersion_per_weight_.data();  // of the previous evaluation
  const double* __restrict inflow_a = inflow_a_.data();
  const double* __restrict inflow_b = inflow_b_.data();
  const double* __restrict outflow_a = outflow_a_.data();
  const double* __restrict outflow_b = outflow_b_.data();
  double* __restrict accumulator = accumulator_.data();
  double* __restrict total = total_tensions_.data();
  double* __restrict f = forces->data();
  accumulator_.setZero();
  for (int s = 0; s < model_->num_springs(); ++s) {
    const int a = springs.a[s];
    const int b = springs.b[s];
    double r[3];
    const double length = Separation(x, a, b, r);
    const double t = SpringTension<Law>(springs.k[s], springs.rest[s], length);
    accumulator[a] += inflow_a[s] * t;
    accumulator[b] += inflow_b[s] * t;
    double t_total = t + outflow_a[s] * g[a] + outflow_b[s] * g[b];
    if constexpr (Damped) t_total += DampingTension(damping, springs, s, r, length);
    total[s] = t_total;
    ApplyPair(f, a, b, t_total / length, r);
  }
}

void ForceEvaluator::CorrectionPass(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces) {
  const auto& a = model_->spring_node_a();
  const auto& b = model_->spring_node_b();
  const auto& rest = model_->spring_rest_length();
  const auto& edges = model_->correction_edges();
  const auto& coefficient = model_->correction_coefficients();
  for (std::size_t e = 0; e < edges.size(); ++e) {
    double r[12][3];
    double length[12];
    double elongation[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      length[i] = Separation(positions.data(), a[s], b[s], r[i]);
      elongation[i / 4] += length[i] - rest[s];
    }
    const double sum = elongation[0] + elongation[1] + elongation[2];
    for (int i = 0; i < 12; ++i) {
      const SpringIndex s = edges[e][i];
      const double tension = coefficient[e] * (sum - elongation[i / 4]);
      total_tensions_[s] += tension;
      ApplyPair(forces->data(), a[s], b[s], tension / length[i], r[i]);
    }
  }
}

void ForceEvaluator::AccumulateForces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces) {
  Accumulate<false>(positions, Damping{}, forces);
}

void ForceEvaluator::AccumulateForces(const Eigen::Matrix3Xd& positions,
                                      const Eigen::Matrix3Xd& velocities, double damping_beta,
                                      Eigen::Matrix3Xd* forces) {
  if (damping_beta == 0.0) {
    Accumulate<false>(positions, Damping{}, forces);
  } else {
    Accumulate<true>(positions, Damping{velocities.data(), damping_beta}, forces);
  }
}

void ForceEvaluator::SetForces(const Eigen::Matrix3Xd& positions,
                               const Eigen::Matrix3Xd& velocities, double damping_beta,
                               Eigen::Matrix3Xd* forces) {
  forces->resize(3, model_->num_nodes());
  overwrite_forces_ = true;
  AccumulateForces(positions, velocities, damping_beta, forces);
  overwrite_forces_ = false;
}

void ForceEvaluator::SetForces(const Eigen::Matrix3Xd& positions,
                               const Eigen::Matrix3Xd& velocities, double damping_beta,
                               Eigen::Matrix3Xd* forces, const NodeStages& stages) {
  if (!UsesSingleLoops()) {
    stages.before(0, 0, model_->num_nodes());
    SetForces(positions, velocities, damping_beta, forces);
    stages.after(0, 0, model_->num_nodes());
    return;
  }
  stages_ = &stages;
  SetForces(positions, velocities, damping_beta, forces);
  stages_ = nullptr;
}

void ForceEvaluator::RoundNodes(const Eigen::Matrix3Xd& positions,
                                const Eigen::Matrix3Xd* velocities, int begin, int end,
                                const double origin[3]) {
  RoundNodeRange(positions.data(), velocities != nullptr ? velocities->data() : nullptr, begin, end,
                 origin);
}

void ForceEvaluator::RoundNodeRange(const double* positions, const double* velocities, int begin,
                                    int end, const double origin[3]) {
  const Eigen::Index stride = SingleStride();
  float* x = single_nodes_.data();
  ToSingleNodeArrays(positions, stride, begin, end, origin, x);
  if (velocities != nullptr) {
    const double zero[3] = {0.0, 0.0, 0.0};
    ToSingleNodeArrays(velocities, stride, begin, end, zero, x + 3 * stride);
  }
}

bool ForceEvaluator::UsesSingleLoops() const {
  // As Accumulate chooses: the run kernels unless one-pass dispersion lags on a previous
  // evaluation, in single precision where the model has them.
  const bool lagged = passes_ == DispersionPasses::kOnePass && has_previous_dispersion_ &&
                      model_->dispersion_fraction() != 0.0;
  return scheduled_ && single_ && !lagged;
}

int ForceEvaluator::NumNodeShares() const { return UsesSingleLoops() ? SingleShares() : 1; }

void ForceEvaluator::ForEachNodeShare(const std::function<void(int, int, int)>& task) {
  const int count = NumNodeShares();
  RunShares(count, [&](int t) {
    const SingleShare share = NodeShare(t, count);
    task(t, share.begin, share.end);
  });
}

template <bool Damped>
void ForceEvaluator::Accumulate(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                Eigen::Matrix3Xd* forces) {
  totals_recorded_ = true;
  const bool dispersion = model_->dispersion_fraction() != 0.0;
  const bool lagged = passes_ == DispersionPasses::kOnePass && has_previous_dispersion_;
  const bool runs = scheduled_ && !(dispersion && lagged);
  // SetForces: every path but the single-precision loops adds to *forces.
  if (overwrite_forces_ && !(runs && single_)) forces->setZero();
  if (runs) {
    AccumulateRuns(positions, damping, forces);
    has_previous_dispersion_ = dispersion;
    // The single-precision loops add the barrier on each share, before its `after` stage.
    if (barrier_ && !single_) barrier_->AccumulateForces(positions, forces);
    return;
  }
  totals_scheduled_ = false;
  const bool linear = model_->spring_law() == SpringLaw::kLinear;
  if (model_->dispersion_fraction() == 0.0) {
    linear ? PlainPass<SpringLaw::kLinear, Damped>(positions, damping, forces)
           : PlainPass<SpringLaw::kNonlinear, Damped>(positions, damping, forces);
    if (!model_->correction_edges().empty()) CorrectionPass(positions, forces);
    if (barrier_) barrier_->AccumulateForces(positions, forces);
    return;
  }
  if (passes_ == DispersionPasses::kOnePass && has_previous_dispersion_) {
    linear ? LaggedPass<SpringLaw::kLinear, Damped>(positions, damping, forces)
           : LaggedPass<SpringLaw::kNonlinear, Damped>(positions, damping, forces);
    dispersion_per_weight_ = accumulator_.cwiseProduct(inverse_star_weight_);  // for next time
  } else {
    // Two passes: the direct tensions fill the accumulators, then every spring applies its
    // direct plus dispersed tension at once.
    linear ? InflowPass<SpringLaw::kLinear>(positions)
           : InflowPass<SpringLaw::kNonlinear>(positions);
    dispersion_per_weight_ = accumulator_.cwiseProduct(inverse_star_weight_);
    OutflowPass<Damped>(positions, damping, forces);
  }
  has_previous_dispersion_ = true;
  if (!model_->correction_edges().empty()) CorrectionPass(positions, forces);
  if (barrier_) barrier_->AccumulateForces(positions, forces);
}

void ForceEvaluator::AccumulateRuns(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                    Eigen::Matrix3Xd* forces) {
  if (single_) {
    AccumulateSingle(positions, damping, forces);
    return;
  }
  const Eigen::Index n = model_->num_nodes();
  node_arrays_.resize(9 * n);
  double* x = node_arrays_.data();
  double* v = x + 3 * n;
  double* f = x + 6 * n;
  ToNodeArrays(positions.data(), n, x);
  const NodeArrays x_arrays{x, x + n, x + 2 * n};
  const NodeArrays v_arrays{v, v + n, v + 2 * n};
  RunDamping run_damping{nullptr, damping.beta};
  if (damping.velocities != nullptr) {
    ToNodeArrays(damping.velocities, n, v);
    run_damping.velocities = &v_arrays;
  }
  std::fill(f, f + 3 * n, 0.0);
  const ScheduledSprings springs = scheduled_->View();
  const int num_runs = static_cast<int>(scheduled_->schedule.runs.size());
  double* totals = scheduled_totals_.data();
  if (model_->dispersion_fraction() == 0.0) {
    ForShares(num_runs, f, 3 * n, [&](int begin, int end, double* target) {
      PlainRuns(springs, begin, end, x_arrays, run_damping, {target, target + n, target + 2 * n},
                totals);
    });
  } else {
    accumulator_.setZero();
    ForShares(num_runs, accumulator_.data(), n, [&](int begin, int end, double* target) {
      InflowRuns(springs, begin, end, x_arrays, run_damping, tensions_.data(),
                 inverse_lengths_.data(), target);
    });
    dispersion_per_weight_ = accumulator_.cwiseProduct(inverse_star_weight_);
    ForShares(num_runs, f, 3 * n, [&](int begin, int end, double* target) {
      OutflowRuns(springs, begin, end, x_arrays, dispersion_per_weight_.data(), tensions_.data(),
                  inverse_lengths_.data(), {target, target + n, target + 2 * n}, totals);
    });
  }
  AddNodeArrays(f, n, forces->data());
  totals_scheduled_ = true;
}

int ForceEvaluator::SingleShares() const {
  return model_->num_nodes() >= kParallelSingleNodes ? max_threads_ : 1;
}

Eigen::Index ForceEvaluator::SingleStride() const {
  return WholeCacheLinesOfFloats(single_ ? single_->PaddedNodes() : model_->num_nodes());
}

namespace {

// Node i rounded down to the runs' alignment, where a share's loops start.
int AlignDown(long long i) { return static_cast<int>(i - i % SinglePrecisionSprings::kAlignment); }

// Share t's first node of `count` equal shares of n nodes: a multiple of the runs' alignment
// (a share's loops start there), 0 for the first, n after the last.
int EqualShareBound(long long n, int t, int count) {
  return t == count ? static_cast<int>(n) : AlignDown(n * t / count);
}

}  // namespace

SingleShare ForceEvaluator::NodeShare(int t, int count) const {
  if (static_cast<int>(share_bounds_.size()) == count + 1) {
    return {share_bounds_[t], share_bounds_[t + 1]};
  }
  const long long n = model_->num_nodes();
  return {EqualShareBound(n, t, count), EqualShareBound(n, t + 1, count)};
}

void ForceEvaluator::CutNodeShares(const std::vector<NodeIndex>& busy, double busy_work) {
  const int count = SingleShares();
  const int n = model_->num_nodes();
  std::vector<int> bounds;
  if (count > 1 && !busy.empty() && busy_work > 0.0) {
    // Node i's share of the work is 1 + busy_work per busy node; share t ends at the first node
    // at which the work before it reaches t / count of the whole, rounded down to the runs'
    // alignment (EqualShareBound), every share keeping some nodes.
    constexpr int kAlign = SinglePrecisionSprings::kAlignment;
    const double total = n + busy_work * static_cast<double>(busy.size());
    bounds.assign(count + 1, n);
    bounds[0] = 0;
    std::size_t next_busy = 0;
    double work = 0.0;
    int t = 1;
    for (int i = 0; i < n && t < count; ++i) {
      while (t < count && work >= total * t / count) {
        bounds[t] = std::max(AlignDown(i), bounds[t - 1] + kAlign);
        ++t;
      }
      const bool is_busy = next_busy < busy.size() && busy[next_busy] == i;
      if (is_busy) ++next_busy;
      work += 1.0 + (is_busy ? busy_work : 0.0);
    }
    for (int u = count - 1; u >= 1; --u) {
      bounds[u] = std::min(bounds[u], AlignDown(bounds[u + 1] - 1));
    }
  }
  if (bounds != share_bounds_) {
    share_bounds_ = std::move(bounds);
    ahead_ = TakenAhead{};  // the shares' overflows move
  }
}

void ForceEvaluator::RunShares(int shares, const std::function<void(int)>& task) {
  if (shares <= 1) {
    task(0);
    return;
  }
  WorkerPool& pool = WorkerPool::Shared();
  std::unique_lock<std::mutex> lock(pool.busy(), std::try_to_lock);
  if (lock.owns_lock()) {
    pool.Run(shares, task);
  } else {  // another evaluator (another World's thread) has the pool: the same shares, here
    for (int t = 0; t < shares; ++t) task(t);
  }
}

void ForceEvaluator::RunSharesInTwoParts(int shares, const std::function<void(int)>& first,
                                         const std::function<void(int)>& second,
                                         const std::function<int(int)>& last_read) {
  if (shares > 1) {
    WorkerPool& pool = WorkerPool::Shared();
    std::unique_lock<std::mutex> lock(pool.busy(), std::try_to_lock);
    if (lock.owns_lock()) {
      pool.RunInTwoParts(shares, first, second, last_read);
      return;
    }
  }
  for (int t = 0; t < shares; ++t) first(t);
  for (int t = 0; t < shares; ++t) second(t);
}

namespace {

// Adds the overflows of the shares before `share` (each `length` floats from its end node, at
// `stride` apart in `overflows`) into `shared` (per node) over the share's own nodes: after
// this, shared holds every b end's sum for them.
void GatherOverflows(const float* overflows, long stride, long length,
                     const std::vector<SingleShare>& shares, int share, float* shared) {
  const SingleShare& own = shares[share];
  for (int earlier = 0; earlier < share; ++earlier) {
    const long from = shares[earlier].end;
    const long lo = std::max<long>(own.begin, from);
    const long hi = std::min<long>(own.end, from + length);
    const float* overflow = overflows + stride * earlier;
    for (long i = lo; i < hi; ++i) shared[i] += overflow[i - from];
  }
}

}  // namespace

void ForceEvaluator::AccumulateSingle(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                      Eigen::Matrix3Xd* forces) {
  const Eigen::Index n = model_->num_nodes();
  const Eigen::Index stride = SingleStride();  // between blocks of n
  single_nodes_.resize(12 * stride);
  float* x = single_nodes_.data();
  float* v = x + 3 * stride;
  float* f = x + 6 * stride;
  // Node shares, each with an overflow of max_offset floats for each of the b ends' x, y, z
  // forces and J_b.
  const int count = SingleShares();
  std::vector<SingleShare> shares(count);
  for (int t = 0; t < count; ++t) shares[t] = NodeShare(t, count);

  // Relative to node 0 (where it is before the stages move it) unless the stages say: a float
  // resolves 6e-8 of the body's size, not of its distance from the world's origin.
  const double* given = stages_ != nullptr ? stages_->origin : nullptr;
  const double origin[3] = {given != nullptr ? given[0] : positions(0, 0),
                            given != nullptr ? given[1] : positions(1, 0),
                            given != nullptr ? given[2] : positions(2, 0)};
  const SingleNodeArrays x_arrays{x, x + stride, x + 2 * stride};
  const SingleNodeArrays v_arrays{v, v + stride, v + 2 * stride};
  const SingleNodeArrays* velocities = damping.velocities != nullptr ? &v_arrays : nullptr;
  const auto beta = static_cast<float>(damping.beta);
  const bool dispersion = model_->dispersion_fraction() != 0.0;
  const bool rounded = stages_ != nullptr && stages_->rounded;
  // What the last evaluation took ahead of this one (NodeStages::rounds_ahead), on these nodes
  // (rounded since): the first pass of the eMSM, and the last share's part of the passes after
  // it from node early_from on, which had that evaluation's dampers (the stages round the
  // velocities for the next one, but only the caller knows whether its beta stays).
  const bool taken_ahead = rounded && ahead_.taken;
  const bool inflowed = taken_ahead && dispersion;
  const bool same_dampers = ahead_.beta == (damping.velocities != nullptr ? beta : 0.0f);
  const int early_from = taken_ahead && same_dampers ? ahead_.early_from : -1;
  ahead_ = TakenAhead{};
  const bool ahead = stages_ != nullptr && stages_->rounds_ahead && !barrier_;
  const long length = single_->max_offset;
  const long overflow_stride = WholeCacheLinesOfFloats(length);  // blocks start a line
  single_overflows_.resize(4 * overflow_stride * count);
  const auto overflow = [&](int t, int block) {
    return single_overflows_.data() + 4 * overflow_stride * t + overflow_stride * block;
  };
  // The last share whose nodes share t's spring loops read (b = a + d, d <= max_offset): its
  // second parts wait for those shares' first parts only (RunSharesInTwoParts).
  const auto last_read = [&](int t) {
    const long reach = std::min<long>(shares[t].end + length, n) - 1;
    int last = t;
    while (last + 1 < count && shares[last + 1].begin <= reach) ++last;
    return last;
  };
  const auto round = [&](int t) {
    if (rounded) return;
    const SingleShare& share = shares[t];
    if (stages_ != nullptr) stages_->before(t, share.begin, share.end);
    RoundNodeRange(positions.data(), damping.velocities, share.begin, share.end, origin);
  };
  const SingleEndForces end_forces{{f, f + stride, f + 2 * stride},
                                   {f + 3 * stride, f + 4 * stride, f + 5 * stride}};
  // Zeroes share t's nodes in `blocks` consecutive node blocks from `nodes`, and its overflows
  // `first` .. `last`.
  const auto clear = [&](int t, float* nodes, int blocks, int first, int last) {
    const SingleShare& share = shares[t];
    for (int b = 0; b < blocks; ++b) {
      std::fill(nodes + b * stride + share.begin, nodes + b * stride + share.end, 0.0f);
    }
    std::fill(overflow(t, first), overflow(t, last) + length, 0.0f);
  };
  const auto apply_forces = [&](int t) {
    for (int d = 0; d < 3; ++d) {
      GatherOverflows(overflow(0, d), 4 * overflow_stride, length, shares, t, f + (3 + d) * stride);
    }
    const SingleShare& share = shares[t];
    if (stages_ != nullptr && stages_->after_unstored && !barrier_) {
      stages_->after_unstored(t, share.begin, share.end, f, stride);
      return;
    }
    if (overwrite_forces_) {
      StoreSingleEndForces(f, stride, share.begin, share.end, forces->data());
    } else {
      AddSingleEndForces(f, stride, share.begin, share.end, forces->data());
    }
    if (barrier_) {
      forces->middleCols(share.begin, share.end - share.begin) +=
          barrier_forces_.middleCols(share.begin, share.end - share.begin);
    }
    if (stages_ != nullptr) stages_->after(t, share.begin, share.end);
  };
  // Zeroes what share t's passes add to: both ends' forces or accumulators, or where the
  // loops take the share by blocks only the b ends' (they store the a ends'), and the overflows.
  const auto clear_sums = [&](int t, float* a_ends, int blocks, int first, int last) {
    if (SingleLoopsByBlocks(*single_, shares[t])) {
      clear(t, a_ends + (blocks / 2) * stride, blocks / 2, first, last);
    } else {
      clear(t, a_ends, blocks, first, last);
    }
  };
  const auto overflow_forces = [&](int t) {
    return MutableSingleNodeArrays{overflow(t, 0), overflow(t, 1), overflow(t, 2)};
  };
  if (dispersion) {
    single_accumulators_.resize(2 * stride);
    accumulator_.resize(n);
    dispersion_per_weight_.resize(n);
    single_dispersion_.resize(stride);  // g, read where the blocks' phantoms reach
  }
  float* j_a = single_accumulators_.data();
  float* j_b = j_a + stride;
  // The last share's nodes [early_from, n), whose plain or eMSM second pass (and dispersion)
  // the last evaluation took ahead.
  const auto ahead_from = [&](int t) {
    return t == count - 1 && early_from >= 0 ? early_from : shares[t].end;
  };
  // The last share's split (count > 1): the later evaluation's passes after the first may take
  // its nodes from `split` on ahead (NodeStages::rounds_ahead: the last share, which does not
  // wait for the first's contacts, a resting block's ground contacts, CutNodeShares, takes its
  // nodes beyond the first share's count, which the cut gave it for those contacts, and beyond
  // the earlier shares' overflows, whose J it has complete). So that they sum alike whether
  // taken ahead or not, the last share's passes after the first always run them apart: first
  // the split's tail, its b ends in place, then the nodes before it, whose b ends from `split` on
  // go to the share's overflow (unused otherwise: the last share's b ends lie below n), added
  // after. (A node's b-end sum then takes the tail's slots, then the rest's, in either case.)
  const int last = count - 1;
  const int nodes = static_cast<int>(n);
  const int extra = (shares[last].end - shares[last].begin) - (shares[0].end - shares[0].begin);
  constexpr int kAlign = SinglePrecisionSprings::kAlignment;  // where its loops start
  const int unaligned = std::max(shares[last].begin + static_cast<int>(length), nodes - extra);
  const int split = count > 1 ? std::min((unaligned + kAlign - 1) / kAlign * kAlign, nodes) : nodes;
  // The forces of the slots in `part` of share t: the plain pass, or the eMSM second pass.
  const auto spring_forces = [&](int t, const SingleShare& part) {
    if (dispersion) {
      SingleOutflowRuns(*single_, part, x_arrays, velocities, beta, single_dispersion_.data(),
                        end_forces, overflow_forces(t));
    } else {
      SinglePlainRuns(*single_, part, x_arrays, velocities, beta, end_forces, overflow_forces(t));
    }
  };
  const auto tail_forces = [&](int t) {
    clear_sums(t, f, 6, 0, 2);
    spring_forces(t, SingleShare{split, nodes, nodes});
  };
  const auto force_pass = [&](int t) {
    if (t != last || split == nodes) {
      clear_sums(t, f, 6, 0, 2);
      spring_forces(t, shares[t]);
      return;
    }
    if (early_from != split) tail_forces(t);  // else taken ahead, its blocks cleared then
    std::fill(overflow(t, 0), overflow(t, 2) + length, 0.0f);
    spring_forces(t, SingleShare{shares[t].begin, split, split});
    const long reach = std::min<long>(length, nodes - split);
    for (int d = 0; d < 3; ++d) {
      float* to = f + (3 + d) * stride + split;
      const float* from = overflow(t, d);
      for (long i = 0; i < reach; ++i) to[i] += from[i];
    }
  };
  // The plain pass, or the eMSM first pass (J's accumulators).
  const auto first_pass = [&](int t) {
    if (!dispersion) {
      force_pass(t);
      return;
    }
    clear_sums(t, j_a, 2, 3, 3);
    SingleInflowRuns(*single_, shares[t], x_arrays, j_a, j_b, overflow(t, 3));
  };
  // J and g in double as well where a one-pass evaluation after this one lags on them; two
  // passes never read them (storing them was half of SingleDispersion's time).
  double* const lagged_j = passes_ == DispersionPasses::kOnePass ? accumulator_.data() : nullptr;
  const auto disperse = [&](int begin, int end) {
    SingleDispersion(j_a, model_->dispersion_fraction(), inverse_star_weight_.data(), stride, begin,
                     end, lagged_j, dispersion_per_weight_.data(), single_dispersion_.data());
  };

  if (barrier_) {
    if (!rounded) RunShares(count, round);
    // In double, once every share's `before` stage has moved its nodes; added per share below.
    barrier_forces_.setZero(3, n);
    barrier_->AccumulateForces(positions, &barrier_forces_);
    RunShares(count, first_pass);
  } else if (!inflowed) {
    RunSharesInTwoParts(count, round, first_pass, last_read);
  }
  if (dispersion) {
    const auto gather_and_disperse = [&](int t) {
      GatherOverflows(overflow(0, 3), 4 * overflow_stride, length, shares, t, j_b);
      disperse(shares[t].begin, ahead_from(t));
    };
    RunSharesInTwoParts(count, gather_and_disperse, force_pass, last_read);
  }
  // Ahead: each share's kick, contacts and drift, then the next evaluation's eMSM first pass on
  // the nodes its `after` stage and the later shares' have rounded; the last share also takes
  // the passes after it for its split's tail (see `split`): the first share's contacts and
  // those nodes are then done at the same time.
  const bool early = ahead && split < nodes;
  if (ahead && (dispersion || early)) {
    const auto next_passes = [&](int t) {
      if (dispersion) first_pass(t);
      if (!early || t != last) return;
      if (dispersion) disperse(split, nodes);
      tail_forces(t);
    };
    RunSharesInTwoParts(count, apply_forces, next_passes, last_read);
    ahead_ = {true, early ? split : -1, velocities != nullptr ? beta : 0.0f};
  } else {
    RunShares(count, apply_forces);
  }
  totals_recorded_ = false;
  totals_scheduled_ = false;
}

}  // namespace msm_sim::core
