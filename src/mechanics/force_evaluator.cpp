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
                                                  max_threads)) {
  single_loops_.passes =
      internal::Copied<internal::SinglePasses>(std::make_unique<internal::SinglePasses>());
  const int n = model.num_nodes();
  const int num_springs = model.num_springs();
  const double q = model.dispersion_fraction();
  // Star weight W of every node: the sum of its springs' outflow weights w = v k L0^2 (the
  // spring count b, up to a common factor, for the paper's equal shares).
  Eigen::VectorXd star_weight = Eigen::VectorXd::Zero(n);
  dispersion_.inflow_a.resize(num_springs);
  dispersion_.inflow_b.resize(num_springs);
  dispersion_.outflow_a.resize(num_springs);
  dispersion_.outflow_b.resize(num_springs);
  for (int s = 0; s < num_springs; ++s) {
    const double rest = model.spring_rest_length()[s];
    const double k_l2 = model.spring_stiffness()[s] * rest * rest;
    const double va = model.dispersion_weight_a()[s];
    const double vb = model.dispersion_weight_b()[s];
    // w = v k L0^2 makes the dispersion conservative (see Model::dispersion_weight_a).
    star_weight[model.spring_node_a()[s]] += va * k_l2;
    star_weight[model.spring_node_b()[s]] += vb * k_l2;
    dispersion_.inflow_a[s] = q * rest * va;
    dispersion_.inflow_b[s] = q * rest * vb;
    dispersion_.outflow_a[s] = va * k_l2 / rest;
    dispersion_.outflow_b[s] = vb * k_l2 / rest;
  }
  dispersion_.inverse_star_weight.resize(n);
  for (int i = 0; i < n; ++i) {
    dispersion_.inverse_star_weight[i] = star_weight[i] > 0.0 ? 1.0 / star_weight[i] : 0.0;
  }
  per_spring_.tensions.setZero(num_springs);
  per_spring_.inverse_lengths.setZero(num_springs);
  totals_.model_order.setZero(num_springs);
  dispersion_.accumulator.setZero(n);
  dispersion_.per_weight.setZero(n);
  // The run kernels know linear springs only, and the Baudet pass adds to model-order tensions.
  if (kernels == SpringKernels::kAuto && model.spring_law() == SpringLaw::kLinear &&
      model.correction_edges().empty()) {
    runs_.springs = ScheduleRuns(model, dispersion_.inflow_a, dispersion_.inflow_b,
                                 dispersion_.outflow_a, dispersion_.outflow_b);
    if (runs_.springs) runs_.totals.setZero(num_springs);
  }
}

ForceEvaluator::ForceEvaluator(const ForceEvaluator& other) = default;
ForceEvaluator::ForceEvaluator(ForceEvaluator&& other) noexcept = default;
ForceEvaluator& ForceEvaluator::operator=(const ForceEvaluator& other) = default;
ForceEvaluator& ForceEvaluator::operator=(ForceEvaluator&& other) noexcept = default;
ForceEvaluator::~ForceEvaluator() = default;

void ForceEvaluator::set_orientation_barrier(std::shared_ptr<const OrientationBarrier> barrier) {
  barrier_ = std::move(barrier);
  barrier_reference_ = BarrierReference{};
  single_loops_.passes->ForgetAhead();
}

void ForceEvaluator::set_max_threads(int max_threads) {
  plan_->set_max_threads(max_threads);
  single_loops_.passes->ForgetAhead();  // the shares' overflows move
}

void ForceEvaluator::set_precision(SpringPrecision precision) {
  precision_ = precision;
  single_loops_.passes->ForgetAhead();
  if (precision == SpringPrecision::kDouble || !runs_.springs) {
    single_loops_.springs.reset();
  } else if (!single_loops_.springs) {
    single_loops_.springs = SinglePrecisionSprings::Schedule(*model_);
    // A linearisation from before takes the single-precision products from now on.
    if (runs_.linearization.size() == 4 * static_cast<Eigen::Index>(model_->num_springs())) {
      RoundLinearization();
    }
  }
}

