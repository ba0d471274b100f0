#pragma once

#include <memory>

#include <Eigen/Core>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Thesis 6.4: a body slides on a plane with Coulomb friction from an initial speed and stops
/// after v0^2 / (2 mu g), whatever its resolution, contact area or shape (docs/physics.md §7).
struct SlideExperimentOptions {
  double initial_speed = 1.0;  ///< v0 (m/s) along +x, > 0
  double friction = 0.5;       ///< mu between the body and the ground, > 0
  double gravity = 9.81;       ///< m/s^2, > 0, along -z
  double step = 1e-3;          ///< s, the caller's step (subdivided into stable substeps)
  /// kImplicit: one implicit substep per step, however long (WorldOptions::integrator).
  Integrator integrator = Integrator::kExplicit;
  /// The body has stopped when its centre of mass moves forwards slower than this fraction of
  /// v0, or backwards: a coarse body that rocks on its supports after stopping (the 12-node box
  /// of the sliding tests) crosses zero speed between two samples.
  double stop_fraction = 1e-3;
  /// Give up after this long (s); <= 0: three times the theoretical stopping time, plus 1 s.
  double max_time = 0.0;
};

struct SlideExperimentResult {
  double distance = 0.0;         ///< m, travel of the centre of mass along x
  double theory_distance = 0.0;  ///< m, v0^2 / (2 mu g)
  double seconds_simulated = 0.0;
  bool stopped = false;
  int steps = 0;
};

/// Runs the experiment: the body at its rest positions, every node moving at v0 along x, on a
/// ground plane placed so that the lowest node's collision sphere just touches it. Throws
/// std::invalid_argument for bad options and std::runtime_error if a step is rejected.
SlideExperimentResult RunSlideExperiment(std::shared_ptr<const Model> model,
                                         const SlideExperimentOptions& options);

}  // namespace msm_sim::core
