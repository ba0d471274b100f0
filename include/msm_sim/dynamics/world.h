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

struct DofProjection;  // mechanics/masked_pcg.h (private)

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
/// §7.1 "Contacts in the solve"). Steps 1-2 and 5-7 are unchanged. Limits: carrier springs with
/// eMSM dispersion (non-symmetric K) are refused; vibrations are damped numerically (a damping
/// ratio of about a/4 for a << 1).
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

  /// Adds a body at rest at the model's rest positions; returns its index. Throws
  /// std::invalid_argument for out-of-range options, and in an implicit world for a model whose
  /// stiffness is not symmetric (carrier springs with eMSM dispersion: conjugate gradient needs
  /// a symmetric system).
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
  /// masses, for `duration` seconds (0: the next Step only). Throws std::invalid_argument for
  /// non-finite values, a negative radius or duration, or an unknown body.
  void ApplyForce(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
                  double radius, double duration);
  /// A wrench at `point`: the force as in ApplyForce, the torque (N m, world) as forces
  /// tau x r_i / sum |r_j|^2 on the same nodes (r from the point), which sum to zero and whose
  /// moment about the point is tau when the nodes surround it evenly. Throws as ApplyForce.
  void ApplyWrench(int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
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

  double time() const { return time_; }
  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  int num_colliders() const { return static_cast<int>(colliders_.size()); }
  const std::string& body_name(int body) const { return bodies_.at(body).name; }
  const Model& model(int body) const { return *bodies_.at(body).model; }
  const State& state(int body) const { return bodies_.at(body).state; }
  /// Replaces a body's state (e.g. an initial velocity). Throws std::invalid_argument for a
  /// wrong size or non-finite values.
  void SetState(int body, const State& state);
  Collider& collider(int index) { return colliders_.at(index); }
  const Collider& collider(int index) const { return colliders_.at(index); }
  const BorderNodes& border(int body) const { return bodies_.at(body).border; }
  /// The body's nodes that its kinematic groups fix or drive, ascending (what its stable step
  /// leaves out).
  std::vector<NodeIndex> constrained_nodes(int body) const {
    return bodies_.at(body).ConstrainedNodes();
  }
  /// The stable substep of the stiffest body (s), computed at rest; explicit steps divide it by
  /// substep_refinement().
  double stable_time_step() const;
  /// 1, or the power of 2 the World has divided the stable substep by since a step diverged
  /// (WorldOptions::max_substep_refinement); Reset() puts it back to 1.
  int substep_refinement() const { return substep_refinement_; }
  Energies ComputeEnergies(int body) const;

  /// Wrenches body `body` exerted during the last Step: one per collider (index = collider
  /// index), then one per kinematic group of that body (in the order added).
  const std::vector<ContactWrench>& wrenches(int body) const { return bodies_.at(body).wrenches; }
  /// With WorldOptions::record_contact_points: body `body`'s microcollisions with colliders
  /// during the last accepted Step, substep by substep (the contact stage's and, implicit, the
  /// held contacts'); their impulses sum to the colliders' wrenches times the step. Empty
  /// otherwise, and after a rejected Step. The vector keeps its capacity between steps.
  const std::vector<ContactPoint>& contact_points(int body) const {
    return bodies_.at(body).contact_points;
  }

 private:
  struct Push {
    std::vector<NodeIndex> nodes;
    std::vector<Eigen::Vector3d> forces;  // per node
    double remaining;                     // s; <= 0 after its one step
  };
  struct Group {
    KinematicGroup spec;
    Eigen::Matrix3Xd local;          // node offsets in the group frame
    Eigen::Isometry3d initial_pose;  // for a fixed group
  };
  // The restitution part of a contact response, due at step 2 of the next substep.
  struct PendingResponse {
    NodeIndex node;
    Eigen::Vector3d delta_v;
  };
  // Impulses a body gave one collider or group during a Step, turned into a wrench at its end.
  struct ImpulseSum {
    Eigen::Vector3d impulse = Eigen::Vector3d::Zero();  // on the collider, N s
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();   // about its frame origin, N m s
    Eigen::Vector3d weighted_point = Eigen::Vector3d::Zero();
    double weight = 0.0;
    int count = 0;
    Eigen::Vector3d normal_impulses = Eigen::Vector3d::Zero();  // sum of j_n n (colliders)
    double normal_impulse = 0.0;                                // sum of j_n, N s
    double area_time = 0.0;  // m^2 s, touching nodes' surface shares times their substeps
    /// Adds one impulse on the collider at `point`, its moment about `origin`. Inline: the
    /// contact stage calls it once per microcollision, on the thread whose share holds the
    /// ground contacts (docs/design/speed-against-bullet.md).
    void Add(const Eigen::Vector3d& point, const Eigen::Vector3d& origin,
             const Eigen::Vector3d& on_collider) {
      // Tested on the square: the branch then need not wait for the square root.
      const double magnitude_sq = on_collider.squaredNorm();
      if (magnitude_sq == 0.0) return;
      const double magnitude = std::sqrt(magnitude_sq);
      impulse += on_collider;
      moment += (point - origin).cross(on_collider);
      weighted_point += magnitude * point;
      weight += magnitude;
      ++count;
    }
    /// Adds another sum's parts (a node share's, World::CollideWithColliders).
    void Merge(const ImpulseSum& other);
  };
  // Where the contact stage records what it does, for the colliders' wrenches, the next
  // substep and the contact points: a body's own records, or a node share's (CollideWithColliders).
  struct ContactRecords {
    std::vector<ImpulseSum>* impulses;      // colliders, then groups
    std::vector<PendingResponse>* pending;  // rebounds for the next substep
    std::vector<ContactPoint>* points;      // if recorded
    int microcollisions = 0;
  };
  // A node share's records beyond the first share, added to the body's in share order.
  struct ShareRecords {
    std::vector<ImpulseSum> impulses;
    std::vector<PendingResponse> pending;
    std::vector<ContactPoint> points;
  };
  struct Body {
    /// At rest, with everything derived from the model: border, stable step (for the World's
    /// safety factor), the self-contact distance; the evaluator gets the World's thread count.
    Body(const std::string& body_name, std::shared_ptr<const Model> body_model,
         const BodyOptions& body_options, const WorldOptions& world_options);
    /// stable_step for the model without the constrained nodes (StableTimeStepOptions::
    /// fixed_nodes): called again whenever the constrained nodes change.
    void UpdateStableStep(const WorldOptions& world_options);
    std::vector<NodeIndex> ConstrainedNodes() const;
    std::string name;
    std::shared_ptr<const Model> model;
    BodyOptions options;
    State state;
    ForceEvaluator evaluator;
    BorderNodes border;
    std::vector<Group> groups;
    std::vector<char> constrained;  // per node
    std::vector<Push> pushes;
    std::vector<PendingResponse> pending;
    // The rebounds the first node share's contacts leave while `pending` is still being applied
    // (SubstepInOnePass), moved into it once it has been.
    std::vector<PendingResponse> next_pending;
    // Node 0's position at the start of the current Step: the explicit force loops of all its
    // substeps round positions relative to it (NodeStages::origin), so that a substep can
    // round the next one's nodes ahead (SubstepInOnePass).
    Eigen::Vector3d float_origin = Eigen::Vector3d::Zero();
    std::vector<double> pair_friction;           // per collider; < 0: default
    double stable_step = 0.0;                    // without the constrained nodes (UpdateStableStep)
    double self_contact_rest_distance_sq = 0.0;  // m^2
    Eigen::VectorXd inverse_masses;
    // During the current Step, noted only when a node breaks max_speed or a value is not
    // finite (then infinite): the fastest node's speed squared, and which node.
    double fastest_speed_sq = 0.0;
    int fastest_node = 0;
    Eigen::Matrix3Xd saved_positions, saved_velocities;  // to restore a rejected Step
    std::vector<PendingResponse> saved_pending;
    Eigen::Matrix3Xd forces;
    Eigen::Matrix3Xd implicit_dv, saved_implicit_dv;  // last implicit kick: the next one's start
    // Per node, the Coulomb impulse of the last implicit kick's sliding contact (0: stuck, or no
    // contact): the next kick starts that contact sliding with it (docs/physics.md §7.1).
    Eigen::Matrix3Xd sliding_friction, saved_sliding_friction;
    std::vector<ImpulseSum> impulses;          // colliders, then groups (during a Step)
    std::vector<ContactWrench> wrenches;       // colliders, then groups (of the last Step)
    std::vector<ContactPoint> contact_points;  // of the last Step, if recorded
    std::vector<char> near_collider;           // per border node, this substep: within reach of one
    std::vector<ShareRecords> share_records;   // the contact stage's shares after the first
    /// The body's own contact records.
    ContactRecords Records() { return {&impulses, &pending, &contact_points}; }
  };

  // Where a Step started, for a rejected one to return to (bodies keep their own saved states).
  struct StepStart {
    std::vector<Eigen::Isometry3d> collider_poses;
    double time = 0.0;
  };
  // One substep's contact records (defined in the private dynamics/world_contact_stage.h, and
  // PairContact in world_pair_contacts.cpp).
  struct ColliderFrame;  // a collider's inverse pose and bounds, for detection
  struct NodeContact;    // a node touching a collider
  struct ContactStage;   // what a body's contact stage shares between its node shares
  struct PairContact;    // two nodes touching

  // Step's stages (world_step.cpp).
  /// Copies every body's state and pending responses into its buffers (the explicit integrator's
  /// node states in each step's first drift, DriftForceAndKick); returns the rest.
  StepStart SaveForRollback();
  /// Zeroes what a Step accumulates: impulses, microcollisions, each body's fastest node.
  void ClearStepRecords();
  /// Runs `count` substeps of h (s); returns the first problem CheckSane finds, empty if none.
  std::string RunSubsteps(int count, double h, const std::vector<Eigen::Isometry3d>& start_poses);
  /// Restores what SaveForRollback saved and drops the pushes; returns whether there were any.
  bool RollBack(const StepStart& start);
  /// Restores what SaveForRollback saved (bodies, collider poses, time); keeps the pushes.
  void RestoreStepStart(const StepStart& start);
  /// Whether a step that failed with no push in flight may be taken again with finer substeps.
  bool MayRefineSubsteps() const;
  /// Zeroes every body's velocities and pending restitution (a failed step with nothing to drop).
  void StopBodies();
  /// Puts every body at rest in its rest shape, its kinematic groups at their current poses.
  void RestoreRestShapes();
  /// Ends an accepted Step of dt (s): time, collider poses, pushes, wrenches.
  void FinishStep(double dt, const StepStart& start);
  /// Pushes for "one step" are done; timed ones count down by dt (s).
  static void CountDownPushes(Body* body, double dt);
  /// The last Step's wrenches: its impulses over dt (s), at the impulses' centroid.
  static void TurnImpulsesIntoWrenches(Body* body, double dt);
  /// Empty if every node is finite and no faster than max_speed, else why not.
  std::string CheckSane() const;

  // Substep: the seven stages of the class comment; a substep of h (s) from t0 = time_ + step_time.
  void Substep(double h, const std::vector<Eigen::Isometry3d>& start_poses, double step_time);
  /// Whether a substep may run stages 5-7 inside the force loops' node shares
  /// (SubstepInOnePass): one body in an explicit world, without kinematic groups or
  /// self-collision, so that nothing between its kick and its last drift needs the whole body
  /// (driving a group's nodes, contacts between nodes).
  bool SubstepsInOnePass() const;
  /// Substep for that body: the colliders at mid-substep first (stages 1-4 do not read them),
  /// then each node share drifts, kicks, collides its border nodes and drifts again on its own
  /// thread: two hand-overs between threads fewer per substep than stage by stage. Within a
  /// Step, a share's last drift also takes the next substep's first (DriftShare), applies
  /// the rebounds its contacts left and rounds its nodes for the next float loops: one pass over
  /// the nodes and one more hand-over fewer. The same arithmetic in the same order per node, and
  /// the same records in the same order, as Substep stage by stage.
  void SubstepInOnePass(Body* body, double h, const std::vector<Eigen::Isometry3d>& start_poses,
                        double step_time);
  /// 1. x += h/2 v for nodes [begin, end); their kinematic nodes go where `poses` (GroupPoses
  /// at t0 + h/2) put them. `save`: first copies the nodes' positions and velocities into the
  /// saved ones, for a rejected step (the explicit integrator's first drift of a step).
  static void DriftHalf(Body* body, double h, const std::vector<Eigen::Isometry3d>& poses,
                        int begin, int end, bool save = false);
  /// 2. v += the restitution left over from the last substep's contacts (then none pending).
  static void ApplyPendingRestitution(Body* body);
  /// The same for the nodes [begin, end) from `rebounds` (body->pending, or a node share's
  /// rebounds applied ahead by SubstepInOnePass), leaving the list as it is.
  static void ApplyPendingRestitution(Body* body, const std::vector<PendingResponse>& rebounds,
                                      int begin, int end);
  /// 3. Springs, dampers and pushes into body->forces (gravity comes with the kick).
  static void ComputeForces(Body* body);
  /// 3. Adds the pushes on nodes [begin, end) to body->forces.
  static void AddPushes(Body* body, int begin, int end);
  /// 4. v += h (F / m + g) for nodes [begin, end). Precondition: their forces of this substep.
  void Kick(Body* body, double h, int begin, int end) const;
  /// At a Step's start: cuts the body's node shares at equal work, counting the work of the
  /// border nodes the last contact stage found near a collider (ForceEvaluator::CutNodeShares),
  /// or, without `cut`, into equal shares.
  void CutNodeSharesAtContacts(Body* body, bool cut) const;
  /// The fewest substeps in a Step for CutNodeSharesAtContacts to cut at the contacts.
  static constexpr int kSubstepsToCutAtContacts = 4;
  /// 1-4 of the explicit integrator: each node share of the body's force loops drifts, places
  /// its kinematic nodes and applies its pending restitution, then, once its forces are set,
  /// adds its pushes and kicks, all on the share's thread (ForceEvaluator::NodeStages).
  /// `finish(share, begin, end)`, if given, runs on each share right after its kick.
  /// `drifted`: stages 1-2 were already taken (drifted_ahead_; only without kinematic groups,
  /// whose nodes it would not place), and the nodes rounded for the float loops if
  /// rounded_ahead_. `rounds_ahead`: `finish` rounds every node for the next substep
  /// (ForceEvaluator::NodeStages::rounds_ahead).
  void DriftForceAndKick(Body* body, double h, double t0,
                         const std::function<void(int, int, int)>* finish = nullptr,
                         bool drifted = false, bool rounded = false, bool rounds_ahead = false);
  /// 4. Kinematic nodes take their frames' velocities; the change is the groups' reaction.
  void DriveKinematicGroups(Body* body, double h, double t0) const;
  /// 3-4, implicit (world_implicit.cpp): forces and gravity at (x_mid, v), then v += dv with
  /// (M + (h^2/2 + h beta) K) dv = h F - (h^2/2) K v (the elastic force at the substep's end
  /// position, docs/physics.md §7.1) by masked conjugate gradient; a kinematic node gets the
  /// velocity the forces (with dv) would give it, for DriveKinematicGroups to record the
  /// reaction. Returns the solver's iterations. Precondition: steps 1-2 of this substep done.
  int ImplicitKick(Body* body, double h, double t0);
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
  /// The deepest collider contact of each free border node of body at its current (mid-substep)
  /// position whose collision sphere is within kSpeculativeReach radii of touching (a
  /// speculative contact, closing_speed = gap / h), detected as CollideWithColliders does.
  /// Precondition: colliders at their mid-substep poses (PlaceCollidersAtMidSubstep), h > 0.
  std::vector<ContactNormal> DeepestColliderContacts(const Body& body, double h) const;
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
  int SolveImplicitKick(Body* body, double h, double t0, double c, std::vector<ContactNormal>* held,
                        std::vector<ContactNormal>* speculative, Eigen::Matrix3Xd* residual);
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
  /// contact whose hold's tangential impulse exceeds friction times its normal one slides, with
  /// the Coulomb impulse along that tangential impulse; a sliding one whose slip (v + dv
  /// relative to the collider) turned more than 45 degrees from against its impulse sticks; a
  /// sliding one's impulse takes friction times the new normal impulse when that moved it by more
  /// than kSlidingImpulseTolerance. Returns whether any of that happened.
  /// Precondition: no contact in held pulls (ReleasePullingContacts).
  static bool UpdateFrictionHolds(const Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& dv,
                                  const Eigen::Matrix3Xd& residual,
                                  std::vector<ContactNormal>* held);
  /// For a stuck contact whose hold applied `impulse` (N s, on the node): the Coulomb impulse it
  /// slides with when the tangential part leaves the cone (friction times the normal part, along
  /// the tangential part); zero while it stays within.
  static Eigen::Vector3d SlidingImpulseOfStick(const ContactNormal& contact,
                                               const Eigen::Vector3d& impulse);
  /// Removes from *held the contacts whose hold pulls the node into the collider after a solve
  /// with this residual (b - A dv); returns whether there was any.
  static bool ReleasePullingContacts(const Eigen::Matrix3Xd& residual,
                                     std::vector<ContactNormal>* held);
  /// Records each held contact's impulse (-residual . n, when it pushes) in its collider's
  /// wrench, with the friction the solve applied (a stuck hold's tangential impulse, a sliding
  /// one's Coulomb impulse) and the restitution of its approach before the kick pending, as
  /// RespondToColliderContact does for the contact stage; a sliding node also takes the
  /// rebound's friction (up to mu times it, never reversing the sliding). Keeps the sliding
  /// impulses in body->sliding_friction for the next kick. Precondition: the held nodes'
  /// velocities are v + dv.
  void RespondToHeldContacts(Body* body, const std::vector<ContactNormal>& held,
                             const Eigen::Matrix3Xd& residual);
  /// Moves every collider to its pose at the middle of the substep [step_time, step_time + h]
  /// of the Step that started with start_poses.
  void PlaceCollidersAtMidSubstep(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                                  double step_time);
  /// The velocity change (m/s, 3 x N) a kinematic group prescribes to its nodes over the
  /// substep [t0, t0 + h] (zero columns for free nodes).
  Eigen::Matrix3Xd PrescribedVelocityChanges(const Body& body, double h, double t0) const;
  /// Throws std::invalid_argument if the world is implicit and the body's stiffness is not
  /// symmetric.
  void RequireIntegrable(const Body& body) const;
  /// 5-6. Colliders at mid-substep; every contact stops approaching, its rebound pending.
  void ResolveContacts(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                       double step_time);
  /// 7. x += h/2 v, noting the fastest node; kinematic nodes at their frames at t0 + h.
  void DriftHalfNotingFastest(Body* body, double h, double t0) const;
  /// 7 for node share `share` [begin, end): x += h/2 v, its fastest velocity component and
  /// whether a value is not finite into fastest[share] and nonfinite[share]. `twice`: then
  /// stage 1 of the next substep (x += h/2 v again, before its restitution), the same two
  /// roundings per coordinate in one pass over the nodes, the extremes noted at the substep's end.
  static void DriftShare(Body* body, double h, bool twice, int share, int begin, int end,
                         std::vector<double>* fastest, std::vector<double>* nonfinite);
  /// 7, after every share's drift: notes the fastest node if a share flagged one, and places the
  /// kinematic nodes at their frames at t.
  void NoteDriftExtremes(Body* body, const std::vector<double>& fastest,
                         const std::vector<double>& nonfinite, double t) const;
  /// Notes the body's fastest node, or a node with a non-finite value, for CheckSane.
  static void NoteFastest(Body* body);

  // Contacts (world_contacts.cpp). Precondition: the impulses are sized (ClearStepRecords).
  /// Stops every approach of body's free border nodes towards the colliders, with friction.
  /// Runs on the node shares of the body's force loops (ForceEvaluator::ForEachNodeShare), each
  /// share taking the border nodes among its nodes and recording into its own ContactRecords,
  /// added to the body's in share order: with one share the body's records directly.
  void CollideWithColliders(Body* body, int* microcollisions);
  /// CollideWithColliders in three parts. Begin: the colliders' frames (at their current
  /// poses) and frictions, the near flags and the shares' records sized. Precondition: some
  /// collider.
  ContactStage BeginContactStage(Body* body) const;
  /// Node share `share` [begin, end): its border nodes, recorded into the body's records (share
  /// 0, its rebounds into *first_pending) or the share's own.
  void CollideShare(ContactStage* stage, Body* body, int share, int begin, int end,
                    std::vector<PendingResponse>* first_pending) const;
  /// End: the records of the shares after the first added to the body's in share order, and
  /// the microcollisions to *microcollisions.
  static void EndContactStage(const ContactStage& stage, Body* body, int* microcollisions);
  /// Border nodes [k_begin, k_end) of CollideWithColliders; `frictions`: Friction(*body, c) per
  /// collider c.
  void CollideBorderNodes(const std::vector<ColliderFrame>& frames,
                          const std::vector<double>& frictions, Body* body, std::size_t k_begin,
                          std::size_t k_end, ContactRecords* records) const;
  /// Each collider's inverse pose and bounds (computed once per body and substep).
  std::vector<ColliderFrame> FrameColliders() const;
  /// Flags in body->near_collider the border nodes [k_begin, k_end) that pass
  /// DetectColliderContacts' first tests (a plane's distance, a bounded collider's world box)
  /// for some enabled collider. Precondition: near_collider sized to the border.
  void FlagNodesNearColliders(const std::vector<ColliderFrame>& frames, Body* body,
                              std::size_t k_begin, std::size_t k_end) const;
  /// Replaces *contacts with the enabled colliders a node at x with this radius (m) touches.
  /// Precondition: frames from FrameColliders for the colliders' current poses.
  void DetectColliderContacts(const std::vector<ColliderFrame>& frames, const Eigen::Vector3d& x,
                              double radius, std::vector<NodeContact>* contacts) const;
  /// Up to contact_iterations Gauss-Seidel sweeps taking each contact's approach out of *v.
  void StopColliderApproaches(std::vector<NodeContact>* contacts, Eigen::Vector3d* v) const;
  /// Friction with coefficient `friction` into *v (0 for none: a node being recovered from a
  /// deep overlap), the rebound pending, the impulse recorded. Precondition: stopped > 0.
  void RespondToColliderContact(const Body& body, NodeIndex node, const NodeContact& contact,
                                double friction, Eigen::Vector3d* v, ContactRecords* records) const;
  /// The impulse a node gave a collider in this substep (normal_impulse N s along -normal,
  /// tangential N s along the surface) into the collider's sum and, if recording, the contact
  /// points.
  void RecordColliderImpulse(ContactRecords* records, NodeIndex node, int collider,
                             const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                             double normal_impulse, const Eigen::Vector3d& tangential) const;
  /// Border node k's surface share into the patch of every collider in *contacts (detected with
  /// the patch's reach), then drops those its collision sphere does not overlap.
  void CountInPatches(const Body& body, std::size_t k, std::vector<NodeContact>* contacts,
                      ContactRecords* records) const;
  /// Stops every approach between touching border nodes (of two bodies, or a folded one).
  void CollideNodes(int* microcollisions);

  // Penetration recovery (world_contacts.cpp, docs/physics.md §7.2).
  /// The separation speed (m/s) an overlap this deep (m) is recovered at; 0 if depth <= 0.
  double RecoverySpeed(double depth) const;
  /// Moves a node with this collision radius out of the colliders it overlaps (contacts as
  /// CountInPatches leaves them), by the part of the recovery speed its velocity lacks, times h.
  void RecoverFromColliders(Body* body, NodeIndex node, double radius,
                            const std::vector<NodeContact>& contacts) const;
  // A collider that appears with node centres inside (world_collider_entry.cpp, docs/physics.md
  // §7.2): moved out of the bodies and pressed back in.
  /// A collider's way back in: its contacts use its pose moved by depth along direction (m,
  /// world frame), and the depth shrinks at RecoverySpeed(depth) to 0.
  struct ColliderEntry {
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();      // unit, out of the bodies
    double depth = 0.0;                                       // m, at the Step's start
    double depth_after = 0.0;                                 // m, at the current Step's end
    Eigen::Vector3d user_velocity = Eigen::Vector3d::Zero();  // the collider's own, m/s
  };
  /// For each bounded enabled collider: if border node centres of any body lie inside it at
  /// its pose plus its entry, the entry grows to where no collision sphere touches it (along
  /// the way out of the bodies, fixed when the entry starts); returns the poses the substeps
  /// start from (poses plus the entries) and adds the entries' shrinking over dt to the
  /// colliders' velocities. Precondition: poses are the colliders' at the Step's start; call
  /// EndColliderEntries after the substeps.
  std::vector<Eigen::Isometry3d> BeginColliderEntries(double dt,
                                                      const std::vector<Eigen::Isometry3d>& poses);
  /// Gives the colliders their own velocities back; the entries advance if the Step was
  /// accepted and stay where they were if not.
  void EndColliderEntries(bool accepted);
  /// max over all bodies' border nodes of r - signed distance from the collider at pose (m),
  /// r their collision radius, or 0 if `centres` (the deepest centre); -inf if none is near.
  double DeepestBorderOverlap(const Collider& collider, const Eigen::Isometry3d& pose,
                              bool centres) const;
  /// The unit direction out of the bodies at the node centres inside the collider at pose: minus
  /// the sum of their stars' unit vectors; zero if there is none.
  Eigen::Vector3d WayOutOfBodies(const Collider& collider, const Eigen::Isometry3d& pose) const;
  /// The least distance (>= from, m) the collider at pose must move along direction for no
  /// collision sphere to overlap it (sphere tracing); NaN if none within the collider's size.
  double DistanceToClear(const Collider& collider, const Eigen::Isometry3d& pose,
                         const Eigen::Vector3d& direction, double from) const;

  /// The touching pairs of border nodes, found with a spatial hash.
  std::vector<PairContact> FindTouchingPairs();
  /// False when no body may touch itself and no two bodies' border nodes come within reach.
  bool MayHaveTouchingPairs() const;
  /// Whether nodes i and j of one body may touch: only if it folds (see self_collision).
  static bool MayTouchItself(const Body& body, NodeIndex i, NodeIndex j);
  /// Adds the pair if |d| = |x_i - x_j| (m) is below reach (m) and one of them may move.
  static void AddPairIfTouching(Body* body_i, NodeIndex i, Body* body_j, NodeIndex j,
                                const Eigen::Vector3d& d, double reach,
                                std::vector<PairContact>* pairs);
  /// Up to contact_iterations Gauss-Seidel sweeps taking every pair's approach out.
  void StopPairApproaches(std::vector<PairContact>* pairs) const;
  /// Friction between the pair's nodes, their rebound pending. Precondition: stopped > 0.
  static void RespondToPairContact(const PairContact& pair);
  /// Moves the nodes of the pairs that overlap beyond the slop apart, by the part of the
  /// recovery speed their relative velocity lacks, times h, shared by inverse masses; each
  /// node's summed shift capped at penetration_max_speed times h.
  void RecoverFromPairs(const std::vector<PairContact>& pairs);
  /// The body's slot of *shifts (one per body), zero-filled on first use.
  Eigen::Matrix3Xd& ShiftOf(const Body* body, std::vector<Eigen::Matrix3Xd>* shifts) const;
  /// Coulomb coefficient of a body against a collider: the pair's, or sqrt(mu_body mu_collider).
  double Friction(const Body& body, int collider) const;

  // Bookkeeping (world.cpp).
  /// The group's frame at time t (s): its pose function's, or the pose it was added with.
  Eigen::Isometry3d GroupPose(const Group& group, double t) const;
  /// Puts a body's kinematic nodes where their frames are at time t.
  void PlaceGroups(Body* body, double t) const;
  /// The body's groups' frames at time t (s), in group order.
  std::vector<Eigen::Isometry3d> GroupPoses(const Body& body, double t) const;
  /// Puts the body's kinematic nodes in [begin, end) where `poses` (GroupPoses) put them; calls
  /// no pose function, so node shares may run it on their threads.
  static void PlaceGroupNodes(Body* body, const std::vector<Eigen::Isometry3d>& poses, int begin,
                              int end);
  int microcollisions_ = 0;
  int solver_iterations_ = 0;           // during the current Step (implicit)
  bool stopped_after_failure_ = false;  // the last Step failed and stopped the bodies
  int substep_refinement_ = 1;          // explicit: stable substep divided by this (Step)
  int substep_index_ = 0;               // of the current substep within its Step
  int substep_count_ = 0;               // substeps of the current Step
  // SubstepInOnePass: the last drift of the substep just taken also took the next substep's
  // first drift (DriftShare twice) and applied its restitution; that substep's first stage then
  // has nothing left to do. rounded_ahead_: and the nodes were rounded for its float loops.
  bool drifted_ahead_ = false;
  bool rounded_ahead_ = false;
  double substep_ = 0.0;  // s, the current substep

  WorldOptions options_;
  std::vector<Body> bodies_;
  std::vector<Collider> colliders_;
  std::vector<ColliderEntry> entries_;  // per collider (BeginColliderEntries)
  double time_ = 0.0;
};

}  // namespace msm_sim::core
