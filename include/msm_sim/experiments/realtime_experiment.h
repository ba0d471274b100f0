#pragma once

#include <memory>
#include <string>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/mechanics/spring_precision.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// How fast the dynamics runs a robot's contact (issue "Real time at real resolution";
/// `msm_lab realtime`): the body rests on a ground plane (touching the lowest collision sphere)
/// under gravity, a rigid sphere starts just touching the collision spheres under it above the
/// centre of the model's bounding box and presses down at constant speed; the World steps as
/// fast as it can for `seconds` of simulated time, with the World's explicit integrator (position
/// Verlet in stable substeps) or its implicit one (one substep per step; docs/physics.md §7.1).
struct RealtimeExperimentOptions {
  double sphere_radius = 0.01;  ///< m, finite, > 0 (the demo robot's fingertip)
  double speed = 0.01;          ///< m/s, finite, > 0, the sphere's, downwards
  double seconds = 0.5;         ///< simulated s, finite, > 0
  double step = 1e-3;           ///< s, finite, > 0: World::Step(step), subdivided inside
  double damping_beta = 1e-4;   ///< s, finite, >= 0: spring dampers c = beta k
  double gravity = 9.81;        ///< m/s^2, finite, >= 0, along -z
  double friction = 0.5;  ///< Coulomb coefficient of the body, the ground and the sphere, >= 0
  /// kImplicit: one implicit substep per step (WorldOptions::implicit_max_substep = step).
  Integrator integrator = Integrator::kExplicit;
  int threads = 1;                                              ///< >= 1: WorldOptions::threads
  SpringPrecision spring_precision = SpringPrecision::kSingle;  ///< WorldOptions::spring_precision
  double time_step_safety = 0.8;  ///< in (0, 1]: WorldOptions::time_step_safety
};

struct RealtimeExperimentResult {
  int nodes = 0;
  int springs = 0;
  std::string integrator = "explicit";  ///< "explicit" (position Verlet) or "implicit"
  double step = 0.0;                    ///< s, the caller's step
  int steps = 0;
  int substeps = 0;      ///< substeps per step (the most any step took)
  double substep = 0.0;  ///< s
  double seconds_simulated = 0.0;
  double wall_seconds = 0.0;  ///< steady_clock time of the stepping alone
  double wall_per_simulated_second = 0.0;
  double real_time_factor = 0.0;  ///< simulated over wall time: 1 / wall_per_simulated_second
  double peak_force = 0.0;        ///< N, the largest |force| the body exerted on the sphere
  double final_force = 0.0;       ///< N, |force| on the sphere during the last step
  /// The World's substep_refinement at the end: > 1 if a step diverged and was taken again with
  /// finer substeps (WorldOptions::max_substep_refinement).
  int substep_refinement = 1;
  /// Implicit: conjugate-gradient iterations (stiffness products) per step, the mean; 0 explicit.
  double solver_iterations_per_step = 0.0;
};

/// Runs the experiment. Throws std::invalid_argument for bad options or a model with no node
/// under the sphere, and std::runtime_error if a step is rejected.
RealtimeExperimentResult RunRealtimeExperiment(std::shared_ptr<const Model> model,
                                               const RealtimeExperimentOptions& options);

}  // namespace msm_sim::core
