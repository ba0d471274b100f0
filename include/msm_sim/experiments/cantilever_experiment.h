#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Where the bar is held and loaded (docs/physics.md §6, "Cantilever").
enum class CantileverEnds {
  /// Thesis 3.2.6: the first layer of nodes is frozen and the last carries the force, both half a
  /// cell inside the ends of a node-centred lattice; the beam is the distance between them.
  kNodeLayers,
  /// As a finite-element model: the face x = 0 is clamped and the face x = L loaded. The model must
  /// have been built with an anchored plane at x = 0 (AnchoredPlane, normal -x; the lab's node-
  /// centred cubic lattices are): its anchors are frozen and nothing else. The force goes onto
  /// the last node layer together with the couple (L - x_layer) F carried by axial forces
  /// proportional to z - z_mean, which makes it statically equal to F on the face x = L.
  kFaces,
};

/// The deflection experiment of docs/physics.md §6 / thesis 3.2.6 on a bar [0, L] x [0, W] x [0,
/// H].
struct CantileverExperimentOptions {
  Eigen::Vector3d body_size = Eigen::Vector3d(4.0, 1.0, 1.0);  ///< m
  double total_force = 1.0;  ///< N, applied in -z, shared equally by the end nodes
  /// Nodes within this distance (m) of the lowest rest x are frozen, and those within it of the
  /// highest rest x carry the load. <= 0: half the characteristic length (one lattice layer).
  double end_layer_depth = 0.0;
  CantileverEnds ends = CantileverEnds::kNodeLayers;
  /// Solver settings; a force_tolerance <= 0 means 1e-7 of the force per loaded node. Up to 200
  /// Newton iterations: at nu = 0.49 the bar (0.2 x 0.05 x 0.05 m, 4 or 8 cells across)
  /// needs more than the solver's default 30 and stopped unconverged there.
  StaticSolverOptions solver{0.0, 200};
};

struct DeflectionSample {
  double x = 0.0;           ///< m, from the frozen layer (kNodeLayers) or the clamped face (kFaces)
  double deflection = 0.0;  ///< m, mean -u_z of the nodes in this layer (positive down)
  double theory = 0.0;      ///< m, Euler-Bernoulli F x^2 (3 L - x) / (6 E I)
};

struct CantileverExperimentResult {
  double tip_deflection = 0.0;  ///< m, mean over the loaded nodes, positive down
  /// m, positive down: the mean deflection of the end face x = L, extrapolated linearly from the
  /// mean deflections of the last two node layers (the bending moment, hence the curvature,
  /// vanishes at a loaded free end, so the error is of third order in the half cell).
  double end_face_deflection = 0.0;
  double theory_tip_deflection = 0.0;  ///< m, F L^3 / (3 E I)
  /// m, the length Euler-Bernoulli is evaluated with: kNodeLayers, from the frozen layer to the
  /// loaded layer (the lattice puts both half a cell inside the bar, thesis 3.2.6); kFaces, the
  /// body's length L = body_size.x().
  double beam_length = 0.0;
  /// One sample per layer of width ã along x; kFaces starts with the clamped face (x = 0, 0).
  std::vector<DeflectionSample> profile;
  int clamped_nodes = 0;
  int loaded_nodes = 0;
  StaticSolverReport solver;
};

/// Runs the experiment with I = W H^3 / 12 and the model's calibration E. Throws
/// std::invalid_argument for a non-finite or zero force, a bar with fewer than three layers, or
/// kFaces on a model without anchors on the face x = 0.
CantileverExperimentResult RunCantileverExperiment(const Model& model,
                                                   const CantileverExperimentOptions& options);

}  // namespace msm_sim::core
