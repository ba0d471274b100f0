#include "lattice/outer_layer_dispersion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace msm_sim::core::lattice {
namespace {

// The fitting below stops when every recipient's total is within this of its target, or after
// this many sweeps. The neighbourhoods need not allow exact totals, and near the limit the
// fitting crawls while the stable step no longer changes (docs/design/surface-dispersion.md);
// the givers' totals, hence the body's summed bulk, are exact after every sweep.
constexpr double kFittingTolerance = 1e-6;
constexpr int kMaxFittingSweeps = 100;

// W_x = sum of v k L0^2 over node x's spring ends.
std::vector<double> StarWeights(const ModelBuilder& builder) {
  std::vector<double> star(builder.num_nodes(), 0.0);
  for (SpringIndex s = 0; s < builder.num_springs(); ++s) {
    const double length = builder.spring_rest_length(s);
    const double w = builder.spring_stiffness(s) * length * length;
    star[builder.spring_node_a(s)] += builder.dispersion_weight_a(s) * w;
    star[builder.spring_node_b(s)] += builder.dispersion_weight_b(s) * w;
  }
  return star;
}

}  // namespace

void ValidateSurfaceDispersion(double keep) {
  if (!(keep > 0.0 && keep <= 1.0)) {
    throw std::invalid_argument("surface_dispersion must lie in (0, 1], got " +
                                std::to_string(keep));
  }
}

namespace {

// The recipients numbered compactly: receiving lists them, and edge[e] is the number of the
// recipient of the layer's neighbourhood entry e.
struct NumberedRecipients {
  std::vector<NodeIndex> receiving;
  std::vector<int> edge;
};

NumberedRecipients NumberRecipients(const OuterLayerNeighbourhoods& layer, int num_nodes) {
  NumberedRecipients numbered;
  std::vector<int> slot(num_nodes, -1);  // a recipient's number, -1 for other nodes
  numbered.edge.resize(layer.recipients.size());
  for (std::size_t e = 0; e < layer.recipients.size(); ++e) {
    const NodeIndex j = layer.recipients[e];
    if (slot[j] < 0) {
      slot[j] = static_cast<int>(numbered.receiving.size());
      numbered.receiving.push_back(j);
    }
    numbered.edge[e] = slot[j];
  }
  return numbered;
}

// Iterative proportional fitting of the plan T_gr = a_g b_r over the neighbourhoods, so that
// giver g gives give[g] and recipient r receives target[r]. A split that followed each giver's
// neighbourhood alone piled the bulk of edges and corners onto the few nodes beneath them, which
// then set the step.
void FitPlan(const OuterLayerNeighbourhoods& layer, const std::vector<int>& edge,
             const std::vector<double>& give, const std::vector<double>& target,
             std::vector<double>* a, std::vector<double>* b) {
  const int givers = static_cast<int>(give.size());
  std::vector<double> column(target.size());
  for (int sweep = 0; sweep < kMaxFittingSweeps; ++sweep) {
    std::fill(column.begin(), column.end(), 0.0);
    for (int g = 0; g < givers; ++g) {
      if (give[g] == 0.0) continue;
      for (int e = layer.offsets[g]; e < layer.offsets[g + 1]; ++e) column[edge[e]] += (*a)[g];
    }
    double mismatch = 0.0;  // of the recipients' totals under the current plan
    for (std::size_t r = 0; r < target.size(); ++r) {
      mismatch = std::max(mismatch, std::abs(column[r] * (*b)[r] / target[r] - 1.0));
    }
    // The givers' totals are exact here (the last update); stop if the recipients' are too.
    if (sweep > 0 && mismatch < kFittingTolerance) break;
    for (std::size_t r = 0; r < target.size(); ++r) (*b)[r] = target[r] / column[r];
    for (int g = 0; g < givers; ++g) {
      if (give[g] == 0.0) continue;
      double row = 0.0;
      for (int e = layer.offsets[g]; e < layer.offsets[g + 1]; ++e) row += (*b)[edge[e]];
      (*a)[g] = give[g] / row;
    }
  }
}

// Scales every spring end's dispersion weight by its node's factor.
void ScaleDispersionWeights(const std::vector<double>& scale, ModelBuilder* builder) {
  for (SpringIndex s = 0; s < builder->num_springs(); ++s) {
    const NodeIndex node_a = builder->spring_node_a(s);
    const NodeIndex node_b = builder->spring_node_b(s);
    const double weight_a = builder->dispersion_weight_a(s);
    const double weight_b = builder->dispersion_weight_b(s);
    builder->SetDispersionWeight(s, node_a, scale[node_a] * weight_a);
    builder->SetDispersionWeight(s, node_b, scale[node_b] * weight_b);
  }
}

}  // namespace

void ShiftOuterLayerDispersion(const OuterLayerNeighbourhoods& layer, double keep,
                               ModelBuilder* builder) {
  const std::vector<double> star = StarWeights(*builder);
  const NumberedRecipients numbered = NumberRecipients(layer, builder->num_nodes());
  const std::vector<NodeIndex>& receiving = numbered.receiving;
  const std::vector<int>& edge = numbered.edge;
  const int givers = static_cast<int>(layer.givers.size());
  std::vector<double> give(givers, 0.0);
  double given = 0.0;
  for (int g = 0; g < givers; ++g) {
    if (layer.offsets[g + 1] == layer.offsets[g]) continue;  // nowhere to go: keeps its bulk
    give[g] = (1.0 - keep) * star[layer.givers[g]];
    given += give[g];
  }
  double receiving_star = 0.0;
  for (const NodeIndex j : receiving) receiving_star += star[j];
  if (!(given > 0.0) || !(receiving_star > 0.0)) return;
  // Recipient r's target: its share of `given` if every recipient's W grew by the same factor.
  std::vector<double> target(receiving.size());
  for (std::size_t r = 0; r < receiving.size(); ++r) {
    target[r] = given * star[receiving[r]] / receiving_star;
  }
  std::vector<double> a(givers, 1.0), b(receiving.size(), 1.0);
  FitPlan(layer, edge, give, target, &a, &b);

  std::vector<double> scale(builder->num_nodes(), 1.0);
  std::vector<double> received(receiving.size(), 0.0);
  for (int g = 0; g < givers; ++g) {
    if (give[g] == 0.0) continue;
    scale[layer.givers[g]] = keep;
    for (int e = layer.offsets[g]; e < layer.offsets[g + 1]; ++e) {
      received[edge[e]] += a[g] * b[edge[e]];
    }
  }
  for (std::size_t r = 0; r < receiving.size(); ++r) {
    scale[receiving[r]] = 1.0 + received[r] / star[receiving[r]];
  }
  ScaleDispersionWeights(scale, builder);
}

}  // namespace msm_sim::core::lattice
