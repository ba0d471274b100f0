#pragma once

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Summary figures every builder reports (docs/physics.md §2.2): counts, spring connectivity and
/// lengths.
struct ModelStatistics {
  int nodes = 0;
  int springs = 0;
  double mean_springs_per_node = 0.0;  ///< <S> = 2 S_total / N
  double mean_spring_length = 0.0;     ///< <L> (m)
  double spring_length_stddev = 0.0;   ///< dL (m)
  double total_mass = 0.0;             ///< kg
  double added_mass = 0.0;             ///< kg of total_mass from mass scaling (Model::added_mass)
};

ModelStatistics ComputeModelStatistics(const Model& model);

}  // namespace msm_sim::core
