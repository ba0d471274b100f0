// StepLoop::Step: substeps of the stages of world.h's class comment, in order (step_loop.h).
// Compiled without contraction into FMAs, as the stages' files (CMakeLists.txt).
#include "dynamics/step_loop.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "dynamics/node_stages.h"
#include "dynamics/world_internal.h"

namespace msm_sim::core::internal {
namespace {

// The collider pose after moving for tau seconds with its (constant) twist.
Eigen::Isometry3d Advance(const Eigen::Isometry3d& pose, const Collider& collider, double tau) {
  Eigen::Isometry3d moved = pose;
  moved.translation() += tau * collider.linear_velocity;
  const double angle = collider.angular_velocity.norm() * tau;
  if (angle > 0.0) {
    moved.linear() =
        Eigen::AngleAxisd(angle, collider.angular_velocity.normalized()).toRotationMatrix() *
        pose.linear();
  }
  return moved;
}

// Equal substeps of dt no longer than the stable step (one if no body limits it).
int NumSubsteps(double dt, double stable) {
  const int substeps = std::isfinite(stable) ? static_cast<int>(std::ceil(dt / stable - 1e-9)) : 1;
  return std::max(substeps, 1);
}

}  // namespace

StepReport StepLoop::Step(double dt) {
  Require(dt > 0.0 && Finite(dt), "step must be finite and > 0");
  StepReport report;
  const StepStart start = SaveForRollback();
  const bool implicit = world_.options.integrator == Integrator::kImplicit;
  std::string problem;
  const int refinement_before = world_.substep_refinement;
  for (;;) {
    report.substeps =
        NumSubsteps(dt, implicit ? world_.options.implicit_max_substep
                                 : world_.StableTimeStep() / world_.substep_refinement);
    report.substep = dt / report.substeps;
    report.substep_refinement = world_.substep_refinement;
    ClearStepRecords();
    const std::vector<Eigen::Isometry3d> poses = entries_.Begin(dt, start.collider_poses);
    body_entries_.Begin(dt);
    problem = RunSubsteps(report.substeps, report.substep, poses);
    entries_.End(problem.empty());
    body_entries_.End(problem.empty());
    if (problem.empty() || !MayRefineSubsteps()) break;
    // The stable step holds for small motions about the rest shape; a lattice that buckles and
    // snaps under a deep press outruns it (docs/physics.md §7, "Deep presses"). From the step's
    // start, with half the substep, for good.
    RestoreStepStart(start);
    world_.substep_refinement *= 2;
    if (report.refined_because.empty()) report.refined_because = problem;
  }
  if (!problem.empty()) {
    // Finer substeps did not cure it (an absurd force, a kinematic group teleported): they
    // would only slow every later step.
    world_.substep_refinement = refinement_before;
    RejectStep(start, problem, &report);
    return report;
  }
  world_.stopped_after_failure = false;
  FinishStep(dt, start);
  report.microcollisions = world_.microcollisions;
  report.solver_iterations = world_.solver_iterations;
  return report;
}

void StepLoop::ClearStepRecords() {
  for (Body& body : world_.bodies) {
    body.impulses.assign(world_.colliders.size() + body.groups.size(), ImpulseSum{});
    body.contact_points.clear();  // keeps its capacity
  }
  world_.microcollisions = 0;
  world_.solver_iterations = 0;
  for (Body& body : world_.bodies) body.fastest_speed_sq = 0.0;
}

std::string StepLoop::RunSubsteps(int count, double h,
                                  const std::vector<Eigen::Isometry3d>& start_poses) {
  world_.substep = h;
  world_.substep_count = count;
  world_.drifted_ahead = false;
  world_.rounded_ahead = false;
  for (Body& body : world_.bodies) {
    if (body.model->num_nodes() > 0) body.float_origin = body.state.positions.col(0);
    // Cut at the contacts only where the one-pass substep's last share makes up for the cut
    // (internal::NodeStages::rounds_ahead): not in a Step's first substep's stages nor in
    // its last's contacts, so it takes several (a one-substep Step ran slower cut;
    // docs/design/threads-default.md).
    const bool cut = world_.options.cut_shares_at_contacts && explicit_.SubstepsInOnePass() &&
                     count >= ExplicitIntegrator::kSubstepsToCutAtContacts;
    contacts_.CutNodeSharesAtContacts(&body, cut);
  }
  for (int k = 0; k < count; ++k) {
    world_.substep_index = k;
    Substep(h, start_poses, k * h);
    std::string problem = CheckSane();
    if (!problem.empty()) return problem;
  }
  return {};
}

std::string StepLoop::CheckSane() const {
  for (const Body& body : world_.bodies) {
    const double speed = std::sqrt(body.fastest_speed_sq);
    if (!std::isfinite(speed)) {
      return "body '" + body.name + "': a node position or velocity became non-finite (node " +
             std::to_string(body.fastest_node) + ")";
    }
    if (speed > world_.options.max_speed) {
      std::ostringstream reason;
      reason << "body '" << body.name << "': node " << body.fastest_node << " would move at "
             << speed << " m/s, above the " << world_.options.max_speed
             << " m/s limit (an absurd force, or a diverging simulation)";
      return reason.str();
    }
  }
  return {};
}

void StepLoop::FinishStep(double dt, const StepStart& start) {
  world_.time = start.time + dt;
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    world_.colliders[c].pose = Advance(start.collider_poses[c], world_.colliders[c], dt);
  }
  for (Body& body : world_.bodies) {
    CountDownPushes(&body, dt);
    TurnImpulsesIntoWrenches(&body, dt);
  }
}

