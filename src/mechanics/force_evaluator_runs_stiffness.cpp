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
  // the dispersion g of the caller's last evaluation (dispersion_.per_weight) is left alone.
  const Eigen::Index n = model_->num_nodes();
  const int count = model_->num_springs();
  runs_.node_arrays.resize(9 * n);
  double* x = runs_.node_arrays.data();
  ToNodeArrays(positions.data(), n, x);
  const NodeArrays x_arrays{x, x + n, x + 2 * n};
  const ScheduledSprings springs = runs_.springs->View();
  const int num_runs = static_cast<int>(runs_.springs->schedule.runs.size());
  runs_.linearization.resize(4 * static_cast<Eigen::Index>(count));
  double* storage = runs_.linearization.data();
  double* totals = runs_.totals.data();
  if (model_->dispersion_fraction() == 0.0) {
    plan_->ForSpringShares(num_runs, nullptr, 0, [&](int begin, int end, double*) {
      LinearizePlainRuns(springs, begin, end, count, x_arrays, drop_compression, totals, storage);
    });
  } else {
    InflowRunsToAccumulator(x);
    dispersion_.accumulator.array() *= dispersion_.inverse_star_weight.array();  // now g = J / W
    plan_->ForSpringShares(num_runs, nullptr, 0, [&](int begin, int end, double*) {
      LinearizeDispersedRuns(springs, begin, end, count, x_arrays, dispersion_.accumulator.data(),
                             drop_compression, totals, storage);
    });
  }
  // total_tensions() now answers with these tensions, as after a double evaluation.
  totals_.recorded = true;
  totals_.scheduled = true;
  if (single_loops_.springs) RoundLinearization();
}

Eigen::Matrix3Xd ForceEvaluator::ScheduledStiffnessDiagonal() const {
  // Per node: the springs' blocks (diagonal), then, with dispersion, the coupling of the node to
  // itself through its own J, (1 / W) s1 s2 (see SpringStiffnessDiagonal).
  const Eigen::Index n = model_->num_nodes();
  const bool disperse = model_->dispersion_fraction() != 0.0;
  const Eigen::Index blocks = disperse ? 9 : 3;
  runs_.diagonal_arrays.setZero(blocks * n);
  double* d = runs_.diagonal_arrays.data();
  // Blocks of N: the diagonal's x, y, z, then with dispersion s1's and s2's.
  const auto block = [n, disperse](double* sums, int b) {
    return disperse || b < 3 ? sums + b * n : nullptr;
  };
  const ScheduledSprings springs = runs_.springs->View();
  const int num_runs = static_cast<int>(runs_.springs->schedule.runs.size());
  const ScheduledLinearization linearization =
      ScheduledLinearization::Of(runs_.linearization.data(), model_->num_springs());
  const double* inverse_weight = disperse ? dispersion_.inverse_star_weight.data() : nullptr;
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
        value +=
            dispersion_.inverse_star_weight[i] * (block(d, 3 + axis)[i] * block(d, 6 + axis)[i]);
      }
      out(axis, i) = value;
    }
  }
  return out;
}

}  // namespace msm_sim::core
