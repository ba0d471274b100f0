#pragma once

#include <Eigen/Core>

#include "msm_sim/dynamics/integrator.h"
#include "msm_sim/mechanics/spring_precision.h"

namespace msm_sim::core {

/// How a body moves, besides its Model (which fixes masses and springs).
struct BodyOptions {
  double damping_beta = 0.0;  ///< s: spring dampers c = beta k (docs/physics.md §7)
  double friction = 0.5;      ///< Coulomb coefficient of the body's surface
  double restitution = 1.0;   ///< e in [0, 1] for contacts between MSM nodes
  /// Border nodes collide with border nodes of the same body that were at least 2.5 longest
  /// springs apart at rest (a fold), never with the ones near them. Off by default: objects a
  /// robot handles rarely fold onto themselves, and a very soft ball squashed flat gained energy
  /// through its self-contacts (docs/dynamics.md, known limits).
  bool self_collision = false;
  /// Orientation barrier (docs/physics.md §4, OrientationBarrier): a cell corner of a cubic
  /// lattice squeezed below this fraction of its rest volume, or turned inside out, is pushed
  /// back with modulus `orientation_modulus`. Without it a lattice squeezed hard enough to fold
  /// stays folded after the release. 0 (the default) turns it off; otherwise in (0, 1). Off by
  /// default because it costs 8 corner evaluations per node and step, and contact-sized
  /// deformations never reach it.
  double orientation_threshold = 0.0;
  /// Pa, >= 0; 0 (the default) takes the material's Young's modulus E.
  double orientation_modulus = 0.0;
};

/// How a World steps all of its bodies: gravity, substeps, the integrator and its solver,
/// contacts and penetration recovery.
struct WorldOptions {
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);  ///< m/s^2
  /// Fraction of each body's stability limit used as the substep (see StableTimeStep).
  double time_step_safety = 0.8;
  /// A step that would move any node faster than this (m/s) is rejected: no soft object a robot
  /// handles gets there, but a diverging simulation or an absurd force does.
  double max_speed = 100.0;
  /// Per body, the pushes (ApplyForce, ApplyWrench) pending at most (>= 1), and the sum of the
  /// magnitudes of the node forces they hold at most (N, > 0): a new push beyond either drops
  /// the oldest pending ones first, so that a stream of long pushes keeps the step's cost and
  /// the memory bounded. A lone push above max_pending_force still acts.
  int max_pending_pushes = 100;
  double max_pending_force = 1e4;
  /// Explicit only: a step that diverges (fails the max_speed check) while no push is in flight
  /// is taken again from its start with twice the substeps, up to this factor (a power of 2,
  /// >= 1; 1 turns it off), and the World keeps the finer substep from then on. The stable step
  /// holds for small motions about the rest shape; a lattice that buckles and snaps (the 4 mm
  /// realtime block at nu = 0.49, surface_dispersion 0.25, pressed 9 mm by a 1 cm sphere:
  /// docs/physics.md §7, "Deep presses") moves faster than it resolves. A step that diverges at
  /// the largest factor too is rejected as before.
  int max_substep_refinement = 8;
  /// Gauss-Seidel sweeps over a node's contacts with colliders, so that touching several
  /// surfaces at once (a wedge, a gripper) ends with no approach towards any of them.
  int contact_iterations = 8;
  Integrator integrator = Integrator::kExplicit;
  /// Implicit only: the longest substep (s, finite, > 0); Step(dt) takes equal substeps of at
  /// most this, whatever the bodies' stable steps.
  double implicit_max_substep = 1e-3;
  /// Implicit only: the conjugate-gradient solve stops when the residual impulse on the free
  /// nodes is this fraction, in (0, 1), of the larger of h |F| and the gravity impulse h M |g|
  /// (a body at rest has F ~ 0; relative to it alone every solve would chase round-off) ...
  double implicit_tolerance = 1e-4;
  /// ... or, earlier, once the residual is at most this fraction of the same reference (in
  /// [implicit_tolerance, 1)) and its impulse r can change the kinetic energy after the kick
  /// by at most 2 implicit_energy_tolerance of it: |r|_(M^-1) <= implicit_energy_tolerance
  /// |v + dv|_M (docs/physics.md §7.1, "Stopping the solve") ...
  double implicit_early_tolerance = 3e-3;
  double implicit_energy_tolerance = 1e-3;  ///< in [0, 1); 0 turns the early stop off
  /// ... or after this many iterations (>= 1), whichever comes first.
  int implicit_max_iterations = 200;
  /// Keep every microcollision with a collider of the last Step (World::contact_points).
  bool record_contact_points = false;
  /// Penetration recovery (docs/physics.md §7.2): a node whose collision sphere overlaps a
  /// collider or another node's sphere by a depth d (beyond a slop of 0.01 of the radii)
  /// is moved out at a pseudo-velocity
  /// min(penetration_max_speed, d / penetration_recovery_time) along the contact normal, a
  /// position-only correction of the second half-drift that never becomes kinetic energy. Any
  /// overlap thus decays with this time constant (s, > 0) ...
  double penetration_recovery_time = 0.05;
  /// ... at no more than this separation speed (m/s, >= 0; 0 turns the recovery off).
  double penetration_max_speed = 0.1;
  /// The threads (>= 1) each body's spring loops and explicit per-node stages use: the
  /// single-precision loops of bodies of 1,000 nodes or more in exactly this many node shares,
  /// the double loops of bodies of 50,000 springs or more on up to this many (ForceEvaluator).
  /// One by default: two threads gain only on an idle machine, and lose to one while another
  /// process keeps a core busy (docs/design/threads-default.md). Results are deterministic for a
  /// given thread count (and contacts, see cut_shares_at_contacts).
  int threads = 1;
  /// With threads > 1, a Step of a single explicit body (no kinematic groups, no self-collision)
  /// in 4 substeps or more cuts the body's node shares at equal work, counting what the contact
  /// stage costs for the border nodes near a collider at the Step's start (docs/physics.md §9):
  /// a block resting on the ground keeps its contacts in its first share. The cut moves where the
  /// shares' float sums meet, so results on several threads then depend, deterministically, on
  /// those contacts too. false: equal shares always.
  bool cut_shares_at_contacts = true;
  /// The arithmetic of each body's spring loops in the dynamics (ForceEvaluator::set_precision).
  /// kSingle (the default) runs cubic lattices' springs in single precision, for speed
  /// (docs/design/single-precision-springs.md); a spring's strain is then resolved to about
  /// 1e-7 times the body's extent over the spring's length. Energies, stable steps, the
  /// linearisation and static solves stay double; the implicit integrator's stiffness products
  /// run in float too (docs/physics.md §9).
  SpringPrecision spring_precision = SpringPrecision::kSingle;
};

}  // namespace msm_sim::core
