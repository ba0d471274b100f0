#pragma once
// Private to msm_sim's World: the implicit integrator's kick (docs/physics.md §7.1), steps 3-4 of
// the substep as one linearly implicit velocity update solved by masked conjugate gradient, with
// each free border node's deepest collider contact held in the solve.

#include <vector>

#include <Eigen/Core>

#include "dynamics/collider_contacts.h"
#include "dynamics/world_state.h"
#include "mechanics/node_array_krylov.h"

namespace msm_sim::core {

namespace internal {

/// How the implicit solve treats a held contact tangentially (docs/physics.md §7.1).
enum class FrictionHold {
  kStuck,    ///< the whole velocity relative to the collider is held
  kSliding,  ///< free tangentially, with the Coulomb impulse sliding_impulse on it
};

/// A free border node's deepest collider contact, held along its normal in the implicit solve.
struct ContactNormal {
  NodeIndex node;
  Eigen::Vector3d normal;    // unit, out of the collider
  Eigen::Vector3d velocity;  // of the collider's material at the contact point
  Eigen::Vector3d point;     // on the collider's surface
  int collider;
  /// Normal speed towards the collider before the kick beyond closing_speed (m/s, >= 0).
  double approach;
  double friction;  // Coulomb coefficient of the pair
  /// The gap between the node's collision sphere and the collider over the substep's length
  /// (m/s, >= 0; 0 for a sphere that touches): a speculative contact's hold lets the node
  /// approach at this speed, closing the gap by the next substep's detection, and no faster.
  double closing_speed;
  /// A speculative contact is held once its node approaches faster than this (m/s): its
  /// closing speed plus kSpeculativeSlop radii per substep.
  double holding_speed;
  /// Stuck while its hold's tangential impulse stays within friction times its normal one;
  /// sliding (always, when friction is 0) with sliding_impulse, tangential, of norm friction
  /// times the last solve's normal impulse, against the slip.
  FrictionHold friction_hold;
  Eigen::Vector3d sliding_impulse;  // N s, on the node
};

/// The implicit kick of a WorldState's bodies.
class ImplicitIntegrator {
 public:
  ImplicitIntegrator(WorldState* world, ColliderContacts* contacts)
      : world_(*world), contacts_(*contacts) {}

  /// 3-4: forces and gravity at (x_mid, v), then v += dv with (M + (h^2/2 + h beta) K) dv =
  /// h F - (h^2/2) K v (the elastic force at the substep's end position) by masked conjugate
  /// gradient; a kinematic node gets the velocity the forces (with dv) would give it, for
  /// DriveKinematicGroups to record the reaction. Returns the solver's iterations.
  /// Preconditions: steps 1-2 of this substep done, colliders at their mid-substep poses.
  int Kick(Body* body, double h, double t0);
  /// The deepest collider contact of each free border node of body at its current (mid-substep)
  /// position whose collision sphere is within kSpeculativeReach radii of touching (a
  /// speculative contact, closing_speed = gap / h), detected as the contact stage does.
  /// Precondition: colliders at their mid-substep poses, h > 0.
  std::vector<ContactNormal> DeepestColliderContacts(const Body& body, double h) const;
  /// Records each held contact's impulse (-residual . n, when it pushes) in its collider's
  /// wrench, with the friction the solve applied (a stuck hold's tangential impulse, a sliding
  /// one's Coulomb impulse) and the restitution of its approach before the kick pending, as the
  /// contact stage does; a sliding node also takes the rebound's friction (up to mu times it,
  /// never reversing the sliding). Keeps the sliding impulses in body->sliding_friction for the
  /// next kick. Precondition: the held nodes' velocities are v + dv.
  void RespondToHeldContacts(Body* body, const std::vector<ContactNormal>& held,
                             const Eigen::Matrix3Xd& residual);

