#pragma once

#include <vector>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A run of springs that a vectorised loop can take at once: springs first .. first + count - 1
/// of the schedule join nodes a0 + i and a0 + offset + i (i < count), so the loop reads and
/// writes the node arrays contiguously.
struct SpringRun {
  int first;
  int a0;
  int offset;  // b - a, > 0
  int count;   // 1 .. SpringSchedule::kMaxRunLength
};

/// The springs of a Model re-ordered for the vectorised force kernels (force_kernels.h): every
/// spring oriented so that a < b, then sorted by the index offset b - a and by a, and cut into
/// runs of consecutive a. On a cubic lattice, whose nodes are numbered row by row, a run is a
/// row of parallel springs (about as long as the row); on a random lattice most runs have one
/// spring, and the evaluator keeps its per-spring loops (see `vectorisable`).
struct SpringSchedule {
  /// Longest run; bounds the kernels' per-run scratch.
  static constexpr int kMaxRunLength = 64;
  /// Mean run length from which the run kernels beat the per-spring loops: runs of one would pay
  /// a loop set-up per spring (docs/design/speed-against-bullet.md).
  static constexpr double kMinMeanRunLength = 4.0;

  std::vector<SpringRun> runs;
  /// Model index of the spring at each schedule position.
  std::vector<SpringIndex> model_index;
  /// Whether the scheduled spring's ends are the model's b, a (swapped to make a < b).
  std::vector<char> swapped;

  int num_springs() const { return static_cast<int>(model_index.size()); }
  bool vectorisable() const {
    return !runs.empty() && num_springs() >= kMinMeanRunLength * static_cast<double>(runs.size());
  }

  /// Copies a per-spring array from model order into schedule order.
  std::vector<double> ToSchedule(const double* model_order) const;
  /// The same for a per-end array (one value per spring at its a or b end): the scheduled a end
  /// takes `end_b` where the spring is swapped.
  std::vector<double> ToScheduleEnd(const double* end_a, const double* end_b) const;
};

/// Schedules the model's springs (deterministic: ties keep the model order).
SpringSchedule ScheduleSprings(const Model& model);

}  // namespace msm_sim::core