const Eigen::VectorXd& ForceEvaluator::total_tensions() const {
  if (!totals_.recorded) {
    throw std::logic_error(
        "ForceEvaluator::total_tensions: the last evaluation was single precision, which records "
        "no tensions; evaluate in double (set_precision(SpringPrecision::kDouble)) first");
  }
  if (totals_.scheduled) {
    const std::vector<SpringIndex>& model_index = runs_.springs->schedule.model_index;
    for (std::size_t p = 0; p < model_index.size(); ++p) {
      totals_.model_order[model_index[p]] = runs_.totals[static_cast<Eigen::Index>(p)];
    }
    totals_.scheduled = false;
  }
  return totals_.model_order;
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

bool ForceEvaluator::UsesSingleLoops() const {
  // As Accumulate chooses: the run kernels in single precision where the model has them.
  return runs_.springs && single_loops_.springs;
}

void ForceEvaluator::Accumulate(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                Eigen::Matrix3Xd* forces) {
  totals_.recorded = true;
  // SetForces: every path but the single-precision loops adds to *forces.
  if (overwrite_forces_ && !(runs_.springs && single_loops_.springs)) forces->setZero();
  if (!runs_.springs) {
    AccumulatePerSpring(positions, damping, forces);
    return;
  }
  if (single_loops_.springs) {
    AccumulateSingle(positions, damping, forces);
  } else {
    AccumulateRuns(positions, damping, forces);
  }
  // The single-precision loops add the barrier on each share, before its `after` stage.
  if (barrier_ && !single_loops_.springs) {
    barrier_->AccumulateForces(positions, forces, &barrier_reference_);
  }
}

void ForceEvaluator::AccumulateRuns(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                    Eigen::Matrix3Xd* forces) {
  const Eigen::Index n = model_->num_nodes();
  runs_.node_arrays.resize(9 * n);
  double* x = runs_.node_arrays.data();
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
  const ScheduledSprings springs = runs_.springs->View();
  const int num_runs = static_cast<int>(runs_.springs->schedule.runs.size());
  double* totals = runs_.totals.data();
  if (model_->dispersion_fraction() == 0.0) {
    plan_->ForSpringShares(num_runs, f, 3 * n, [&](int begin, int end, double* target) {
      PlainRuns(springs, begin, end, x_arrays, run_damping, {target, target + n, target + 2 * n},
                totals);
    });
  } else {
    InflowRunsToAccumulator(x);
    dispersion_.per_weight = dispersion_.accumulator.cwiseProduct(dispersion_.inverse_star_weight);
    plan_->ForSpringShares(num_runs, f, 3 * n, [&](int begin, int end, double* target) {
      OutflowRuns(springs, begin, end, x_arrays, run_damping, dispersion_.per_weight.data(),
                  {target, target + n, target + 2 * n}, totals);
    });
  }
  AddNodeArrays(f, n, forces->data());
  totals_.scheduled = true;
}

void ForceEvaluator::InflowRunsToAccumulator(const double* x_arrays) {
  const Eigen::Index n = model_->num_nodes();
  const NodeArrays x{x_arrays, x_arrays + n, x_arrays + 2 * n};
  const ScheduledSprings springs = runs_.springs->View();
  const int num_runs = static_cast<int>(runs_.springs->schedule.runs.size());
  runs_.end_sums.setZero(2 * n);
  plan_->ForSpringShares(num_runs, runs_.end_sums.data(), 2 * n,
                         [&](int begin, int end, double* target) {
                           InflowRuns(springs, begin, end, x, target, target + n);
                         });
  dispersion_.accumulator =
      model_->dispersion_fraction() * (runs_.end_sums.head(n) + runs_.end_sums.tail(n));
}

void ForceEvaluator::AccumulateSingle(const Eigen::Matrix3Xd& positions, const Damping& damping,
                                      Eigen::Matrix3Xd* forces) {
  const internal::SingleInputs in{model_,           single_loops_.springs.get(),
                                  &positions,       damping.velocities,
                                  damping.beta,     single_loops_.stages,
                                  barrier_.get(),   dispersion_.inverse_star_weight.data(),
                                  overwrite_forces_};
  const internal::SingleOutputs out{forces, &barrier_forces_, &barrier_reference_};
  single_loops_.passes->Evaluate(*plan_, in, out);
  totals_.recorded = false;
  totals_.scheduled = false;
}

}  // namespace msm_sim::core
