// The rollback of a failed Step and the bookkeeping at the end of an accepted one (step_loop.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "dynamics/node_stages.h"
#include "dynamics/step_loop.h"
#include "mechanics/node_shares.h"

namespace msm_sim::core::internal {

StepStart StepLoop::SaveForRollback() {
  // The bodies save into buffers kept between steps: a fresh 300 kB allocation per step is an
  // mmap and page faults, a tenth of a 12k-node step.
  const bool explicit_drift = world_.options.integrator == Integrator::kExplicit;
  for (Body& body : world_.bodies) {
    body.saved_positions.resize(3, body.state.positions.cols());
    body.saved_velocities.resize(3, body.state.velocities.cols());
    // The explicit integrator's first drift copies the nodes as it reads them, on each node
    // share's thread (DriftForceAndKick); nothing before it changes them. (A step taken again
    // with finer substeps copies them again from the restored start, the same values.)
    // Each node share copies its own nodes on its own thread, as the stages that follow use
    // them (docs/physics.md §9): copied on the caller's thread, the other share's nodes left its
    // cache shared, and its first drift waited for them (docs/design/threads-default.md).
    if (!explicit_drift) {
      internal::NodeShares::ForEach(&body.evaluator, [&body](int, int begin, int end) {
        body.saved_positions.middleCols(begin, end - begin) =
            body.state.positions.middleCols(begin, end - begin);
        body.saved_velocities.middleCols(begin, end - begin) =
            body.state.velocities.middleCols(begin, end - begin);
      });
    }
    body.saved_pending = body.pending;
    body.saved_implicit_dv = body.implicit_dv;  // empty for the explicit integrator
    body.saved_sliding_friction = body.sliding_friction;
  }
  StepStart start;
  for (const Collider& collider : world_.colliders) start.collider_poses.push_back(collider.pose);
  start.time = world_.time;
  return start;
}

bool StepLoop::RollBack(const StepStart& start) {
  RestoreStepStart(start);
  bool dropped = false;
  for (Body& body : world_.bodies) {
    dropped = dropped || !body.pushes.empty();
    body.pushes.clear();
  }
  return dropped;
}

void StepLoop::RestoreStepStart(const StepStart& start) {
  for (Body& body : world_.bodies) {
    body.state.positions = body.saved_positions;
    body.state.velocities = body.saved_velocities;
    body.pending = body.saved_pending;
    body.implicit_dv = body.saved_implicit_dv;
    body.sliding_friction = body.saved_sliding_friction;
    body.contact_points.clear();
  }
  for (std::size_t c = 0; c < world_.colliders.size(); ++c)
    world_.colliders[c].pose = start.collider_poses[c];
  world_.time = start.time;
}

bool StepLoop::MayRefineSubsteps() const {
  // Without a finite stable step (free particles) the substep is the whole step either way.
  if (world_.options.integrator != Integrator::kExplicit ||
      world_.substep_refinement >= world_.options.max_substep_refinement ||
      !std::isfinite(world_.StableTimeStep())) {
    return false;
  }
  // A push is what usually makes a step fail (an absurd force): RollBack drops it instead.
  return std::all_of(world_.bodies.begin(), world_.bodies.end(),
                     [](const Body& body) { return body.pushes.empty(); });
}

void StepLoop::StopBodies() {
  for (Body& body : world_.bodies) {
    body.state.velocities.setZero();
    body.pending.clear();
  }
}

void StepLoop::RestoreRestShapes() {
  for (Body& body : world_.bodies) {
    body.state = State::AtRest(*body.model);
    body.pending.clear();
    body.implicit_dv.resize(3, 0);
    body.sliding_friction.resize(3, 0);
    PlaceGroups(&body, world_.time);
  }
}

void StepLoop::CountDownPushes(Body* body, double dt) {
  for (Push& push : body->pushes) push.remaining -= dt;
  body->pushes.erase(std::remove_if(body->pushes.begin(), body->pushes.end(),
                                    [](const Push& push) { return push.remaining <= 1e-12; }),
                     body->pushes.end());
}

void StepLoop::TurnImpulsesIntoWrenches(Body* body, double dt) {
  body->wrenches.resize(body->impulses.size());
  for (std::size_t w = 0; w < body->impulses.size(); ++w) {
    const ImpulseSum& sum = body->impulses[w];
    ContactWrench& wrench = body->wrenches[w];
    wrench.force = sum.impulse / dt;
    wrench.torque = sum.moment / dt;
    wrench.centroid = sum.weight > 0.0 ? Eigen::Vector3d(sum.weighted_point / sum.weight)
                                       : Eigen::Vector3d::Zero();
    wrench.microcollisions = sum.count;
    wrench.normal = sum.normal_impulse > 0.0 ? Eigen::Vector3d(sum.normal_impulses.normalized())
                                             : Eigen::Vector3d::Zero();
    wrench.normal_force = sum.normal_impulse / dt;
    wrench.area = sum.area_time / dt;
    wrench.mean_pressure = sum.area_time > 0.0 ? sum.normal_impulse / sum.area_time : 0.0;
  }
}

void StepLoop::RejectStep(const StepStart& start, const std::string& problem, StepReport* report) {
  report->substep_refinement = world_.substep_refinement;
  // An absurd push is what usually makes a step fail; keeping it would fail every step.
  const bool dropped = RollBack(start);
  // Without a push to drop, the saved state itself diverges and every later step would fail
  // the same way (docs/robustness.md, "Long runs"): first the bodies stop where they are (a node
  // pushed to near max_speed whose springs then fling it past it); if they still diverge from
  // rest, their shape does (a lattice crushed beyond what its springs resolve), and they go
  // back to their rest shape.
  const char* recovery = "; the step's applied forces were dropped";
  if (!dropped && !world_.stopped_after_failure) {
    StopBodies();
    recovery = "; the bodies were stopped where they are";
  } else if (!dropped) {
    RestoreRestShapes();
    recovery = "; stopped, they still diverged: the bodies were put back in their rest shape";
  }
  world_.stopped_after_failure = !dropped && !world_.stopped_after_failure;
  report->accepted = false;
  report->reason = problem + recovery;
  report->solver_iterations = world_.solver_iterations;
}

}  // namespace msm_sim::core::internal
