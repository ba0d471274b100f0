#include "msm_sim/model/model_builder.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace msm_sim::core {

NodeIndex ModelBuilder::AddNode(const Eigen::Vector3d& rest_position, double mass,
                                double surface_inset) {
  if (!(mass > 0.0) || !std::isfinite(mass) || !rest_position.allFinite()) {
    throw std::invalid_argument("node mass must be finite and > 0 and its position finite");
  }
  if (!(surface_inset >= 0.0) || !std::isfinite(surface_inset)) {
    throw std::invalid_argument("a node's surface inset must be finite and >= 0");
  }
  positions_.push_back(rest_position);
  masses_.push_back(mass);
  surface_insets_.push_back(surface_inset);
  return static_cast<NodeIndex>(masses_.size() - 1);
}

SpringIndex ModelBuilder::AddSpring(NodeIndex a, NodeIndex b, double stiffness) {
  if (a == b || a < 0 || b < 0 || a >= num_nodes() || b >= num_nodes()) {
    throw std::invalid_argument("spring must join two distinct existing nodes, got " +
                                std::to_string(a) + " and " + std::to_string(b));
  }
  const double length = (positions_[b] - positions_[a]).norm();
  if (!(length > 0.0)) throw std::invalid_argument("spring joins two coincident nodes");
  if (!(stiffness > 0.0) || !std::isfinite(stiffness)) {
    throw std::invalid_argument("spring stiffness must be finite and > 0");
  }
  node_a_.push_back(a);
  node_b_.push_back(b);
  rest_length_.push_back(length);
  stiffness_.push_back(stiffness);
  weight_a_.push_back(1.0);
  weight_b_.push_back(1.0);
  return static_cast<SpringIndex>(stiffness_.size() - 1);
}

void ModelBuilder::AddScaledMass(NodeIndex node, double extra) {
  if (!(extra >= 0.0) || !std::isfinite(extra)) {
    throw std::invalid_argument("added mass must be finite and >= 0");
  }
  masses_[node] += extra;
  added_mass_ += extra;
}

void ModelBuilder::AddStiffness(SpringIndex spring, double extra) { stiffness_[spring] += extra; }

void ModelBuilder::SetDispersionWeight(SpringIndex spring, NodeIndex node, double weight) {
  (node_a_[spring] == node ? weight_a_ : weight_b_)[spring] = weight;
}

void ModelBuilder::SetSpringLaw(SpringLaw law, const PowerSpringLaw& power) {
  if (law == SpringLaw::kPower &&
      !(std::isfinite(power.alpha) && std::isfinite(power.beta) && power.beta >= 0.0)) {
    throw std::invalid_argument(
        "power spring law: alpha must be finite and beta finite and >= 0, got alpha " +
        std::to_string(power.alpha) + ", beta " + std::to_string(power.beta));
  }
  spring_law_ = law;
  // The members of the family of docs/physics.md §4.1 that the other laws are.
  if (law == SpringLaw::kPower) {
    power_spring_law_ = power;
  } else {
    power_spring_law_ = PowerSpringLaw{law == SpringLaw::kLinear ? 1.0 : -1.0, 0.0};
  }
}

Model ModelBuilder::Build(double volume, double characteristic_length) const {
  if (masses_.empty()) throw std::invalid_argument("the model has no nodes");
  if (!(volume > 0.0) || !(characteristic_length > 0.0)) {
    throw std::invalid_argument("model volume and characteristic length must be > 0");
  }
  Model model(material_);
  const int n = num_nodes();
  model.rest_positions_.resize(3, n);
  model.masses_.resize(n);
  model.surface_insets_.resize(n);
  for (int i = 0; i < n; ++i) {
    model.rest_positions_.col(i) = positions_[i];
    model.masses_[i] = masses_[i];
    model.surface_insets_[i] = surface_insets_[i];
  }
  model.spring_node_a_ = node_a_;
  model.spring_node_b_ = node_b_;
  model.spring_rest_length_ = rest_length_;
  model.spring_stiffness_ = stiffness_;
  model.dispersion_weight_a_ = weight_a_;
  model.dispersion_weight_b_ = weight_b_;
  model.correction_edges_ = correction_edges_;
  model.correction_coefficients_ = correction_coefficients_;

  // Compressed incidence lists (counting sort by node).
  model.incidence_offsets_.assign(n + 1, 0);
  for (std::size_t s = 0; s < node_a_.size(); ++s) {
    ++model.incidence_offsets_[node_a_[s] + 1];
    ++model.incidence_offsets_[node_b_[s] + 1];
  }
  for (int i = 0; i < n; ++i) model.incidence_offsets_[i + 1] += model.incidence_offsets_[i];
  model.incident_springs_.resize(model.incidence_offsets_[n]);
  std::vector<std::int32_t> cursor(model.incidence_offsets_.begin(),
                                   model.incidence_offsets_.end() - 1);
  for (std::size_t s = 0; s < node_a_.size(); ++s) {
    model.incident_springs_[cursor[node_a_[s]]++] = static_cast<SpringIndex>(s);
    model.incident_springs_[cursor[node_b_[s]]++] = static_cast<SpringIndex>(s);
  }
  model.spring_law_ = spring_law_;
  model.power_spring_law_ = power_spring_law_;
  model.dispersion_fraction_ = dispersion_fraction_;
  model.self_calibration_ = self_calibration_;
  model.added_mass_ = added_mass_;
  model.mass_scaling_limited_ = mass_scaling_limited_;
  model.volume_ = volume;
  model.characteristic_length_ = characteristic_length;
  return model;
}

}  // namespace msm_sim::core
