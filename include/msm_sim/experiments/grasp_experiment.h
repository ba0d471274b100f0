#pragma once

#include <memory>

#include "msm_sim/dynamics/integrator.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A parallel-gripper grasp and lift (`msm_lab grasp`): the body rests on the ground; two rigid
/// box pads facing each other across its narrower horizontal extent (along x, or along y if
/// the body is narrower in y), centred on the body's centroid in the other two axes, close on it
/// under force control until each presses F_n = Q m g / (2 mu) (docs/physics.md §7: Coulomb
/// friction on both pads then carries Q times the weight), hold for `hold_time`, lift by `lift`
/// along +z with a smooth (quintic) profile over `lift_time` while keeping the squeeze, and hold
/// up there for `final_hold`. Friction mu acts between the body and both pads, and the ground,
/// from the start: the grasp a robot performs, not a friction switched on after the squeeze.
struct GraspExperimentOptions {
  double friction = 0.8;        ///< mu, pads and ground, finite, > 0
  double force_ratio = 1.5;     ///< Q = 2 mu F_n / (m g), finite, > 0
  double pad_size = 0.02;       ///< m, edge of the pads' square faces, finite, > 0
  double pad_thickness = 0.01;  ///< m, along the closing axis, finite, > 0
  double close_speed = 0.02;    ///< m/s, the pads' fastest closing (force control), finite, > 0
  double close_timeout = 3.0;   ///< s: the hold starts when the squeeze is reached or after this
  double hold_time = 0.5;       ///< s, finite, >= 0
  double lift = 0.05;           ///< m, finite, >= 0
  double lift_time = 1.0;       ///< s, finite, > 0
  double final_hold = 1.0;      ///< s, finite, >= 0
  double gravity = 9.81;        ///< m/s^2, finite, > 0, along -z
  double damping_beta = 1e-3;   ///< s, finite, >= 0: the body's spring dampers c = beta k
  /// BodyOptions::orientation_threshold, 0 (off) or in (0, 1); ignored by a model without cells
  /// (random lattices). On by default: a hard squeeze folds the cells of a cubic lattice under
  /// the pads' edges, which then snap through (docs/physics.md §4, "Orientation barrier").
  double orientation_threshold = 0.2;
  double step = 1e-3;  ///< s, finite, > 0: World::Step(step), subdivided inside
  /// The body counts as held when it rose at least held_rise times the lift and slipped at most
  /// held_slip (m) relative to the pads.
  double held_rise = 0.98;
  double held_slip = 1e-3;
  /// kImplicit: one implicit substep per step (WorldOptions::implicit_max_substep = step).
  Integrator integrator = Integrator::kExplicit;
  /// WorldOptions::implicit_energy_tolerance, in [0, 1) (0: the implicit solve's early stop off).
  double implicit_energy_tolerance = 1e-3;
};

struct GraspExperimentResult {
  int nodes = 0;
  double mass = 0.0;           ///< kg
  double target_force = 0.0;   ///< N per pad, Q m g / (2 mu)
  double squeeze_force = 0.0;  ///< N per pad: the pads' mean normal force over the first hold
  double rise = 0.0;           ///< m, the centroid's rise at the end (from the start of the lift)
  double slip = 0.0;           ///< m, the largest lag of the centroid behind the pads' rise
  bool held = false;
  double max_node_speed = 0.0;     ///< m/s, over every step
  double energy_max = 0.0;         ///< J, the largest kinetic plus elastic energy at a step's end
  double real_time_factor = 0.0;   ///< simulated seconds per wall-clock second of stepping
  double simulated_time = 0.0;     ///< s
  double solver_iterations = 0.0;  ///< implicit: conjugate-gradient iterations per step
};

/// Runs the experiment on `model` (any frame: it is placed on the ground as built). Throws
/// std::invalid_argument for bad options or a model without border nodes, std::runtime_error if
/// a step is rejected.
GraspExperimentResult RunGraspExperiment(std::shared_ptr<const Model> model,
                                         const GraspExperimentOptions& options);

}  // namespace msm_sim::core
