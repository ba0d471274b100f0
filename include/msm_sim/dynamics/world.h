#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/collider.h"
#include "msm_sim/dynamics/contact_point.h"
#include "msm_sim/dynamics/contact_wrench.h"
#include "msm_sim/dynamics/energies.h"
#include "msm_sim/dynamics/integrator.h"
#include "msm_sim/dynamics/kinematic_group.h"
#include "msm_sim/dynamics/step_report.h"
#include "msm_sim/dynamics/world_options.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/model/model.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core {
namespace internal {
struct WorldState;  // dynamics/world_state.h (private)
class StepLoop;     // dynamics/step_loop.h (private)
}  // namespace internal

/// The simulation: any number of MSM bodies, each an immutable Model (the analogue of MuJoCo's
/// mjModel) with its mutable State (mjData), and the rigid colliders they touch, advanced by
/// docs/physics.md §7's position Verlet with the split microcollision response:
///
///   1. x += dt/2 v            4. v += dt F / m
///   2. pending restitution    5. detect contacts, compute their velocity changes
///   3. F = springs, dampers,  6. v += the part that stops every approach
///      gravity, pushes        7. x += dt/2 v; the rest (restitution) is pending for step 2
///
/// After step 6 no node approaches any surface it touches, so steps 7 and 1 never deepen an
/// overlap. Each contact's normal velocity change is (1 + e) times the approach speed; friction
/// adds up to mu times that, against the tangential velocity and never reversing it.
///
/// With WorldOptions::integrator = kImplicit, steps 3-4 become one linearly implicit kick
/// (docs/physics.md §7.1): F as in step 3 plus gravity at (x_mid, v), K the stiffness at x_mid
/// (without compressed springs' negative geometric part), and v += dv with (M + (h^2/2 + h beta) K)
/// dv = h F - (h^2/2) K v solved by Jacobi-preconditioned conjugate gradient (kinematic nodes' dv
/// fixed to their frames' velocities). This takes the elastic force at the substep's end position
/// and the dampers at v + dv, to first order: for a potential convex along the step the kick never
/// adds energy, and every mode (a = h omega) is damped, stable at any h. Each free border node's
/// deepest collider contact is held in the solve, with its Coulomb friction (docs/physics.md
/// §7.1 "Contacts in the solve"). Steps 1-2 and 5-7 are unchanged. Limits: vibrations are
/// damped numerically (a damping ratio of about a/4 for a << 1).
///
/// Step() subdivides the caller's step into stable substeps (implicit: substeps of at most
/// implicit_max_substep), and either advances everything or,
/// if any substep produces a non-finite value or a node faster than max_speed, restores the
/// last good state, drops the forces applied with ApplyForce (an absurd push is the usual cause,
/// and would fail every later step) and reports why. A failed step without applied forces to
/// drop means that the last good state itself diverges, and every later step would fail too: the
/// bodies are then stopped where they are (velocities zeroed), and if the next step fails again,
/// put back in their rest shape (kinematic groups at their current poses).
class World {
 public:
  explicit World(const WorldOptions& options = {});
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  /// Adds a body at rest at the model's rest positions; returns its index. Throws
  /// std::invalid_argument for out-of-range options.
  int AddBody(const std::string& name, std::shared_ptr<const Model> model,
              const BodyOptions& options = {});
  /// Adds a collider; returns its index. Its pose and twist may be changed between steps.
  int AddCollider(const Collider& collider);
  /// Fixes or drives nodes of a body (see KinematicGroup); returns the group's index. Its
  /// reaction appears among the wrenches with the group's name. Throws std::invalid_argument
  /// for an unknown body or node index.
  int AddKinematicGroup(int body, const KinematicGroup& group);
  /// Pushes a body with `force` (N, world) at `point` (m, world): the force is shared by the
  /// nodes within `radius` of the point (the nearest node if none), in proportion to their
  /// masses, for `duration` seconds (0: the next Step only). Beyond the body's pending-push
  /// bounds (WorldOptions::max_pending_pushes, max_pending_force) the oldest pending pushes are
  /// dropped; returns how many. Throws std::invalid_argument for non-finite values, a negative
  /// radius or duration, or an unknown body.
  int ApplyForce(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                 double radius, double duration);
  /// A wrench at `point`: the force as in ApplyForce, the torque (N m, world) as forces
  /// tau x r_i / sum |r_j|^2 on the same nodes (r from the point), which sum to zero and whose
  /// moment about the point is tau when the nodes surround it evenly. Throws as ApplyForce.
  int ApplyWrench(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                  const Eigen::Vector3d& torque, double radius, double duration);
  /// Swaps a body's model for one with the same nodes (a recalibrated material), keeping its
  /// state, groups and pushes. Throws std::invalid_argument if the node counts differ, and as
  /// AddBody.
  void ReplaceModel(int body, std::shared_ptr<const Model> model, const BodyOptions& options);
  /// Coulomb coefficient for a body against a collider, overriding the default
  /// sqrt(mu_body mu_collider).
  void SetPairFriction(int body, int collider, double friction);
  /// Changes WorldOptions::threads (>= 1) for every body, present and future. Throws
  /// std::invalid_argument if threads < 1.
  void SetThreads(int threads);

