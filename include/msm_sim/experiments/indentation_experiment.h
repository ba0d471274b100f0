#pragma once

#include <memory>
#include <vector>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/mechanics/spring_precision.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// A rigid sphere pressed at constant speed into the middle of the top of a body clamped at its
/// base, its force against Hertz's (issue "Real time at real resolution"; `msm_lab indent`).
/// The body is the model at rest, without gravity (so that it does not sag before contact); a
/// kinematic group fixes the nodes within half a characteristic length of its lowest node. The
/// sphere starts `start_gap` above the collision spheres of the nodes under it, above the centre
/// of the model's bounding box, and moves down at `speed` until it is `depth` into the surface.
/// Depth is measured from the body's surface under the sphere, as a measured curve's is: the
/// plane through the highest top of the collision spheres within one characteristic length of
/// the sphere's axis (the body at rest, computed from the geometry). It is not measured from the
/// first collision sphere touched, which lies slightly lower where the axis falls between nodes,
/// nor from the step that first records a force, which ends up to one step's travel later.
struct IndentationExperimentOptions {
  double sphere_radius = 0.01;  ///< R (m), finite, > 0 (the demo robot's fingertip)
  double depth = 0.005;         ///< D (m), finite, > 0 and less than the body's height
  double speed = 0.005;         ///< V (m/s), finite, > 0, downwards
  double step = 1e-3;           ///< s, finite, > 0, the caller's step (substeps: see integrator)
  double damping_beta = 1e-4;   ///< s, finite, >= 0: spring dampers c = beta k
  /// Coulomb coefficient between the sphere and the body, finite, >= 0 (World::SetPairFriction).
  /// Hertz's contact is frictionless; 0.5 is the package's default surface (BodyOptions).
  double friction = 0.5;
  /// Rows of the profile over the depth, >= 1: each row covers about D / samples of depth.
  int samples = 50;
  double start_gap = 1e-4;  ///< m, finite, >= 0: sphere to the nearest collision sphere at start
  /// kImplicit: one implicit substep per step (WorldOptions::implicit_max_substep = step).
  Integrator integrator = Integrator::kExplicit;
  /// In (0, 1]: WorldOptions::time_step_safety, the explicit substep's fraction of the stable
  /// step (a shorter one checks that a force has converged in the substep).
  double time_step_safety = 0.8;
  SpringPrecision spring_precision = SpringPrecision::kSingle;  ///< WorldOptions::spring_precision
  /// Penetration recovery (docs/physics.md §7.2), m, finite, >= 0. > 0: instead of pressing, the
  /// sphere starts this far past first contact (its lowest point start_depth below the height at
  /// which it would touch the first collision sphere under it, as if teleported into the
  /// block), and is held still for `hold` seconds; the profile stays empty and the result's
  /// overlap, force and energy fields are filled.
  double start_depth = 0.0;
  double hold = 0.2;  ///< s, finite, > 0: how long the sphere is held at start_depth
};

/// One row of the profile: a run of consecutive steps covering about D / samples of depth.
struct IndentationSample {
  double depth = 0.0;  ///< m below the surface (above), the mean over the row's steps
  /// N, the mean over the row's steps of the vertical force the body exerts on the sphere
  /// (upwards positive; each step's force is its contact impulses over the step).
  double force = 0.0;
  double hertz_force = 0.0;  ///< N, HertzForce at `depth` with the model's target E and nu
};

struct IndentationExperimentResult {
  std::vector<IndentationSample> profile;  ///< by increasing depth
  double contact_time = 0.0;  ///< s, simulated time at the end of the first step with force
  /// m, the depth below the surface at which the sphere touches the first collision sphere: 0
  /// where a node lies under its axis, about s^2 / (2 (R + r)) where the axis falls between
  /// nodes at horizontal distance s (pressing only).
  double touch_depth = 0.0;
  double seconds_simulated = 0.0;  ///< s, up to depth D
  int steps = 0;
  /// start_depth > 0 only. Overlap (m): the deepest penetration of a border node's collision
  /// sphere into the indenter, max over the nodes of R + r_node - |x_node - c| (<= 0: none);
  /// before the first step and after the hold.
  double overlap_before = 0.0;
  double overlap_after = 0.0;
  /// N, upwards: the mean vertical force on the sphere over the last tenth of the hold.
  double force_after = 0.0;
  double peak_kinetic = 0.0;   ///< J, the body's largest kinetic energy after any step
  double final_kinetic = 0.0;  ///< J, after the hold
  double final_elastic = 0.0;  ///< J, after the hold
};

/// Hertz's force (N) of a rigid sphere of radius R (m) pressed to depth delta (m) into an elastic
/// half-space: F = 4/3 E / (1 - nu^2) sqrt(R) delta^(3/2); 0 for delta <= 0.
double HertzForce(double youngs, double poisson, double radius, double depth);

/// The overlap of overlap_before / overlap_after for the body's border nodes at `positions`.
double SphereOverlap(const BorderNodes& border, const Eigen::Matrix3Xd& positions,
                     const Eigen::Vector3d& centre, double radius);

/// The profile's force (N) at this depth (m), interpolated linearly between its rows and
/// extrapolated from the last two beyond them; 0 for an empty profile.
double ProfileForceAt(const std::vector<IndentationSample>& profile, double depth);

/// Runs the experiment. Throws std::invalid_argument for bad options (or a depth not less than
/// the body's height) and std::runtime_error if a step is rejected or the sphere has not touched
/// the body after travelling the start gap plus two characteristic lengths.
IndentationExperimentResult RunIndentationExperiment(std::shared_ptr<const Model> model,
                                                     const IndentationExperimentOptions& options);

}  // namespace msm_sim::core
