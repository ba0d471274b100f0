#include "msm_sim/model/model_statistics.h"

#include <cmath>

namespace msm_sim::core {

ModelStatistics ComputeModelStatistics(const Model& model) {
  ModelStatistics stats;
  stats.nodes = model.num_nodes();
  stats.springs = model.num_springs();
  stats.mean_springs_per_node = 2.0 * stats.springs / stats.nodes;
  stats.total_mass = model.masses().sum();
  stats.added_mass = model.added_mass();
  if (stats.springs > 0) {
    double sum = 0.0;
    double sum_sq = 0.0;
    for (double length : model.spring_rest_length()) {
      sum += length;
      sum_sq += length * length;
    }
    stats.mean_spring_length = sum / stats.springs;
    const double variance =
        sum_sq / stats.springs - stats.mean_spring_length * stats.mean_spring_length;
    stats.spring_length_stddev = std::sqrt(std::max(0.0, variance));
  }
  return stats;
}

}  // namespace msm_sim::core
