#include "msm_sim/experiments/cantilever_experiment.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/dof_constraints.h"

namespace msm_sim::core {
namespace {

// Which nodes are held, which carry the load, and where the profile's x starts.
struct BarEnds {
  std::vector<int> loaded;
  std::vector<bool> lattice;  // false for face anchors: fixed points, not material layers
  double clamp_x = 0.0;       // m, origin of the profile's x
  double load_x = 0.0;        // m, mean rest x of the loaded nodes
  double x_first = 0.0;       // m, lowest and highest rest x of the lattice nodes
  double x_last = 0.0;
};

// The lattice nodes within `depth` of the highest lattice x carry the load.
void SelectLoaded(const Eigen::Matrix3Xd& rest, double depth, BarEnds* ends) {
  for (int i = 0; i < rest.cols(); ++i) {
    if (ends->lattice[i] && rest(0, i) >= ends->x_last - depth) {
      ends->loaded.push_back(i);
      ends->load_x += rest(0, i);
    }
  }
  ends->load_x /= static_cast<double>(ends->loaded.size());
}

// kNodeLayers: freezes the nodes within `depth` of the lowest rest x (thesis 3.2.6).
BarEnds FreezeFirstLayer(const Eigen::Matrix3Xd& rest, double depth, DofConstraints* constraints,
                         CantileverExperimentResult* result) {
  BarEnds ends;
  ends.lattice.assign(rest.cols(), true);
  ends.x_first = rest.row(0).minCoeff();
  ends.x_last = rest.row(0).maxCoeff();
  for (int i = 0; i < rest.cols(); ++i) {
    if (rest(0, i) > ends.x_first + depth) continue;
    constraints->FixNode(i);
    ends.clamp_x += rest(0, i);
    ++result->clamped_nodes;
  }
  ends.clamp_x /= result->clamped_nodes;
  return ends;
}

// kFaces: freezes the anchors on the face x = 0 and nothing else.
BarEnds FreezeFaceAnchors(const Model& model, DofConstraints* constraints,
                          CantileverExperimentResult* result) {
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const std::vector<NodeIndex> anchors = AnchorNodes(model, AnchoredPlane{});
  if (anchors.empty()) {
    throw std::invalid_argument(
        "a cantilever clamped at its face needs a model with anchors on the face x = 0 (a "
        "node-centred cubic lattice built with an anchored plane there)");
  }
  BarEnds ends;
  ends.lattice.assign(rest.cols(), true);
  for (NodeIndex i : anchors) {
    constraints->FixNode(i);
    ends.lattice[i] = false;
  }
  result->clamped_nodes = static_cast<int>(anchors.size());
  ends.x_first = INFINITY;
  ends.x_last = -INFINITY;
  for (int i = 0; i < rest.cols(); ++i) {
    if (!ends.lattice[i]) continue;
    ends.x_first = std::min(ends.x_first, rest(0, i));
    ends.x_last = std::max(ends.x_last, rest(0, i));
  }
  return ends;
}

// The force F in -z shared by the loaded nodes and, if moment_arm != 0, the couple moment_arm F
// about y (axial forces proportional to z - z_mean) that moves its line of action moment_arm
// further along +x: statically the same load as F at x = load_x + moment_arm.
Eigen::Matrix3Xd EndLoad(const Eigen::Matrix3Xd& rest, const std::vector<int>& loaded, double force,
                         double moment_arm) {
  Eigen::Matrix3Xd external = Eigen::Matrix3Xd::Zero(3, rest.cols());
  double z_mean = 0.0;
  for (int i : loaded) {
    external(2, i) = -force / static_cast<double>(loaded.size());
    z_mean += rest(2, i) / static_cast<double>(loaded.size());
  }
  double second_moment = 0.0;
  for (int i : loaded) second_moment += std::pow(rest(2, i) - z_mean, 2);
  if (moment_arm == 0.0 || second_moment == 0.0) return external;
  // A downward force hogs the bar: the couple pulls the upper fibres towards +x.
  for (int i : loaded) external(0, i) = moment_arm * force * (rest(2, i) - z_mean) / second_moment;
  return external;
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

// Mean deflection per lattice layer of width a along x, from ends.clamp_x, beside the theory.
std::vector<DeflectionSample> DeflectionProfile(const Eigen::Matrix3Xd& rest,
                                                const Eigen::Matrix3Xd& positions, double a,
                                                const BarEnds& ends, const BeamTheory& theory) {
  struct Layer {
    double x_sum = 0.0;
    double deflection_sum = 0.0;
    int count = 0;
  };
  std::map<long, Layer> layers;
  for (int i = 0; i < rest.cols(); ++i) {
    if (!ends.lattice[i]) continue;
    Layer& layer = layers[std::lround((rest(0, i) - ends.x_first) / a)];
    layer.x_sum += rest(0, i);
    layer.deflection_sum += rest(2, i) - positions(2, i);
    ++layer.count;
  }
  std::vector<DeflectionSample> profile;
  for (const auto& [index, layer] : layers) {
    const double x = layer.x_sum / layer.count - ends.clamp_x;
    profile.push_back({x, layer.deflection_sum / layer.count, theory(std::max(0.0, x))});
  }
  return profile;
}

// The profile's last two samples extrapolated linearly to x.
double ExtrapolatedDeflection(const std::vector<DeflectionSample>& profile, double x) {
  const DeflectionSample& last = profile[profile.size() - 1];
  const DeflectionSample& before = profile[profile.size() - 2];
  const double slope = (last.deflection - before.deflection) / (last.x - before.x);
  return last.deflection + slope * (x - last.x);
}

}  // namespace

CantileverExperimentResult RunCantileverExperiment(const Model& model,
                                                   const CantileverExperimentOptions& options) {
  if (!std::isfinite(options.total_force) || options.total_force == 0.0) {
    throw std::invalid_argument("cantilever force must be finite and non-zero");
  }
  const auto& rest = model.rest_positions();
  const double a = model.characteristic_length();
  const double depth = options.end_layer_depth > 0.0 ? options.end_layer_depth : 0.5 * a;
  const bool faces = options.ends == CantileverEnds::kFaces;

  CantileverExperimentResult result;
  DofConstraints constraints(model.num_nodes());
  BarEnds ends = faces ? FreezeFaceAnchors(model, &constraints, &result)
                       : FreezeFirstLayer(rest, depth, &constraints, &result);
  if (ends.x_last - ends.x_first < 2.0 * a) {
    throw std::invalid_argument("the bar needs at least three node layers along x");
  }
  SelectLoaded(rest, depth, &ends);
  result.loaded_nodes = static_cast<int>(ends.loaded.size());
  const double length = options.body_size.x();
  result.beam_length = faces ? length : ends.load_x - ends.clamp_x;

  const Eigen::Matrix3Xd external =
      EndLoad(rest, ends.loaded, options.total_force, faces ? length - ends.load_x : 0.0);
  const double per_node = options.total_force / result.loaded_nodes;
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
  result.profile = DeflectionProfile(rest, positions, a, ends, theory);
  result.end_face_deflection = ExtrapolatedDeflection(result.profile, length - ends.clamp_x);
  if (faces) result.profile.insert(result.profile.begin(), DeflectionSample{0.0, 0.0, 0.0});
  return result;
}

}  // namespace msm_sim::core
