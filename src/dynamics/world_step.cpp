// World::Step and World::Substep: the integrator of world.h's class comment, stage by stage.
#include "msm_sim/dynamics/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "dynamics/world_contact_stage.h"
#include "dynamics/world_internal.h"
#include "mechanics/simd_clones.h"

namespace msm_sim::core {
namespace {

using internal::Finite;
using internal::Require;

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

// The per-node loops of the drifts and the kick, with AVX2 clones as the spring loops: compiled
// for baseline x86-64 alone they were a tenth of a substep.

// x += tau v over `count` coordinates.
MSM_SIM_SIMD_CLONES
void Drift(long count, double tau, const double* v, double* x) {
  const double* __restrict from = v;
  double* __restrict to = x;
  for (long j = 0; j < count; ++j) to[j] += tau * from[j];
}

// The same, first copying x and v into saved_x and saved_v: the step's first drift saves the
// state for a rejected step as it reads it, saving a pass over the nodes
// (docs/design/threads-default.md).
MSM_SIM_SIMD_CLONES
void SaveAndDrift(long count, double tau, const double* v, double* x, double* saved_v,
                  double* saved_x) {
  const double* __restrict from = v;
  double* __restrict to = x;
  double* __restrict v_copy = saved_v;
  double* __restrict x_copy = saved_x;
  for (long j = 0; j < count; ++j) {
    x_copy[j] = to[j];
    v_copy[j] = from[j];
    to[j] += tau * from[j];
  }
}

// The same as Drift, also returning the largest |velocity component| and x - x summed (0 while
// every x is finite, NaN once one is not; a NaN velocity makes x NaN too). kTwice: then Drift
// again with the same v, x = (x + tau v) + tau v in one pass, each sum rounded as two passes
// round it (the file is compiled without contraction), the extremes those of the first.
template <bool kTwice>
inline __attribute__((always_inline)) void DriftNoting(long count, double tau, const double* v,
                                                       double* x, double* fastest_component,
                                                       double* nonfinite) {
  const double* __restrict from = v;
  double* __restrict to = x;
  double fastest = 0.0, sum = 0.0;
#pragma omp simd reduction(max : fastest) reduction(+ : sum)
  for (long j = 0; j < count; ++j) {
    const double once = to[j] + tau * from[j];
    fastest = std::max(fastest, std::abs(from[j]));
    sum += once - once;
    to[j] = kTwice ? once + tau * from[j] : once;
  }
  *fastest_component = fastest;
  *nonfinite = sum;
}

MSM_SIM_SIMD_CLONES
void DriftNotingExtremes(long count, double tau, const double* v, double* x,
                         double* fastest_component, double* nonfinite) {
  DriftNoting<false>(count, tau, v, x, fastest_component, nonfinite);
}

MSM_SIM_SIMD_CLONES
void DriftTwiceNotingExtremes(long count, double tau, const double* v, double* x,
                              double* fastest_component, double* nonfinite) {
  DriftNoting<true>(count, tau, v, x, fastest_component, nonfinite);
}

// v += h f / m + h g for n nodes (3-vectors, column-major).
MSM_SIM_SIMD_CLONES
void KickNodes(int n, double h, const double* forces, const double* inverse_masses,
               const double g[3], double* velocities) {
  const double* __restrict f = forces;
  const double* __restrict inverse_mass = inverse_masses;
  double* __restrict v = velocities;
  const double hg[3] = {h * g[0], h * g[1], h * g[2]};
  for (int i = 0; i < n; ++i) {
    const double scale = h * inverse_mass[i];
    for (int d = 0; d < 3; ++d) v[3 * i + d] += scale * f[3 * i + d] + hg[d];
  }
}

// KickNodes for nodes [begin, end) with the forces as the single-precision loops leave them
// (ForceEvaluator::NodeStages::after_unstored: x, y, z blocks of the a ends, then of the b ends,
// `stride` floats apart): node i's force is the double sum of its a- and
// b-end floats, which StoreSingleEndForces would have stored for KickNodes to read back. The
// same arithmetic, without that round trip through memory.
MSM_SIM_SIMD_CLONES
void KickNodesFromEndForces(long stride, long begin, long end, double h, const float* end_forces,
                            const double* inverse_masses, const double g[3], double* velocities) {
  const float* __restrict a = end_forces;
  const float* __restrict b = end_forces + 3 * stride;
  const double* __restrict inverse_mass = inverse_masses;
  double* __restrict v = velocities;
  const double hg[3] = {h * g[0], h * g[1], h * g[2]};
  for (long i = begin; i < end; ++i) {
    const double scale = h * inverse_mass[i];
    for (long d = 0; d < 3; ++d) {
      const double f =
          static_cast<double>(a[d * stride + i]) + static_cast<double>(b[d * stride + i]);
      v[3 * i + d] += scale * f + hg[d];
    }
  }
}

// Equal substeps of dt no longer than the stable step (one if no body limits it).
int NumSubsteps(double dt, double stable) {
  const int substeps = std::isfinite(stable) ? static_cast<int>(std::ceil(dt / stable - 1e-9)) : 1;
  return std::max(substeps, 1);
}

}  // namespace

StepReport World::Step(double dt) {
  Require(dt > 0.0 && Finite(dt), "step must be finite and > 0");
  StepReport report;
  const StepStart start = SaveForRollback();
  const bool implicit = options_.integrator == Integrator::kImplicit;
  std::string problem;
  const int refinement_before = substep_refinement_;
  for (;;) {
    report.substeps = NumSubsteps(
        dt, implicit ? options_.implicit_max_substep : stable_time_step() / substep_refinement_);
    report.substep = dt / report.substeps;
    report.substep_refinement = substep_refinement_;
    ClearStepRecords();
    const std::vector<Eigen::Isometry3d> poses = BeginColliderEntries(dt, start.collider_poses);
    problem = RunSubsteps(report.substeps, report.substep, poses);
    EndColliderEntries(problem.empty());
    if (problem.empty() || !MayRefineSubsteps()) break;
    // The stable step holds for small motions about the rest shape; a lattice that buckles and
    // snaps under a deep press outruns it (docs/physics.md §7, "Deep presses"). From the step's
    // start, with half the substep, for good.
    RestoreStepStart(start);
    substep_refinement_ *= 2;
    if (report.refined_because.empty()) report.refined_because = problem;
  }
  if (!problem.empty()) {
    // Finer substeps did not cure it (an absurd force, a kinematic group teleported): they
    // would only slow every later step.
    substep_refinement_ = refinement_before;
    report.substep_refinement = substep_refinement_;
    // An absurd push is what usually makes a step fail; keeping it would fail every step.
    const bool dropped = RollBack(start);
    // Without a push to drop, the saved state itself diverges and every later step would fail
    // the same way (docs/robustness.md, "Long runs"): first the bodies stop where they are (a node
    // pushed to near max_speed whose springs then fling it past it); if they still diverge from
    // rest, their shape does (a lattice crushed beyond what its springs resolve), and they go
    // back to their rest shape.
    const char* recovery = "; the step's applied forces were dropped";
    if (!dropped && !stopped_after_failure_) {
      StopBodies();
      recovery = "; the bodies were stopped where they are";
    } else if (!dropped) {
      RestoreRestShapes();
      recovery = "; stopped, they still diverged: the bodies were put back in their rest shape";
    }
    stopped_after_failure_ = !dropped && !stopped_after_failure_;
    report.accepted = false;
    report.reason = problem + recovery;
    report.solver_iterations = solver_iterations_;
    return report;
  }
  stopped_after_failure_ = false;
  FinishStep(dt, start);
  report.microcollisions = microcollisions_;
  report.solver_iterations = solver_iterations_;
  return report;
}

World::StepStart World::SaveForRollback() {
  // The bodies save into buffers kept between steps: a fresh 300 kB allocation per step is an
  // mmap and page faults, a tenth of a 12k-node step.
  const bool explicit_drift = options_.integrator == Integrator::kExplicit;
  for (Body& body : bodies_) {
    body.saved_positions.resize(3, body.state.positions.cols());
    body.saved_velocities.resize(3, body.state.velocities.cols());
    // The explicit integrator's first drift copies the nodes as it reads them, on each node
    // share's thread (DriftForceAndKick); nothing before it changes them. (A step taken again
    // with finer substeps copies them again from the restored start, the same values.)
    // Each node share copies its own nodes on its own thread, as the stages that follow use
    // them (docs/physics.md §9): copied on the caller's thread, the other share's nodes left its
    // cache shared, and its first drift waited for them (docs/design/threads-default.md).
    if (!explicit_drift) {
      body.evaluator.ForEachNodeShare([&body](int, int begin, int end) {
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
  for (const Collider& collider : colliders_) start.collider_poses.push_back(collider.pose);
  start.time = time_;
  return start;
}

void World::ClearStepRecords() {
  for (Body& body : bodies_) {
    body.impulses.assign(colliders_.size() + body.groups.size(), ImpulseSum{});
    body.contact_points.clear();  // keeps its capacity
  }
  microcollisions_ = 0;
  solver_iterations_ = 0;
  for (Body& body : bodies_) body.fastest_speed_sq = 0.0;
}

std::string World::RunSubsteps(int count, double h,
                               const std::vector<Eigen::Isometry3d>& start_poses) {
  substep_ = h;
  substep_count_ = count;
  drifted_ahead_ = false;
  rounded_ahead_ = false;
  for (Body& body : bodies_) {
    if (body.model->num_nodes() > 0) body.float_origin = body.state.positions.col(0);
    // Cut at the contacts only where the one-pass substep's last share makes up for the cut
    // (ForceEvaluator::NodeStages::rounds_ahead): not in a Step's first substep's stages nor in
    // its last's contacts, so it takes several (a one-substep Step ran slower cut;
    // docs/design/threads-default.md).
    const bool cut =
        options_.cut_shares_at_contacts && SubstepsInOnePass() && count >= kSubstepsToCutAtContacts;
    CutNodeSharesAtContacts(&body, cut);
  }
  for (int k = 0; k < count; ++k) {
    substep_index_ = k;
    Substep(h, start_poses, k * h);
    std::string problem = CheckSane();
    if (!problem.empty()) return problem;
  }
  return {};
}

void World::StopBodies() {
  for (Body& body : bodies_) {
    body.state.velocities.setZero();
    body.pending.clear();
  }
}

void World::RestoreRestShapes() {
  for (Body& body : bodies_) {
    body.state = State::AtRest(*body.model);
    body.pending.clear();
    body.implicit_dv.resize(3, 0);
    body.sliding_friction.resize(3, 0);
    PlaceGroups(&body, time_);
  }
}

bool World::MayRefineSubsteps() const {
  // Without a finite stable step (free particles) the substep is the whole step either way.
  if (options_.integrator != Integrator::kExplicit ||
      substep_refinement_ >= options_.max_substep_refinement ||
      !std::isfinite(stable_time_step())) {
    return false;
  }
  // A push is what usually makes a step fail (an absurd force): RollBack drops it instead.
  return std::all_of(bodies_.begin(), bodies_.end(),
                     [](const Body& body) { return body.pushes.empty(); });
}

void World::RestoreStepStart(const StepStart& start) {
  for (Body& body : bodies_) {
    body.state.positions = body.saved_positions;
    body.state.velocities = body.saved_velocities;
    body.pending = body.saved_pending;
    body.implicit_dv = body.saved_implicit_dv;
    body.sliding_friction = body.saved_sliding_friction;
    body.contact_points.clear();
  }
  for (std::size_t c = 0; c < colliders_.size(); ++c) colliders_[c].pose = start.collider_poses[c];
  time_ = start.time;
}

bool World::RollBack(const StepStart& start) {
  RestoreStepStart(start);
  bool dropped = false;
  for (Body& body : bodies_) {
    dropped = dropped || !body.pushes.empty();
    body.pushes.clear();
  }
  return dropped;
}

void World::FinishStep(double dt, const StepStart& start) {
  time_ = start.time + dt;
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    colliders_[c].pose = Advance(start.collider_poses[c], colliders_[c], dt);
  }
  for (Body& body : bodies_) {
    CountDownPushes(&body, dt);
    TurnImpulsesIntoWrenches(&body, dt);
  }
}

void World::CountDownPushes(Body* body, double dt) {
  for (Push& push : body->pushes) push.remaining -= dt;
  body->pushes.erase(std::remove_if(body->pushes.begin(), body->pushes.end(),
                                    [](const Push& push) { return push.remaining <= 1e-12; }),
                     body->pushes.end());
}

void World::TurnImpulsesIntoWrenches(Body* body, double dt) {
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

std::string World::CheckSane() const {
  for (const Body& body : bodies_) {
    const double speed = std::sqrt(body.fastest_speed_sq);
    if (!std::isfinite(speed)) {
      return "body '" + body.name + "': a node position or velocity became non-finite (node " +
             std::to_string(body.fastest_node) + ")";
    }
    if (speed > options_.max_speed) {
      std::ostringstream reason;
      reason << "body '" << body.name << "': node " << body.fastest_node << " would move at "
             << speed << " m/s, above the " << options_.max_speed
             << " m/s limit (an absurd force, or a diverging simulation)";
      return reason.str();
    }
  }
  return {};
}

void World::Substep(double h, const std::vector<Eigen::Isometry3d>& start_poses, double step_time) {
  const double t0 = time_ + step_time;  // time_ stays at the step's start until it ends
  // The implicit kick holds the contacts it detects at mid-substep, as the contact stage does.
  const bool implicit = options_.integrator == Integrator::kImplicit;
  if (SubstepsInOnePass()) {
    SubstepInOnePass(&bodies_.front(), h, start_poses, step_time);  // 1-7
    return;
  }
  if (implicit) PlaceCollidersAtMidSubstep(h, start_poses, step_time);
  for (Body& body : bodies_) {
    if (implicit) {
      DriftHalf(&body, h, GroupPoses(body, t0 + 0.5 * h), 0, body.model->num_nodes());  // 1
      ApplyPendingRestitution(&body);                                                   // 2
      solver_iterations_ += ImplicitKick(&body, h, t0);  // 3-4 (world_implicit.cpp)
    } else {
      DriftForceAndKick(&body, h, t0);  // 1-4
    }
    DriveKinematicGroups(&body, h, t0);  // 4, for the nodes a frame dictates
  }
  ResolveContacts(h, start_poses, step_time);                       // 5-6
  for (Body& body : bodies_) DriftHalfNotingFastest(&body, h, t0);  // 7
}

bool World::SubstepsInOnePass() const {
  if (options_.integrator != Integrator::kExplicit || bodies_.size() != 1) return false;
  const Body& body = bodies_.front();
  return body.groups.empty() && !body.options.self_collision;
}

void World::SubstepInOnePass(Body* body, double h,
                             const std::vector<Eigen::Isometry3d>& start_poses, double step_time) {
  const double t0 = time_ + step_time;
  PlaceCollidersAtMidSubstep(h, start_poses, step_time);  // 5's poses
  const bool contacts = !colliders_.empty();
  ContactStage stage;
  if (contacts) stage = BeginContactStage(body);
  std::vector<double> fastest(body->evaluator.NumNodeShares()), nonfinite(fastest.size());
  // The first share's rebounds wait in next_pending while the shares still apply `pending`.
  body->next_pending.clear();
  // Within a Step, the next substep's stages 1-2 come with this one's last drift, and its float
  // loops' rounding with them (one pass over the nodes and one hand-over fewer). Nothing between
  // the two substeps moves a node: the sanity check reads the drift's flags (a flagged substep's
  // NoteFastest sees the rebounds applied), and a rejected step restores its start.
  const bool drifted = drifted_ahead_, rounded = rounded_ahead_;
  drifted_ahead_ = substep_index_ + 1 < substep_count_;
  rounded_ahead_ = drifted_ahead_ && body->evaluator.RoundsNodes();
  const Eigen::Matrix3Xd* dampers =
      body->options.damping_beta != 0.0 ? &body->state.velocities : nullptr;
  const std::function<void(int, int, int)> finish = [&](int share, int begin, int end) {
    if (contacts) CollideShare(&stage, body, share, begin, end, &body->next_pending);  // 5-6
    DriftShare(body, h, drifted_ahead_, share, begin, end, &fastest, &nonfinite);      // 7 (, 1)
    if (!drifted_ahead_) return;
    if (contacts) {  // the next 2: the rebounds this share's contacts left, on its own nodes
      ApplyPendingRestitution(
          body, share == 0 ? body->next_pending : body->share_records[share - 1].pending, begin,
          end);
    }
    if (rounded_ahead_) {
      body->evaluator.RoundNodes(body->state.positions, dampers, begin, end,
                                 body->float_origin.data());
    }
  };
  DriftForceAndKick(body, h, t0, &finish, drifted, rounded, rounded_ahead_);  // 1-4, `finish`
  body->pending.swap(body->next_pending);  // `pending` was cleared
  if (contacts) EndContactStage(stage, body, &microcollisions_);
  if (drifted_ahead_) body->pending.clear();  // applied
  NoteDriftExtremes(body, fastest, nonfinite, t0 + h);
}

void World::NoteFastest(Body* body) {
  const Eigen::Matrix3Xd& x = body->state.positions;
  const Eigen::Matrix3Xd& v = body->state.velocities;
  for (int i = 0; i < body->model->num_nodes(); ++i) {
    const double speed_sq = v.col(i).squaredNorm();
    const bool finite = std::isfinite(speed_sq) && x.col(i).allFinite();
    const double fastest = finite ? speed_sq : std::numeric_limits<double>::infinity();
    if (fastest > body->fastest_speed_sq) {
      body->fastest_speed_sq = fastest;
      body->fastest_node = i;
    }
  }
}

void World::DriftHalf(Body* body, double h, const std::vector<Eigen::Isometry3d>& poses, int begin,
                      int end, bool save) {
  const long count = 3L * (end - begin);
  const double* v = body->state.velocities.data() + 3L * begin;
  double* x = body->state.positions.data() + 3L * begin;
  if (save) {
    SaveAndDrift(count, 0.5 * h, v, x, body->saved_velocities.data() + 3L * begin,
                 body->saved_positions.data() + 3L * begin);
  } else {
    Drift(count, 0.5 * h, v, x);
  }
  PlaceGroupNodes(body, poses, begin, end);
}

void World::ApplyPendingRestitution(Body* body) {
  ApplyPendingRestitution(body, body->pending, 0, body->model->num_nodes());
  body->pending.clear();
}

void World::ApplyPendingRestitution(Body* body, const std::vector<PendingResponse>& rebounds,
                                    int begin, int end) {
  for (const PendingResponse& response : rebounds) {
    if (response.node >= begin && response.node < end) {
      body->state.velocities.col(response.node) += response.delta_v;
    }
  }
}

void World::ComputeForces(Body* body) {
  body->evaluator.SetForces(body->state.positions, body->state.velocities,
                            body->options.damping_beta, &body->forces);
  AddPushes(body, 0, body->model->num_nodes());
}

void World::AddPushes(Body* body, int begin, int end) {
  for (const Push& push : body->pushes) {
    for (std::size_t k = 0; k < push.nodes.size(); ++k) {
      const NodeIndex node = push.nodes[k];
      if (node >= begin && node < end) body->forces.col(node) += push.forces[k];
    }
  }
}

void World::Kick(Body* body, double h, int begin, int end) const {
  // Gravity comes in the same pass over the nodes: this loop and the drifts are a third of a
  // 12k-node step besides the force evaluation.
  KickNodes(end - begin, h, body->forces.data() + 3L * begin, body->inverse_masses.data() + begin,
            options_.gravity.data(), body->state.velocities.data() + 3L * begin);
}

void World::DriftForceAndKick(Body* body, double h, double t0,
                              const std::function<void(int, int, int)>* finish, bool drifted,
                              bool rounded, bool rounds_ahead) {
  // Each node share of the force loops drifts, kicks and places its own nodes on its own thread
  // (ForceEvaluator::NodeStages): they stay in that core's cache, and with two threads the
  // per-node stages no longer wait on one core (docs/physics.md §9).
  // The frames' poses here, on the caller's thread: a pose function need not be thread-safe.
  const std::vector<Eigen::Isometry3d> poses = GroupPoses(*body, t0 + 0.5 * h);
  ForceEvaluator::NodeStages stages;
  stages.origin = body->float_origin.data();
  stages.rounded = rounded && body->evaluator.RoundsNodes();
  stages.rounds_ahead = rounds_ahead;
  const bool save = substep_index_ == 0;  // SaveForRollback's copy of the nodes
  stages.before = [body, h, &poses, save, drifted](int, int begin, int end) {
    if (drifted) return;                                       // 1-2 taken ahead
    DriftHalf(body, h, poses, begin, end, save);               // 1
    ApplyPendingRestitution(body, body->pending, begin, end);  // 2
  };
  stages.after = [this, body, h, finish](int share, int begin, int end) {
    AddPushes(body, begin, end);  // 3, with the springs' and dampers' forces
    Kick(body, h, begin, end);    // 4
    if (finish != nullptr) (*finish)(share, begin, end);
  };
  if (body->pushes.empty()) {
    // Without pushes the kick takes the springs' forces as the float loops leave them (body->
    // forces is not written): the same sums, one pass over the nodes instead of two.
    stages.after_unstored = [this, body, h, finish](int share, int begin, int end,
                                                    const float* end_forces, long stride) {
      KickNodesFromEndForces(stride, begin, end, h, end_forces, body->inverse_masses.data(),
                             options_.gravity.data(), body->state.velocities.data());  // 3-4
      if (finish != nullptr) (*finish)(share, begin, end);
    };
  }
  body->evaluator.SetForces(body->state.positions, body->state.velocities,
                            body->options.damping_beta, &body->forces, stages);
  body->pending.clear();
}

void World::DriveKinematicGroups(Body* body, double h, double t0) const {
  const Eigen::VectorXd& m = body->model->masses();
  for (std::size_t g = 0; g < body->groups.size(); ++g) {
    const Group& group = body->groups[g];
    const Eigen::Isometry3d from = GroupPose(group, t0);
    const Eigen::Isometry3d to = GroupPose(group, t0 + h);
    const Eigen::Isometry3d mid = GroupPose(group, t0 + 0.5 * h);
    ImpulseSum& reaction = body->impulses[colliders_.size() + g];
    for (std::size_t k = 0; k < group.spec.nodes.size(); ++k) {
      const NodeIndex node = group.spec.nodes[k];
      const Eigen::Vector3d local = group.local.col(k);
      const Eigen::Vector3d prescribed = (to * local - from * local) / h;
      // The group gave the node m (v_prescribed - v_free); the node pushed back.
      const Eigen::Vector3d on_group =
          -m[node] * (prescribed - Eigen::Vector3d(body->state.velocities.col(node)));
      reaction.Add(body->state.positions.col(node), mid.translation(), on_group);
      body->state.velocities.col(node) = prescribed;
    }
  }
}

void World::ResolveContacts(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                            double step_time) {
  // Contacts at mid-substep positions, colliders at their mid-substep poses.
  PlaceCollidersAtMidSubstep(h, start_poses, step_time);
  for (Body& body : bodies_) CollideWithColliders(&body, &microcollisions_);
  CollideNodes(&microcollisions_);
}

void World::PlaceCollidersAtMidSubstep(double h, const std::vector<Eigen::Isometry3d>& start_poses,
                                       double step_time) {
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    colliders_[c].pose = Advance(start_poses[c], colliders_[c], step_time + 0.5 * h);
  }
}

void World::DriftHalfNotingFastest(Body* body, double h, double t0) const {
  // The drift also flags what the sanity check after the substep must look at: a velocity
  // component above max_speed / sqrt(3) (every node faster than max_speed has one) and any
  // non-finite value. One flat loop of reductions vectorises (tracking the fastest node in it
  // would not; docs/design/speed-against-bullet.md); the rare flagged substep finds the node in a
  // second pass.
  // Each node share on its own thread, as in DriftForceAndKick.
  std::vector<double> fastest(body->evaluator.NumNodeShares()), nonfinite(fastest.size());
  body->evaluator.ForEachNodeShare([&](int share, int begin, int end) {
    DriftShare(body, h, false, share, begin, end, &fastest, &nonfinite);
  });
  NoteDriftExtremes(body, fastest, nonfinite, t0 + h);
}

void World::DriftShare(Body* body, double h, bool twice, int share, int begin, int end,
                       std::vector<double>* fastest, std::vector<double>* nonfinite) {
  const auto drift = twice ? DriftTwiceNotingExtremes : DriftNotingExtremes;
  drift(3L * (end - begin), 0.5 * h, body->state.velocities.data() + 3L * begin,
        body->state.positions.data() + 3L * begin, &(*fastest)[share], &(*nonfinite)[share]);
}

void World::NoteDriftExtremes(Body* body, const std::vector<double>& fastest,
                              const std::vector<double>& nonfinite, double t) const {
  const double component_limit = options_.max_speed / std::sqrt(3.0);
  for (std::size_t share = 0; share < fastest.size(); ++share) {
    if (!(fastest[share] <= component_limit) || nonfinite[share] != 0.0) {
      NoteFastest(body);
      break;
    }
  }
  PlaceGroups(body, t);
}

}  // namespace msm_sim::core
