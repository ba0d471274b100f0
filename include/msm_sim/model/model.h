#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/material/material.h"
#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/self_calibration.h"

namespace msm_sim::core {

using NodeIndex = std::int32_t;
using SpringIndex = std::int32_t;

/// The immutable, compiled description of a mass-spring model (the analogue of MuJoCo's mjModel).
///
/// Built once by a builder through ModelBuilder, then shared read-only by solvers, integrators and
/// measurements; everything that changes in time lives in State. Springs are stored as a structure
/// of arrays so that force loops stream through contiguous memory.
///
/// Invariants (established by ModelBuilder::Build):
/// - every spring joins two distinct, valid nodes and has rest length > 0 and stiffness > 0;
/// - every mass is > 0;
/// - incident_springs(i) lists every spring touching node i exactly once.
class Model {
 public:
  int num_nodes() const { return static_cast<int>(masses_.size()); }
  int num_springs() const { return static_cast<int>(spring_stiffness_.size()); }

  /// Node rest positions, one column per node (m).
  const Eigen::Matrix3Xd& rest_positions() const { return rest_positions_; }
  /// Node masses (kg).
  const Eigen::VectorXd& masses() const { return masses_; }
  /// Per node (m, >= 0): how far the body's surface lies inside the outer face of the node's
  /// lattice cell, a / 2 less the cell centre's depth below the surface (its distance to the
  /// nearest surface point, negative outside) for a node-centred cell the surface cuts, at least
  /// 0 (docs/physics.md §7); 0 for a whole cell and for lattices whose nodes are not cell
  /// centres. Model files before the mesh builder measured the depth hold the flat-cut estimate
  /// (1 - chi) a (the same on a cut parallel to a face). Collision spheres shrink by it
  /// (FindBorderNodes, docs/physics.md §7).
  const Eigen::VectorXd& surface_insets() const { return surface_insets_; }

  /// Spring end points: spring s joins spring_node_a()[s] and spring_node_b()[s].
  const std::vector<NodeIndex>& spring_node_a() const { return spring_node_a_; }
  const std::vector<NodeIndex>& spring_node_b() const { return spring_node_b_; }
  /// Rest lengths (m).
  const std::vector<double>& spring_rest_length() const { return spring_rest_length_; }
  /// Linear stiffnesses (N/m).
  const std::vector<double>& spring_stiffness() const { return spring_stiffness_; }
  /// eMSM dispersion weight v of each spring at its end node a (resp. b), docs/physics.md §3
  /// generalised: node x accumulates J_x = q sum_n v_n L0_n t_n and spring n receives w_n J_x / W_x
  /// of it, with w_n = v_n k_n L0_n^2 and W_x = sum of w over x's springs. That choice makes the
  /// dispersion the gradient of Phi = sum_x J_x^2 / (2 q W_x), so the stiffness stays symmetric
  /// (the paper's equal shares are not when k L0^2 differs between springs, as between the A and
  /// B springs of a cubic lattice, and the undamped dynamics then flutters). All v = 1 with equal
  /// k L0^2 is the paper's algorithm. Builders change v where a node's star would otherwise
  /// disperse anisotropically (surface nodes of a cubic lattice, random stars).
  const std::vector<double>& dispersion_weight_a() const { return dispersion_weight_a_; }
  const std::vector<double>& dispersion_weight_b() const { return dispersion_weight_b_; }

  /// Compressed adjacency: springs incident to node i are
  /// incident_springs()[incidence_offsets()[i] .. incidence_offsets()[i + 1]).
  const std::vector<std::int32_t>& incidence_offsets() const { return incidence_offsets_; }
  const std::vector<SpringIndex>& incident_springs() const { return incident_springs_; }
  int num_incident_springs(NodeIndex node) const {
    return incidence_offsets_[node + 1] - incidence_offsets_[node];
  }

  /// Tension law shared by every spring.
  SpringLaw spring_law() const { return spring_law_; }
  /// The law's (alpha, beta) in the family of docs/physics.md §4.1, shared by every spring: the
  /// fitted ones for SpringLaw::kPower, (1, 0) for kLinear and (-1, 0) for kNonlinear.
  const PowerSpringLaw& power_spring_law() const { return power_spring_law_; }
  /// eMSM dispersion fraction q (docs/physics.md §3); 0 for a plain MSM (nu = 1/4).
  double dispersion_fraction() const { return dispersion_fraction_; }

  /// Baudet et al.'s orthogonal correction (docs/baudet_derivation.md). Each correction element
  /// lists the springs of its 4 x-, 4 y- and 4 z-edges (in that order) and a coefficient c: with
  /// S_i the summed elongation of its edges along axis i it stores the energy
  /// c (S_x S_y + S_y S_z + S_z S_x), i.e. every edge along axis j carries the extra tension
  /// c sum_{i != j} S_i. Empty for the other models.
  const std::vector<std::array<SpringIndex, 12>>& correction_edges() const {
    return correction_edges_;
  }
  const std::vector<double>& correction_coefficients() const { return correction_coefficients_; }

  /// The material the springs were calibrated for.
  const Material& material() const { return material_; }
  /// Volume of the body the model represents (m^3); used by calibration and measurements.
  double volume() const { return volume_; }
  /// Characteristic node spacing ã (m): the lattice spacing of a cubic lattice or l = (V/N)^(1/3)
  /// of a random one. Measurements scale their probes with it (docs/physics.md §6).
  double characteristic_length() const { return characteristic_length_; }
  /// The self-calibration the stiffnesses and q were corrected by (random lattices built with
  /// one, docs/physics.md §2.2), with what it was measured for; empty for every other model.
  const std::optional<SelfCalibration>& self_calibration() const { return self_calibration_; }
  /// Mass (kg, >= 0) that selective mass scaling added to the nodes of cut lattice cells so that
  /// they do not set the explicit stable step (docs/physics.md §7 "Selective mass scaling");
  /// already part of masses(). 0 for models without cut cells or built without it.
  double added_mass() const { return added_mass_; }
  /// True when the bound on the added mass stopped the scaling short of the full-cell figure.
  bool mass_scaling_limited() const { return mass_scaling_limited_; }

 private:
  friend class ModelBuilder;
  explicit Model(const Material& material) : material_(material) {}

  Eigen::Matrix3Xd rest_positions_;
  Eigen::VectorXd masses_;
  Eigen::VectorXd surface_insets_;
  std::vector<NodeIndex> spring_node_a_;
  std::vector<NodeIndex> spring_node_b_;
  std::vector<double> spring_rest_length_;
  std::vector<double> spring_stiffness_;
  std::vector<double> dispersion_weight_a_;
  std::vector<double> dispersion_weight_b_;
  std::vector<std::array<SpringIndex, 12>> correction_edges_;
  std::vector<double> correction_coefficients_;
  std::vector<std::int32_t> incidence_offsets_;
  std::vector<SpringIndex> incident_springs_;
  Material material_;
  SpringLaw spring_law_ = SpringLaw::kLinear;
  PowerSpringLaw power_spring_law_;
  double dispersion_fraction_ = 0.0;
  double volume_ = 0.0;
  double characteristic_length_ = 0.0;
  std::optional<SelfCalibration> self_calibration_;
  double added_mass_ = 0.0;
  bool mass_scaling_limited_ = false;
};

}  // namespace msm_sim::core