void StepLoop::Substep(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                       double step_time) {
  const double t0 = world_.time + step_time;  // time stays at the step's start until it ends
  if (explicit_.SubstepsInOnePass()) {
    PlaceCollidersAtMidSubstep(h, start_poses, step_time);      // 5's poses
    explicit_.SubstepInOnePass(&world_.bodies.front(), h, t0);  // 1-7
    return;
  }
  // The implicit kick holds the contacts it detects at mid-substep, as the contact stage does.
  if (world_.options.integrator == Integrator::kImplicit) {
    PlaceCollidersAtMidSubstep(h, start_poses, step_time);
  }
  KickBodies(h, t0);                           // 1-4
  ResolveContacts(h, start_poses, step_time);  // 5-6
  DriftBodies(h, t0);                          // 7
}

void StepLoop::KickBodies(double h, double t0) {
  const bool implicit = world_.options.integrator == Integrator::kImplicit;
  for (Body& body : world_.bodies) {
    if (implicit) {
      DriftHalf(&body, h, GroupPoses(body, t0 + 0.5 * h), 0, body.model->num_nodes());  // 1
      ApplyPendingRestitution(&body);                                                   // 2
      world_.solver_iterations += implicit_.Kick(&body, h, t0);                         // 3-4
    } else {
      explicit_.DriftForceAndKick(&body, h, t0);  // 1-4
    }
    DriveKinematicGroups(&body, world_.colliders.size(), h, t0);  // 4, the nodes a frame moves
  }
}

void StepLoop::DriftBodies(double h, double t0) {
  for (Body& body : world_.bodies) DriftHalfNotingFastest(&body, h, t0, world_.options.max_speed);
}

void StepLoop::ResolveContacts(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                               double step_time) {
  // Contacts at mid-substep positions, colliders at their mid-substep poses.
  PlaceCollidersAtMidSubstep(h, start_poses, step_time);
  for (Body& body : world_.bodies) contacts_.CollideWithColliders(&body, &world_.microcollisions);
  body_entries_.Place(step_time + 0.5 * h);  // the pairs see entering bodies where they enter
  pairs_.CollideNodes(&world_.microcollisions);
}

void StepLoop::PlaceCollidersAtMidSubstep(double h,
                                          const std::vector<Eigen::Isometry3d>& start_poses,
                                          double step_time) {
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    world_.colliders[c].pose = Advance(start_poses[c], world_.colliders[c], step_time + 0.5 * h);
  }
}

}  // namespace msm_sim::core::internal
