#pragma once

#include <memory>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A parallel-jaw grip (issue "real time"; `msm_lab grip`): the body rests on a frictionless
/// ground between two rigid box jaws facing each other along x, which just touch its outermost
/// collision spheres. The jaws close, frictionless, by `squeeze` each over `close_time` and hold
/// still for `settle_time`; the jaws' mean normal force F_n over the last `measure_time` of the
/// settling fixes the jaw-body friction mu = hold_ratio m g / (2 F_n) (docs/physics.md §7:
/// Coulomb friction holds the weight while 2 mu F_n >= m g). Then the ground is removed and the
/// jaws rise along +z, their speed ramped from 0 to `lift_speed` over `lift_ramp`, for
/// `lift_time`. The slip is how far the body's centre of mass lags behind the jaws.
struct GripExperimentOptions {
  double squeeze = 2e-4;       ///< m, finite, > 0: each jaw's travel into the body
  double hold_ratio = 1.3;     ///< 2 mu F_n / (m g) the friction is chosen for, finite, > 0
  double gravity = 9.81;       ///< m/s^2, finite, > 0, along -z
  double damping_beta = 1e-3;  ///< s, finite, >= 0: the body's spring dampers c = beta k
  double close_time = 0.05;    ///< s, finite, > 0
  double settle_time = 0.15;   ///< s, finite, > 0 (includes the measurement window)
  double measure_time = 0.05;  ///< s, finite, in (0, settle_time]
  double lift_speed = 0.05;    ///< m/s, finite, >= 0
  double lift_ramp = 0.1;      ///< s, finite, > 0
  double lift_time = 2.0;      ///< s, finite, > 0
  double step = 1e-3;          ///< s, finite, > 0: World::Step(step), subdivided inside
  /// The body counts as held if its slip never exceeds this (m, finite, > 0).
  double held_slip = 1e-3;
  /// kImplicit: one implicit substep per step (WorldOptions::implicit_max_substep = step).
  Integrator integrator = Integrator::kExplicit;
};

struct GripExperimentResult {
  double mass = 0.0;          ///< kg
  double weight = 0.0;        ///< N, m g
  double normal_force = 0.0;  ///< N, F_n: each jaw's normal force before the lift, the mean
  double friction = 0.0;      ///< mu = hold_ratio m g / (2 F_n)
  double lift_normal_force_mean = 0.0;  ///< N, each jaw's normal force during the lift, the mean
  double lift_normal_force_min = 0.0;   ///< N, and the least over the lift's steps
  double slip = 0.0;            ///< m, at the end of the lift (or when the body left the jaws)
  double max_slip = 0.0;        ///< m, the largest during the lift
  double seconds_lifted = 0.0;  ///< s; shorter than lift_time if the body left the jaws
  bool left_jaws = false;       ///< the body slipped further than the jaws are high
  bool held = false;            ///< max_slip <= held_slip
  int steps = 0;                ///< of the whole run
};

/// Runs the experiment. Throws std::invalid_argument for bad options or a model without border
/// nodes, std::runtime_error if a step is rejected or the jaws measure no normal force.
GripExperimentResult RunGripExperiment(std::shared_ptr<const Model> model,
                                       const GripExperimentOptions& options);

}  // namespace msm_sim::core
