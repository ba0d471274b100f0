#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The deflection experiment of docs/physics.md §6 / thesis 3.2.6 on a bar [0, L] x [0, W] x [0,
/// H].
struct CantileverExperimentOptions {
  Eigen::Vector3d body_size = Eigen::Vector3d(4.0, 1.0, 1.0);  ///< m
  double total_force = 1.0;  ///< N, applied in -z, shared equally by the end nodes
  /// Nodes within this distance (m) of the lowest rest x are frozen, and those within it of the
  /// highest rest x carry the load. <= 0: half the characteristic length (one lattice layer).
  double end_layer_depth = 0.0;
  /// Solver settings; a force_tolerance <= 0 means 1e-7 of the force per loaded node.
  StaticSolverOptions solver{0.0};
};

struct DeflectionSample {
  double x = 0.0;           ///< m, from the centre of the frozen layer
  double deflection = 0.0;  ///< m, mean -u_z of the nodes in this layer (positive down)
  double theory = 0.0;      ///< m, Euler-Bernoulli F x^2 (3 L - x) / (6 E I)
};

struct CantileverExperimentResult {
  double tip_deflection = 0.0;         ///< m, mean over the loaded nodes, positive down
  double theory_tip_deflection = 0.0;  ///< m, F L^3 / (3 E I)
  /// m: from the frozen layer to the loaded layer (the lattice puts both half a cell inside the
  /// bar, thesis 3.2.6), the length Euler-Bernoulli is evaluated with.
  double beam_length = 0.0;
  std::vector<DeflectionSample> profile;  ///< one sample per layer of width ã along x
  int clamped_nodes = 0;
  int loaded_nodes = 0;
  StaticSolverReport solver;
};

/// Runs the experiment with I = W H^3 / 12 and the model's calibration E. Throws
/// std::invalid_argument for a non-finite or zero force or a bar with fewer than three layers.
CantileverExperimentResult RunCantileverExperiment(const Model& model,
                                                   const CantileverExperimentOptions& options);

}  // namespace msm_sim::core