  /// The kick's conjugate-gradient options for a substep h of a body whose free DOFs are `free`
  /// (WorldOptions' tolerances; the early stop bounds the change the residual impulse r can make
  /// to the kinetic energy after the kick: |r|_(M^-1) <= implicit_energy_tolerance |v + dv|_M,
  /// docs/physics.md §7.1, over the nodes free in `free`). The options refer to *body's masses
  /// and velocities, which must outlive them and not change while they are in use.
  static MaskedPcgOptions SolverOptions(const WorldOptions& options, const Body& body, double h,
                                        const Eigen::Matrix3Xd& free);
  /// Moves from *speculative to *held the contacts whose node, at velocity v + dv, approaches
  /// its collider faster than its holding speed; returns whether there was any.
  static bool HoldReachingContacts(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
                                   std::vector<ContactNormal>* speculative,
                                   std::vector<ContactNormal>* held);
  /// With a projection: holds in it the held contacts' normals, and the whole node of a stuck
  /// one; without: sets the held part of *dv, a normal velocity towards the collider of its
  /// closing speed (and, stuck, no tangential one relative to the collider).
  static void HoldContacts(const Eigen::Matrix3Xd& v, const std::vector<ContactNormal>& held,
                           DofProjection* projection, Eigen::Matrix3Xd* dv);
  /// After a solve with this residual (b - A dv, the sliding impulses included in b): a stuck
  /// contact whose hold's tangential impulse exceeds friction times its normal one by more than
  /// kSlidingImpulseTolerance of it slides, with the Coulomb impulse along that tangential
  /// impulse; a sliding one whose slip (v + dv relative to the collider) turned more than 45
  /// degrees from against its impulse sticks; a sliding one's impulse takes friction times the
  /// new normal impulse when that moved it by more than kSlidingImpulseTolerance. Returns
  /// whether any of that happened.
  /// Precondition: no contact in held pulls (ReleasePullingContacts).
  static bool UpdateFrictionHolds(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
                                  const Eigen::Matrix3Xd& residual,
                                  std::vector<ContactNormal>* held);
  /// For a stuck contact whose hold applied `impulse` (N s, on the node): the Coulomb impulse it
  /// slides with when the tangential part leaves the cone widened by `margin` (a fraction of
  /// friction times the normal part), friction times the normal part along the tangential
  /// part; zero while it stays within. Precondition: margin >= 0.
  static Eigen::Vector3d SlidingImpulseOfStick(const ContactNormal& contact,
                                               const Eigen::Vector3d& impulse, double margin = 0.0);
  /// Removes from *held the contacts whose hold pulls the node into the collider after a solve
  /// with this residual (b - A dv); returns whether there was any.
  static bool ReleasePullingContacts(const Eigen::Matrix3Xd& residual,
                                     std::vector<ContactNormal>* held);

 private:
  /// Solves (M + c K) dv = h F - (h^2/2) K v into body->implicit_dv with the kinematic nodes and
  /// the contacts in *held held (a held node ends approaching its collider at its closing speed:
  /// not at all once touching; a stuck one moves with the collider tangentially, a sliding one
  /// takes its Coulomb impulse); then releases the holds that pull, holds the contacts of
  /// *speculative whose node the solution takes past the surface (moving them to *held), lets
  /// slide the stuck contacts whose hold leaves Coulomb's cone and sticks the sliding ones whose
  /// slip turned away from their friction (UpdateFrictionHolds), and solves again while any of
  /// that changed anything (at most kImplicitContactPasses solves).
  /// *held ends as the contacts held in the last solve, *residual as the right-hand side minus
  /// (M + c K) dv. Returns the solver's iterations. Precondition: body->forces and the stiffness
  /// linearised.
  int SolveKick(Body* body, double h, double t0, double c, std::vector<ContactNormal>* held,
                std::vector<ContactNormal>* speculative, Eigen::Matrix3Xd* residual);
  /// The velocity change (m/s, 3 x N) a kinematic group prescribes to its nodes over the
  /// substep [t0, t0 + h] (zero columns for free nodes).
  static Eigen::Matrix3Xd PrescribedVelocityChanges(const Body& body, double h, double t0);

  WorldState& world_;
  ColliderContacts& contacts_;
};

}  // namespace internal
}  // namespace msm_sim::core
