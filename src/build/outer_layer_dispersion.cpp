#include "build/outer_layer_dispersion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace msm_sim::core::lattice {
namespace {

// The fitting below stops when every recipient's share is within this of its target (a box
// takes about 200 sweeps), or after this many sweeps (an odd shape may not allow exact shares).
constexpr double kFittingTolerance = 1e-6;
constexpr int kMaxFittingSweeps = 1000;

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

void ShiftOuterLayerDispersion(const std::vector<std::vector<NodeIndex>>& recipients, double keep,
                               ModelBuilder* builder) {
  const int n = builder->num_nodes();
  const std::vector<double> star = StarWeights(*builder);
  // The bulk each outer node gives up (give > 0: a giver), and the nodes that may receive it.
  std::vector<double> give(n, 0.0);
  std::vector<char> is_recipient(n, 0);
  double given = 0.0;
  for (NodeIndex node = 0; node < n; ++node) {
    if (recipients[node].empty() || !(star[node] > 0.0)) continue;
    give[node] = (1.0 - keep) * star[node];
    given += give[node];
    for (const NodeIndex j : recipients[node]) is_recipient[j] = 1;
  }
  double recipient_star = 0.0;
  for (NodeIndex j = 0; j < n; ++j) recipient_star += is_recipient[j] ? star[j] : 0.0;
  if (!(given > 0.0) || !(recipient_star > 0.0)) return;
  // Iterative proportional fitting of the plan T_xj = a_x b_j over the neighbourhoods: each giver
  // gives exactly its share (the last update), each recipient j receives as nearly as the
  // neighbourhoods allow its share of the total if every recipient's star grew by the same factor
  // (target_of(j); exactly on a box). A plan that followed
  // each giver's neighbourhood alone piles the bulk of edges and corners onto the few nodes
  // beneath them, which then set the step.
  std::vector<double> a(n, 1.0), b(n, 1.0), column(n, 0.0);
  auto target_of = [&](NodeIndex j) { return given * star[j] / recipient_star; };
  auto sum_columns = [&] {
    std::fill(column.begin(), column.end(), 0.0);
    for (NodeIndex x = 0; x < n; ++x) {
      if (give[x] == 0.0) continue;
      for (const NodeIndex j : recipients[x]) column[j] += a[x];
    }
  };
  for (int sweep = 0; sweep < kMaxFittingSweeps; ++sweep) {
    sum_columns();
    double mismatch = 0.0;  // of the recipients' shares under the current plan
    for (NodeIndex j = 0; j < n; ++j) {
      if (is_recipient[j]) {
        mismatch = std::max(mismatch, std::abs(column[j] * b[j] / target_of(j) - 1.0));
      }
    }
    if (sweep > 0 && mismatch < kFittingTolerance) break;  // the givers' sums are exact
    for (NodeIndex j = 0; j < n; ++j) {
      if (is_recipient[j]) b[j] = target_of(j) / column[j];
    }
    for (NodeIndex x = 0; x < n; ++x) {
      if (give[x] == 0.0) continue;
      double row = 0.0;
      for (const NodeIndex j : recipients[x]) row += b[j];
      a[x] = give[x] / row;
    }
  }
  std::vector<double> scale(n, 1.0);
  std::vector<double> received(n, 0.0);
  for (NodeIndex x = 0; x < n; ++x) {
    if (give[x] == 0.0) continue;
    scale[x] = keep;
    for (const NodeIndex j : recipients[x]) received[j] += a[x] * b[j];
  }
  for (NodeIndex j = 0; j < n; ++j) {
    if (is_recipient[j]) scale[j] = 1.0 + received[j] / star[j];
  }
  for (SpringIndex s = 0; s < builder->num_springs(); ++s) {
    const NodeIndex node_a = builder->spring_node_a(s);
    const NodeIndex node_b = builder->spring_node_b(s);
    const double weight_a = builder->dispersion_weight_a(s);
    const double weight_b = builder->dispersion_weight_b(s);
    builder->SetDispersionWeight(s, node_a, scale[node_a] * weight_a);
    builder->SetDispersionWeight(s, node_b, scale[node_b] * weight_b);
  }
}

}  // namespace msm_sim::core::lattice
