// ForceEvaluator's linearisation and stiffness diagonal through the run kernels (models with a
// spring schedule: linear springs, no Baudet elements). Both work in schedule order only: the
// per-spring arrays of force_evaluator_stiffness.cpp are left unfilled, since every user of the
// linearisation takes the runs when there is a schedule.

#include <algorithm>

#include "mechanics/force_kernels.h"
#include "mechanics/linearization_kernels.h"
#include "mechanics/share_plan.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {

void ForceEvaluator::LinearizeScheduled(const Eigen::Matrix3Xd& positions, bool drop_compression) {
  // The two-pass total tensions in double, whatever the caller's precision (K and the solve
  // need the exact tensions), as AccumulateRuns computes them but without dampers and forces;
  // the dispersion g of the caller's last evaluation (dispersion_per_weight_) is left alone.
  const Eigen::Index n = model_->num_nodes();
  const int count = model_->num_springs();
  node_arrays_.resize(9 * n);
  double* x = node_arrays_.data();
  ToNodeArrays(positions.data(), n, x);
  const NodeArrays x_arrays{x, x + n, x + 2 * n};
  const ScheduledSprings springs = scheduled_->View();
  const int num_runs = static_cast<int>(scheduled_->schedule.runs.size());
  scheduled_linearization_.resize(4 * static_cast<Eigen::Index>(count));
  double* storage = scheduled_linearization_.data();
  double* totals = scheduled_totals_.data();
  if (model_->dispersion_fraction() == 0.0) {
    plan_->ForSpringShares(num_runs, nullptr, 0, [&](int begin, int end, double*) {
      LinearizePlainRuns(springs, begin, end, count, x_arrays, drop_compression, totals, storage);
    });
  } else {
    InflowRunsToAccumulator(x);
    accumulator_.array() *= inverse_star_weight_.array();  // now g = J / W
    plan_->ForSpringShares(num_runs, nullptr, 0, [&](int begin, int end, double*) {
      LinearizeDispersedRuns(springs, begin, end, count, x_arrays, accumulator_.data(),
                             drop_compression, totals, storage);
    });
  }
  // total_tensions() now answers with these tensions, as after a double evaluation.
  totals_recorded_ = true;
  totals_scheduled_ = true;
  if (single_) RoundLinearization();
}

Eigen::Matrix3Xd ForceEvaluator::ScheduledStiffnessDiagonal() const {
  // Per node: the springs' blocks (diagonal), then, with dispersion, the coupling of the node to
  // itself through its own J, (1 / W) s1 s2 (see SpringStiffnessDiagonal).
  const Eigen::Index n = model_->num_nodes();
  const bool disperse = model_->dispersion_fraction() != 0.0;
  const Eigen::Index blocks = disperse ? 9 : 3;
  diagonal_arrays_.setZero(blocks * n);
  double* d = diagonal_arrays_.data();
  // Blocks of N: the diagonal's x, y, z, then with dispersion s1's and s2's.
  const auto block = [n, disperse](double* sums, int b) {
    return disperse || b < 3 ? sums + b * n : nullptr;
  };
  const ScheduledSprings springs = scheduled_->View();
  const int num_runs = static_cast<int>(scheduled_->schedule.runs.size());
  const ScheduledLinearization linearization =
      ScheduledLinearization::Of(scheduled_linearization_.data(), model_->num_springs());
  const double* inverse_weight = disperse ? inverse_star_weight_.data() : nullptr;
  plan_->ForSpringShares(num_runs, d, blocks * n, [&](int begin, int end, double* target) {
    StiffnessDiagonalRuns(springs, begin, end, linearization, inverse_weight,
                          {block(target, 0), block(target, 1), block(target, 2)},
                          {block(target, 3), block(target, 4), block(target, 5)},
                          {block(target, 6), block(target, 7), block(target, 8)});
  });
  Eigen::Matrix3Xd out(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      double value = d[axis * n + i];
      if (disperse) {
        value += inverse_star_weight_[i] * (block(d, 3 + axis)[i] * block(d, 6 + axis)[i]);
      }
      out(axis, i) = value;
    }
  }
  return out;
}

}  // namespace msm_sim::core
