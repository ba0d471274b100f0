#pragma once
// Private to msm_sim's World: what it holds (the analogue of MuJoCo's mjModel and mjData for the
// whole scene), which its stages read and advance.

#include <algorithm>
#include <limits>
#include <vector>

#include "dynamics/world_body.h"
#include "msm_sim/dynamics/collider.h"
#include "msm_sim/dynamics/world_options.h"

namespace msm_sim::core::internal {

/// The World's bodies, colliders, time and the counters of the Step under way.
struct WorldState {
  explicit WorldState(const WorldOptions& world_options) : options(world_options) {}
  /// The stable substep of the stiffest body (s), computed at rest; infinite without bodies.
  double StableTimeStep() const {
    double step = std::numeric_limits<double>::infinity();
    for (const Body& body : bodies) step = std::min(step, body.stable_step);
    return step;
  }

  WorldOptions options;
  std::vector<Body> bodies;
  std::vector<Collider> colliders;
  double time = 0.0;
  int microcollisions = 0;
  int solver_iterations = 0;           // during the current Step (implicit)
  bool stopped_after_failure = false;  // the last Step failed and stopped the bodies
  int substep_refinement = 1;          // explicit: stable substep divided by this (Step)
  int substep_index = 0;               // of the current substep within its Step
  int substep_count = 0;               // substeps of the current Step
  // SubstepInOnePass: the last drift of the substep just taken also took the next substep's
  // first drift (DriftShare twice) and applied its restitution; that substep's first stage then
  // has nothing left to do. rounded_ahead: and the nodes were rounded for its float loops.
  bool drifted_ahead = false;
  bool rounded_ahead = false;
  double substep = 0.0;  // s, the current substep
};

}  // namespace msm_sim::core::internal