  /// Advances by dt (s, > 0) in equal substeps no longer than the stable step (implicit: no
  /// longer than implicit_max_substep); each collider's pose advances with its twist. A bounded
  /// collider found at the start with border node centres inside a body is moved out of it and
  /// pressed back in to its own pose over the following steps (penetration recovery, docs/
  /// physics.md §7.2); its pose and twist as the caller sees them are not changed.
  StepReport Step(double dt);
  /// Puts every body back at rest at its rest positions (kinematic groups at their poses at
  /// time 0), drops pending pushes and contacts, and sets the time to 0.
  void Reset();

  double time() const;
  int num_bodies() const;
  int num_colliders() const;
  const std::string& body_name(int body) const;
  const Model& model(int body) const;
  const State& state(int body) const;
  /// Replaces a body's state (e.g. an initial velocity). Throws std::invalid_argument for a
  /// wrong size or non-finite values.
  void SetState(int body, const State& state);
  Collider& collider(int index);
  const Collider& collider(int index) const;
  const BorderNodes& border(int body) const;
  /// The body's nodes that its kinematic groups fix or drive, ascending (what its stable step
  /// leaves out).
  std::vector<NodeIndex> constrained_nodes(int body) const;
  /// The stable substep of the stiffest body (s), computed at rest; explicit steps divide it by
  /// substep_refinement().
  double stable_time_step() const;
  /// 1, or the power of 2 the World has divided the stable substep by since a step diverged
  /// (WorldOptions::max_substep_refinement); Reset() puts it back to 1.
  int substep_refinement() const;
  Energies ComputeEnergies(int body) const;

  /// Wrenches body `body` exerted during the last Step: one per collider (index = collider
  /// index), then one per kinematic group of that body (in the order added).
  const std::vector<ContactWrench>& wrenches(int body) const;
  /// With WorldOptions::record_contact_points: body `body`'s microcollisions with colliders
  /// during the last accepted Step, substep by substep (the contact stage's and, implicit, the
  /// held contacts'); their impulses sum to the colliders' wrenches times the step. Empty
  /// otherwise, and after a rejected Step. The vector keeps its capacity between steps.
  const std::vector<ContactPoint>& contact_points(int body) const;

 private:
  // The bodies, colliders and time, and the stages that advance them (src/dynamics/): held
  // apart so that this header carries the contract only (docs/architecture.md, "The World").
  std::unique_ptr<internal::WorldState> state_;
  std::unique_ptr<internal::StepLoop> step_loop_;
};

}  // namespace msm_sim::core
