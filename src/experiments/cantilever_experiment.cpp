#include "msm_sim/experiments/cantilever_experiment.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "msm_sim/mechanics/dof_constraints.h"

namespace msm_sim::core {

CantileverExperimentResult RunCantileverExperiment(const Model& model,
                                                   const CantileverExperimentOptions& options) {
  if (!std::isfinite(options.total_force) || options.total_force == 0.0) {
    throw std::invalid_argument("cantilever force must be finite and non-zero");
  }
  const auto& rest = model.rest_positions();
  const int n = model.num_nodes();
  const double a = model.characteristic_length();
  const double depth = options.end_layer_depth > 0.0 ? options.end_layer_depth : 0.5 * a;
  const double x_first = rest.row(0).minCoeff();
  const double x_last = rest.row(0).maxCoeff();
  if (x_last - x_first < 2.0 * a) {
    throw std::invalid_argument("the bar needs at least three node layers along x");
  }

  CantileverExperimentResult result;
  DofConstraints constraints(n);
  std::vector<int> loaded;
  double clamp_x = 0.0;
  double load_x = 0.0;
  for (int i = 0; i < n; ++i) {
    if (rest(0, i) <= x_first + depth) {
      constraints.FixNode(i);
      clamp_x += rest(0, i);
      ++result.clamped_nodes;
    } else if (rest(0, i) >= x_last - depth) {
      loaded.push_back(i);
      load_x += rest(0, i);
    }
  }
  result.loaded_nodes = static_cast<int>(loaded.size());
  clamp_x /= result.clamped_nodes;
  load_x /= result.loaded_nodes;
  result.beam_length = load_x - clamp_x;

  Eigen::Matrix3Xd external = Eigen::Matrix3Xd::Zero(3, n);
  const double per_node = options.total_force / result.loaded_nodes;
  for (int i : loaded) external(2, i) = -per_node;

  StaticSolverOptions solver = options.solver;
  if (solver.force_tolerance <= 0.0) solver.force_tolerance = 1e-7 * std::abs(per_node);
  Eigen::Matrix3Xd positions = rest;
  result.solver = SolveStaticEquilibrium(model, constraints, external, solver, &positions);

  const Eigen::Vector3d& size = options.body_size;
  const double inertia = size.y() * std::pow(size.z(), 3) / 12.0;
  const double flexural = 6.0 * model.material().youngs_modulus() * inertia;
  const double length = result.beam_length;
  const auto theory = [&](double x) {
    return options.total_force * x * x * (3.0 * length - x) / flexural;
  };
  result.theory_tip_deflection = theory(length);

  double tip = 0.0;
  for (int i : loaded) tip += rest(2, i) - positions(2, i);
  result.tip_deflection = tip / result.loaded_nodes;

  // Profile: mean deflection per layer of width ã along x.
  struct Layer {
    double x_sum = 0.0;
    double deflection_sum = 0.0;
    int count = 0;
  };
  std::map<long, Layer> layers;
  for (int i = 0; i < n; ++i) {
    Layer& layer = layers[std::lround((rest(0, i) - x_first) / a)];
    layer.x_sum += rest(0, i);
    layer.deflection_sum += rest(2, i) - positions(2, i);
    ++layer.count;
  }
  for (const auto& [index, layer] : layers) {
    const double x = layer.x_sum / layer.count - clamp_x;
    result.profile.push_back({x, layer.deflection_sum / layer.count, theory(std::max(0.0, x))});
  }
  return result;
}

}  // namespace msm_sim::core
