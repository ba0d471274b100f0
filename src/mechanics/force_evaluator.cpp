// ForceEvaluator's construction and the order of its force passes: which loops an evaluation
// takes. The per-spring reference loops are in force_evaluator_reference.cpp, the share plan in
// share_plan.cpp, the single loops' stages in single_pipeline.cpp, the elastic energy and the
// linearisation in force_evaluator_stiffness.cpp.

#include "msm_sim/mechanics/force_evaluator.h"

#include <algorithm>
#include <functional>
#include <memory>
#include <stdexcept>
#include <utility>

#include "mechanics/force_kernels.h"
#include "mechanics/share_plan.h"
#include "mechanics/single_pipeline.h"
#include "mechanics/single_precision_kernels.h"

namespace msm_sim::core {

namespace {

// The schedule-order copy of the springs and their eMSM end coefficients that the run kernels
// read, or null where the springs do not line up in runs (SpringSchedule::vectorisable).
std::shared_ptr<const ScheduledSpringData> ScheduleRuns(const Model& model,
                                                        const Eigen::VectorXd& inflow_a,
                                                        const Eigen::VectorXd& inflow_b,
                                                        const Eigen::VectorXd& outflow_a,
                                                        const Eigen::VectorXd& outflow_b) {
  SpringSchedule schedule = ScheduleSprings(model);
  if (!schedule.vectorisable()) return nullptr;
  auto data = std::make_shared<ScheduledSpringData>();
  data->rest = schedule.ToSchedule(model.spring_rest_length().data());
  data->stiffness = schedule.ToSchedule(model.spring_stiffness().data());
  data->inflow_a = schedule.ToScheduleEnd(inflow_a.data(), inflow_b.data());
  data->inflow_b = schedule.ToScheduleEnd(inflow_b.data(), inflow_a.data());
  data->outflow_a = schedule.ToScheduleEnd(outflow_a.data(), outflow_b.data());
  data->outflow_b = schedule.ToScheduleEnd(outflow_b.data(), outflow_a.data());
  data->schedule = std::move(schedule);
  return data;
}

}  // namespace

ForceEvaluator::ForceEvaluator(const Model& model, SpringKernels kernels, int max_threads)
    : model_(&model),
      plan_(std::make_unique<internal::SharePlan>(model.num_nodes(), model.num_springs(),
                                                  max_threads)),
      single_passes_(std::make_unique<internal::SinglePasses>()) {
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
  // The run kernels know linear springs only, and the Baudet pass adds to model-order tensions.
  if (kernels == SpringKernels::kAuto && model.spring_law() == SpringLaw::kLinear &&
      model.correction_edges().empty()) {
    scheduled_ = ScheduleRuns(model, inflow_a_, inflow_b_, outflow_a_, outflow_b_);
    if (scheduled_) scheduled_totals_.setZero(num_springs);
  }
}

ForceEvaluator::ForceEvaluator(const ForceEvaluator& other) = default;
ForceEvaluator::ForceEvaluator(ForceEvaluator&& other) noexcept = default;
ForceEvaluator& ForceEvaluator::operator=(const ForceEvaluator& other) = default;
ForceEvaluator& ForceEvaluator::operator=(ForceEvaluator&& other) noexcept = default;
ForceEvaluator::~ForceEvaluator() = default;

void ForceEvaluator::set_orientation_barrier(std::shared_ptr<const OrientationBarrier> barrier) {
  barrier_ = std::move(barrier);
  single_passes_->ForgetAhead();
}

void ForceEvaluator::set_max_threads(int max_threads) {
  plan_->set_max_threads(max_threads);
  single_passes_->ForgetAhead();  // the shares' overflows move
}

void ForceEvaluator::set_precision(SpringPrecision precision) {
  precision_ = precision;
  single_passes_->ForgetAhead();
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

void ForceEvaluator::AccumulateForces(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xd* forces) {
  Accumulate(positions, Damping{}, forces);
}

void ForceEvaluator::AccumulateForces(const Eigen::Matrix3Xd& positions,
                                      const Eigen::Matrix3Xd& velocities, double damping_beta,
                                      Eigen::Matrix3Xd* forces) {
  Accumulate(positions, damping_beta == 0.0 ? Damping{} : Damping{velocities.data(), damping_beta},
             forces);
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
  single_passes_->Round(*single_, positions.data(),
                        velocities != nullptr ? velocities->data() : nullptr, begin, end, origin);
}

bool ForceEvaluator::UsesSingleLoops() const {
  // As Accumulate chooses: the run kernels in single precision where the model has them.
  return scheduled_ && single_;
}

int ForceEvaluator::NumNodeShares() const {
  return UsesSingleLoops() ? plan_->NodeShareCount() : 1;
}

void ForceEvaluator::ForEachNodeShare(const std::function<void(int, int, int)>& task) {
  const int count = NumNodeShares();
  internal::SharePlan::Run(count, [&](int t) {
    const SingleShare share = plan_->NodeShare(t, count);
    task(t, share.begin, share.end);
  });
}

void ForceEvaluator::CutNodeShares(const std::vector<NodeIndex>& busy, double busy_work) {
  if (plan_->Cut(busy, busy_work)) single_passes_->ForgetAhead();  // the overflows move
}

void ForceEvaluator::Accumulate(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                Eigen::Matrix3Xd* forces) {
  totals_recorded_ = true;
  // SetForces: every path but the single-precision loops adds to *forces.
  if (overwrite_forces_ && !(scheduled_ && single_)) forces->setZero();
  if (!scheduled_) {
    AccumulatePerSpring(positions, damping, forces);
    return;
  }
  if (single_) {
    AccumulateSingle(positions, damping, forces);
  } else {
    AccumulateRuns(positions, damping, forces);
  }
  // The single-precision loops add the barrier on each share, before its `after` stage.
  if (barrier_ && !single_) barrier_->AccumulateForces(positions, forces);
}

void ForceEvaluator::AccumulateRuns(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                    Eigen::Matrix3Xd* forces) {
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
    plan_->ForSpringShares(num_runs, f, 3 * n, [&](int begin, int end, double* target) {
      PlainRuns(springs, begin, end, x_arrays, run_damping, {target, target + n, target + 2 * n},
                totals);
    });
  } else {
    InflowRunsToAccumulator(x);
    dispersion_per_weight_ = accumulator_.cwiseProduct(inverse_star_weight_);
    plan_->ForSpringShares(num_runs, f, 3 * n, [&](int begin, int end, double* target) {
      OutflowRuns(springs, begin, end, x_arrays, run_damping, dispersion_per_weight_.data(),
                  {target, target + n, target + 2 * n}, totals);
    });
  }
  AddNodeArrays(f, n, forces->data());
  totals_scheduled_ = true;
}

void ForceEvaluator::InflowRunsToAccumulator(const double* x_arrays) {
  const Eigen::Index n = model_->num_nodes();
  const NodeArrays x{x_arrays, x_arrays + n, x_arrays + 2 * n};
  const ScheduledSprings springs = scheduled_->View();
  const int num_runs = static_cast<int>(scheduled_->schedule.runs.size());
  end_sums_.setZero(2 * n);
  plan_->ForSpringShares(num_runs, end_sums_.data(), 2 * n,
                         [&](int begin, int end, double* target) {
                           InflowRuns(springs, begin, end, x, target, target + n);
                         });
  accumulator_ = model_->dispersion_fraction() * (end_sums_.head(n) + end_sums_.tail(n));
}

void ForceEvaluator::AccumulateSingle(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                      Eigen::Matrix3Xd* forces) {
  const internal::SingleInputs in{
      model_,           single_.get(), &positions,     damping.velocities,
      damping.beta,     stages_,       barrier_.get(), inverse_star_weight_.data(),
      overwrite_forces_};
  const internal::SingleOutputs out{forces, &barrier_forces_};
  single_passes_->Evaluate(*plan_, in, out);
  totals_recorded_ = false;
  totals_scheduled_ = false;
}

}  // namespace msm_sim::core
