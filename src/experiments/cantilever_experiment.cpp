#include "msm_sim/experiments/cantilever_experiment.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "msm_sim/mechanics/dof_constraints.h"

namespace msm_sim::core {
namespace {

// The nodes that carry the load and where the frozen layer sits.
struct BarEnds {
  std::vector<int> loaded;
  double clamp_x = 0.0;  // m, mean rest x of the frozen nodes
};

// Freezes the nodes within `depth` of the lowest rest x and picks those within it of the highest
// to carry the load; fills in the result's node counts and beam length.
BarEnds ClampAndSelectLoaded(const Eigen::Matrix3Xd& rest, double x_first, double x_last,
                             double depth, DofConstraints* constraints,
                             CantileverExperimentResult* result) {
  BarEnds ends;
  double load_x = 0.0;
  for (int i = 0; i < rest.cols(); ++i) {
    if (rest(0, i) <= x_first + depth) {
      constraints->FixNode(i);
      ends.clamp_x += rest(0, i);
      ++result->clamped_nodes;
    } else if (rest(0, i) >= x_last - depth) {
      ends.loaded.push_back(i);
      load_x += rest(0, i);
    }
  }
  result->loaded_nodes = static_cast<int>(ends.loaded.size());
  ends.clamp_x /= result->clamped_nodes;
  load_x /= result->loaded_nodes;
  result->beam_length = load_x - ends.clamp_x;
  return ends;
}

// Euler-Bernoulli deflection F x^2 (3 L - x) / (6 E I) of a cantilever of length L.
struct BeamTheory {
  double force;     // N
  double length;    // m
  double flexural;  // 6 E I
  double operator()(double x) const { return force * x * x * (3.0 * length - x) / flexural; }
};

// Mean -u_z of `nodes`, positive down.
double MeanDeflection(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& positions,
                      const std::vector<int>& nodes) {
  double sum = 0.0;
  for (int i : nodes) sum += rest(2, i) - positions(2, i);
  return sum / static_cast<int>(nodes.size());
}

// Mean deflection per layer of width a along x, from the clamp, beside the theory.
std::vector<DeflectionSample> DeflectionProfile(const Eigen::Matrix3Xd& rest,
                                                const Eigen::Matrix3Xd& positions, double x_first,
                                                double a, double clamp_x,
                                                const BeamTheory& theory) {
  struct Layer {
    double x_sum = 0.0;
    double deflection_sum = 0.0;
    int count = 0;
  };
  std::map<long, Layer> layers;
  for (int i = 0; i < rest.cols(); ++i) {
    Layer& layer = layers[std::lround((rest(0, i) - x_first) / a)];
    layer.x_sum += rest(0, i);
    layer.deflection_sum += rest(2, i) - positions(2, i);
    ++layer.count;
  }
  std::vector<DeflectionSample> profile;
  for (const auto& [index, layer] : layers) {
    const double x = layer.x_sum / layer.count - clamp_x;
    profile.push_back({x, layer.deflection_sum / layer.count, theory(std::max(0.0, x))});
  }
  return profile;
}

}  // namespace

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
  const BarEnds ends = ClampAndSelectLoaded(rest, x_first, x_last, depth, &constraints, &result);

  Eigen::Matrix3Xd external = Eigen::Matrix3Xd::Zero(3, n);
  const double per_node = options.total_force / result.loaded_nodes;
  for (int i : ends.loaded) external(2, i) = -per_node;

  StaticSolverOptions solver = options.solver;
  if (solver.force_tolerance <= 0.0) solver.force_tolerance = 1e-7 * std::abs(per_node);
  Eigen::Matrix3Xd positions = rest;
  result.solver = SolveStaticEquilibrium(model, constraints, external, solver, &positions);

  const Eigen::Vector3d& size = options.body_size;
  const double inertia = size.y() * std::pow(size.z(), 3) / 12.0;
  const BeamTheory theory{options.total_force, result.beam_length,
                          6.0 * model.material().youngs_modulus() * inertia};
  result.theory_tip_deflection = theory(result.beam_length);
  result.tip_deflection = MeanDeflection(rest, positions, ends.loaded);
  result.profile = DeflectionProfile(rest, positions, x_first, a, ends.clamp_x, theory);
  return result;
}

}  // namespace msm_sim::core
