#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Collects nodes and springs and compiles them into an immutable Model.
///
/// Lattice builders use it as their single way of making a Model, so that every Model satisfies
/// the invariants documented in model.h. Rest lengths are taken from the node rest positions.
class ModelBuilder {
 public:
  explicit ModelBuilder(const Material& material) : material_(material) {}

  /// Adds a node and returns its index. Precondition: mass > 0 and finite; surface_inset (m,
  /// Model::surface_insets) finite and >= 0.
  NodeIndex AddNode(const Eigen::Vector3d& rest_position, double mass, double surface_inset = 0.0);
  /// Adds a spring between two existing distinct nodes; returns its index.
  /// Precondition: stiffness > 0 and the nodes do not coincide.
  SpringIndex AddSpring(NodeIndex a, NodeIndex b, double stiffness);
  /// Adds `extra` (kg, finite, >= 0) to an existing node's mass and counts it as added mass
  /// (Model::added_mass: selective mass scaling, docs/physics.md §7).
  void AddScaledMass(NodeIndex node, double extra);
  /// Records mass added before (a model rebuilt from another: Model::added_mass, already in the
  /// masses given to AddNode) and whether its bound limited it (Model::mass_scaling_limited).
  void SetMassScaling(double added_mass, bool limited) {
    added_mass_ = added_mass;
    mass_scaling_limited_ = limited;
  }
  /// Adds `extra` (N/m) to an existing spring's stiffness.
  void AddStiffness(SpringIndex spring, double extra);
  /// Sets the eMSM dispersion weight of `spring` at its end `node` (starts at 1; see
  /// Model::dispersion_weight_a). Precondition: node is one of the spring's ends; weight >= 0
  /// (0: that end neither collects nor receives dispersion, as at a fixed face anchor).
  void SetDispersionWeight(SpringIndex spring, NodeIndex node, double weight);
  NodeIndex spring_node_a(SpringIndex s) const { return node_a_[s]; }
  double spring_stiffness(SpringIndex s) const { return stiffness_[s]; }
  double node_mass(NodeIndex node) const { return masses_[node]; }
  NodeIndex spring_node_b(SpringIndex s) const { return node_b_[s]; }
  double spring_rest_length(SpringIndex s) const { return rest_length_[s]; }
  /// The dispersion weights of spring s at its ends a and b (SetDispersionWeight).
  double dispersion_weight_a(SpringIndex s) const { return weight_a_[s]; }
  double dispersion_weight_b(SpringIndex s) const { return weight_b_[s]; }
  /// Adds a Baudet correction element (see Model::correction_edges): 4 x-, 4 y- and 4 z-edge
  /// springs and the coefficient c (N/m). Precondition: the springs exist.
  void AddCorrectionElement(const std::array<SpringIndex, 12>& edges, double coefficient) {
    correction_edges_.push_back(edges);
    correction_coefficients_.push_back(coefficient);
  }
  /// The law of every spring; `power` (alpha, beta) is used for SpringLaw::kPower only (see
  /// Model::power_spring_law). Throws std::invalid_argument for kPower with alpha or beta not
  /// finite or beta < 0.
  void SetSpringLaw(SpringLaw law, const PowerSpringLaw& power = PowerSpringLaw{});
  /// eMSM dispersion fraction q; precondition: q > -1/2 (Q > -1).
  void SetDispersionFraction(double q) { dispersion_fraction_ = q; }
  /// The self-calibration the model was corrected by (Model::self_calibration); default none.
  void SetSelfCalibration(const std::optional<SelfCalibration>& calibration) {
    self_calibration_ = calibration;
  }

  int num_nodes() const { return static_cast<int>(masses_.size()); }
  int num_springs() const { return static_cast<int>(stiffness_.size()); }

  /// Compiles the model. Throws std::invalid_argument if there are no nodes or if volume or
  /// characteristic length are not positive.
  Model Build(double volume, double characteristic_length) const;

 private:
  Material material_;
  SpringLaw spring_law_ = SpringLaw::kLinear;
  PowerSpringLaw power_spring_law_;
  double dispersion_fraction_ = 0.0;
  std::optional<SelfCalibration> self_calibration_;
  double added_mass_ = 0.0;
  bool mass_scaling_limited_ = false;
  std::vector<Eigen::Vector3d> positions_;
  std::vector<double> masses_;
  std::vector<double> surface_insets_;
  std::vector<NodeIndex> node_a_;
  std::vector<NodeIndex> node_b_;
  std::vector<double> rest_length_;
  std::vector<double> stiffness_;
  std::vector<double> weight_a_;
  std::vector<double> weight_b_;
  std::vector<std::array<SpringIndex, 12>> correction_edges_;
  std::vector<double> correction_coefficients_;
};

}  // namespace msm_sim::core
