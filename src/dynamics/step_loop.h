#pragma once
// Private to msm_sim's World: World::Step (world.h's class comment): substeps of named stages in
// order, each a collaborator's, and the rollback of a Step that failed.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "dynamics/body_entries.h"
#include "dynamics/collider_contacts.h"
#include "dynamics/collider_entries.h"
#include "dynamics/explicit_integrator.h"
#include "dynamics/implicit_integrator.h"
#include "dynamics/pair_contacts.h"
#include "dynamics/world_state.h"
#include "msm_sim/dynamics/step_report.h"

namespace msm_sim::core::internal {

/// Where a Step started, for a rejected one to return to (bodies keep their own saved states).
struct StepStart {
  std::vector<Eigen::Isometry3d> collider_poses;
  double time = 0.0;
};

/// Advances a WorldState: the integrators, the contact stages and penetration recovery are its
/// collaborators, each over the same state.
class StepLoop {
 public:
  explicit StepLoop(WorldState* world)
      : world_(*world),
        contacts_(world),
        pairs_(world),
        entries_(world),
        body_entries_(world),
        explicit_(world, &contacts_),
        implicit_(world, &contacts_) {}
  StepLoop(const StepLoop&) = delete;
  StepLoop& operator=(const StepLoop&) = delete;

  /// World::Step: substeps of dt, refined or rolled back as world.h describes.
  StepReport Step(double dt);
  /// Puts every body at rest in its rest shape, its kinematic groups at their current poses.
  void RestoreRestShapes();

 private:
  // A Step (step_loop.cpp).
  /// Zeroes what a Step accumulates: impulses, microcollisions, each body's fastest node.
  void ClearStepRecords();
  /// Runs `count` substeps of h (s); returns the first problem CheckSane finds, empty if none.
  std::string RunSubsteps(int count, double h, const std::vector<Eigen::Isometry3d>& start_poses);
  /// The seven stages of world.h's class comment: a substep of h (s) from t0 = time +
  /// step_time, the colliders moving from start_poses.
  void Substep(double h, const std::vector<Eigen::Isometry3d>& start_poses, double step_time);
  /// 1-4 for every body: the explicit kick, or the implicit one after the drift and the
  /// restitution; then the kinematic nodes driven. Implicit: colliders at mid-substep.
  void KickBodies(double h, double t0);
  /// 5-6. Colliders at mid-substep; every contact stops approaching, its rebound pending.
  void ResolveContacts(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                       double step_time);
  /// 7 for every body: x += h/2 v, noting the fastest node.
  void DriftBodies(double h, double t0);
  /// Moves every collider to its pose at the middle of the substep [step_time, step_time + h]
  /// of the Step that started with start_poses.
  void PlaceCollidersAtMidSubstep(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                                  double step_time);
  /// Empty if every node is finite and no faster than max_speed, else why not.
  std::string CheckSane() const;
  /// Ends an accepted Step of dt (s): time, collider poses, pushes, wrenches.
  void FinishStep(double dt, const StepStart& start);

  // Rollback and the end of a Step (step_rollback.cpp).
  /// Copies every body's state and pending responses into its buffers (the explicit
  /// integrator's node states in each step's first drift, DriftForceAndKick); returns the rest.
  StepStart SaveForRollback();
  /// Restores what SaveForRollback saved and drops the pushes; returns whether there were any.
  bool RollBack(const StepStart& start);
  /// Restores what SaveForRollback saved (bodies, collider poses, time); keeps the pushes.
  void RestoreStepStart(const StepStart& start);
  /// A Step that failed with `problem` even with finer substeps: back to its start, the pushes
  /// dropped, or the bodies stopped, or put back in their rest shape; the report says which.
  void RejectStep(const StepStart& start, const std::string& problem, StepReport* report);
  /// Whether a step that failed with no push in flight may be taken again with finer substeps.
  bool MayRefineSubsteps() const;
  /// Zeroes every body's velocities and pending restitution (a failed step with nothing to drop).
  void StopBodies();
  /// Pushes for "one step" are done; timed ones count down by dt (s).
  static void CountDownPushes(Body* body, double dt);
  /// The last Step's wrenches: its impulses over dt (s), at the impulses' centroid.
  static void TurnImpulsesIntoWrenches(Body* body, double dt);

  WorldState& world_;
  ColliderContacts contacts_;
  PairContacts pairs_;
  ColliderEntries entries_;
  BodyEntries body_entries_;
  ExplicitIntegrator explicit_;
  ImplicitIntegrator implicit_;
};

}  // namespace msm_sim::core::internal
