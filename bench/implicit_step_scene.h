#pragma once
// The real-time block of `msm_lab realtime` (realtime_experiment.cpp) built on the World's private
// state, so that implicit_step_benchmark.cpp can time the implicit step's parts one by one at the
// state a real run reaches, and census its contact re-solves by mirroring SolveKick.
#include <algorithm>
#include <ctime>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "dynamics/implicit_integrator.h"
#include "dynamics/node_stages.h"
#include "dynamics/step_loop.h"
#include "dynamics/world_state.h"
#include "experiments/indenter.h"
#include "mechanics/node_array_krylov.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core::bench {

/// The calling thread's CPU time (s): every part runs on one thread, and the machine is shared
/// (wall time would count other processes' turns on the core).
struct Clock {
  static double now() {
    timespec time;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &time);
    return static_cast<double>(time.tv_sec) + 1e-9 * static_cast<double>(time.tv_nsec);
  }
};

inline double SecondsSince(double start) { return Clock::now() - start; }

// Solves of one kick at most, as the integrator's kImplicitContactPasses.
constexpr int kContactSolvesAtMost = 4;

/// One of the cases: Poisson's ratio and node spacing (m).
struct BlockCase {
  double poisson;
  double spacing;
};

/// The 10 x 10 x 5 cm block (E 200 kPa, rho 1100), built once per case.
inline std::shared_ptr<const Model> RealtimeBlock(const BlockCase& block_case) {
  CubicLatticeOptions lattice;
  lattice.size = Eigen::Vector3d(0.1, 0.1, 0.05);
  lattice.lattice.spacing = block_case.spacing;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, block_case.poisson, 1100.0), lattice));
}

/// RunRealtimeExperiment's scene (defaults: dampers beta 1e-4 s, friction 0.5, gravity, a 1 cm
/// sphere pressing at 1 cm/s from first touch, one thread, the World's default float springs)
/// with the World's step loop over its private state.
class RealtimeScene {
 public:
  static constexpr double kStep = 1e-3;  // s, World::Step's dt (one implicit substep)

  RealtimeScene(std::shared_ptr<const Model> model, Integrator integrator)
      : world_(Options(integrator)) {
    BodyOptions body_options;
    body_options.damping_beta = 1e-4;
    body_options.friction = 0.5;
    world_.bodies.emplace_back("block", model, body_options, world_.options);
    internal::Body& block = world_.bodies.back();
    Collider ground = GroundTouching(model->rest_positions(), block.border, 0.5);
    Collider sphere = SphereIndenter(*model, block.border, 0.01, 0.0, 0.01);
    sphere.friction = 0.5;
    for (const Collider& collider : {ground, sphere}) {
      world_.colliders.push_back(collider);
      block.pair_friction.push_back(-1.0);
      block.wrenches.emplace_back();
    }
    loop_ = std::make_unique<internal::StepLoop>(&world_);
  }
  RealtimeScene(const RealtimeScene&) = delete;
  RealtimeScene& operator=(const RealtimeScene&) = delete;

  StepReport Step() { return loop_->Step(kStep); }
  internal::WorldState& world() { return world_; }
  internal::Body& block() { return world_.bodies.front(); }

 private:
  static WorldOptions Options(Integrator integrator) {
    WorldOptions options;
    options.integrator = integrator;
    options.implicit_max_substep = kStep;
    options.threads = 1;
    return options;
  }

  internal::WorldState world_;
  std::unique_ptr<internal::StepLoop> loop_;
};

/// What one implicit kick did, by a mirror of ImplicitIntegrator::Kick and SolveKick (same
/// calls, same order) that also counts the solves and times its phases (s).
struct KickCensus {
  int touching = 0;     // contacts held from the start
  int speculative = 0;  // contacts that may be held later
  int held_at_end = 0;
  int solves = 0;  // masked PCG solves: 1 + the contact re-solves
  int iterations = 0;
  double forces_seconds = 0.0;     // ComputeForces and gravity
  double linearize_seconds = 0.0;  // Linearize, StiffnessDiagonal's preconditioner
  double contacts_seconds = 0.0;   // DeepestColliderContacts and the holds' updates
  double solve_seconds = 0.0;      // SolveMaskedPcg, all solves
};

/// 1 on the free nodes' DOFs, as the integrator's FreeDofMask.
inline Eigen::Matrix3Xd FreeDofs(const internal::Body& body) {
  Eigen::Matrix3Xd free(3, body.model->num_nodes());
  for (Eigen::Index i = 0; i < free.cols(); ++i) {
    free.col(i).setConstant(body.constrained[i] ? 0.0 : 1.0);
  }
  return free;
}

/// 1 / (m + c max(diag K, 0)), as the integrator's InverseSystemDiagonal.
inline Eigen::Matrix3Xd InverseSystemDiagonal(const internal::Body& body, double c) {
  Eigen::Matrix3Xd diagonal = c * body.evaluator.StiffnessDiagonal().cwiseMax(0.0);
  diagonal.rowwise() += body.model->masses().transpose();
  return diagonal.cwiseInverse();
}

/// The operator of the implicit solve, (M + c K) x, as SolveKick builds it.
inline NodeArrayOperator SystemOperator(const internal::Body& body, double c,
                                        Eigen::Matrix3Xd* stiffness_product) {
  const Eigen::VectorXd& m = body.model->masses();
  return [&body, &m, c, stiffness_product](const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* out) {
    body.evaluator.ApplyStiffness(x, stiffness_product);
    *out = c * *stiffness_product;
    *out += x * m.asDiagonal();
  };
}

/// c = h^2 / 2 + h beta of the kick.
inline double SystemStiffnessWeight(const internal::Body& body, double h) {
  return 0.5 * h * h + h * body.options.damping_beta;
}

// The implicit scene's state at the next kick's start (after stages 1-2, colliders at
// mid-substep), a copy the parts may change: Restore() puts it back.
/// (A copy of a warm implicit scene's world.)
class KickState {
 public:
  explicit KickState(const internal::WorldState& warm) : world(warm) {
    internal::Body& body = world.bodies.front();
    const double h = RealtimeScene::kStep;
    for (Collider& collider : world.colliders) {
      collider.pose.translation() += 0.5 * h * collider.linear_velocity;
    }
    internal::DriftHalf(&body, h, {}, 0, body.model->num_nodes());
    internal::ApplyPendingRestitution(&body);
    body.impulses.assign(world.colliders.size(), internal::ImpulseSum{});
    saved_state = body.state;
    saved_dv = body.implicit_dv;
    saved_sliding = body.sliding_friction;
    saved_impulses = body.impulses;
    saved_pending = body.pending;
  }
  internal::Body& body() { return world.bodies.front(); }
  void Restore() {
    internal::Body& body = world.bodies.front();
    body.state = saved_state;
    body.implicit_dv = saved_dv;
    body.sliding_friction = saved_sliding;
    body.impulses = saved_impulses;
    body.pending = saved_pending;
  }

  internal::WorldState world;

 private:
  State saved_state;
  Eigen::Matrix3Xd saved_dv, saved_sliding;
  std::vector<internal::ImpulseSum> saved_impulses;
  std::vector<internal::PendingResponse> saved_pending;
};

// What a census leaves for the hold benchmarks: the contacts and the last solve.
struct CensusEnd {
  std::vector<internal::ContactNormal> held, speculative;
  Eigen::Matrix3Xd residual, dv;
};

// Partitions the deepest contacts as Kick does: held from the start, or speculative.
inline void SplitContacts(const internal::Body& body, std::vector<internal::ContactNormal>* held,
                          std::vector<internal::ContactNormal>* speculative) {
  const Eigen::Matrix3Xd& v = body.state.velocities;
  const auto touching =
      std::stable_partition(held->begin(), held->end(), [&v](const internal::ContactNormal& c) {
        return c.closing_speed == 0.0 ||
               (c.velocity - v.col(c.node)).dot(c.normal) > c.holding_speed;
      });
  speculative->assign(touching, held->end());
  held->erase(touching, held->end());
}

// The solves of SolveKick, timed and counted, from the right-hand side b on.
inline void CensusSolves(internal::Body& body, const Eigen::Matrix3Xd& b, double c, double h,
                         const Eigen::Matrix3Xd& inverse_diagonal, const WorldOptions& options,
                         KickCensus* census, CensusEnd* end) {
  using internal::ImplicitIntegrator;
  const Eigen::Matrix3Xd& v = body.state.velocities;
  Eigen::Matrix3Xd stiffness_product(3, body.model->num_nodes());
  const NodeArrayOperator apply = SystemOperator(body, c, &stiffness_product);
  DofProjection projection;
  const MaskedPcgOptions solver =
      ImplicitIntegrator::SolverOptions(options, body, h, FreeDofs(body));
  Eigen::Matrix3Xd& dv = body.implicit_dv;
  for (int pass = 0; pass < kContactSolvesAtMost; ++pass) {
    auto start = Clock::now();
    projection.free = FreeDofs(body);
    ImplicitIntegrator::HoldContacts(v, end->held, &projection, &dv);
    projection.Apply(&dv);
    ImplicitIntegrator::HoldContacts(v, end->held, nullptr, &dv);
    Eigen::Matrix3Xd b_pass = b;
    for (const internal::ContactNormal& contact : end->held) {
      if (contact.friction_hold == internal::FrictionHold::kSliding)
        b_pass.col(contact.node) += contact.sliding_impulse;
    }
    census->contacts_seconds += SecondsSince(start);
    start = Clock::now();
    census->iterations +=
        SolveMaskedPcg(apply, b_pass, projection, inverse_diagonal, solver, &dv, &end->residual)
            .iterations;
    census->solve_seconds += SecondsSince(start);
    ++census->solves;
    start = Clock::now();
    bool changed = ImplicitIntegrator::ReleasePullingContacts(end->residual, &end->held);
    if (pass + 1 < kContactSolvesAtMost) {
      changed |= ImplicitIntegrator::UpdateFrictionHolds(v, dv, end->residual, &end->held);
      changed |= ImplicitIntegrator::HoldReachingContacts(v, dv, &end->speculative, &end->held);
    }
    census->contacts_seconds += SecondsSince(start);
    if (!changed) break;
  }
  end->dv = dv;
}

// A mirror of ImplicitIntegrator::Kick up to its velocity update (the scene has no kinematic
// groups, so no prescribed velocities), from the kick state as it is.
inline KickCensus CensusKick(KickState* kick, CensusEnd* end) {
  internal::Body& body = kick->body();
  internal::WorldState& world = kick->world;
  const double h = RealtimeScene::kStep;
  KickCensus census;
  auto start = Clock::now();
  internal::ComputeForces(&body);
  body.forces += world.options.gravity * body.model->masses().transpose();
  census.forces_seconds = SecondsSince(start);
  start = Clock::now();
  body.evaluator.Linearize(body.state.positions, GeometricStiffness::kDropCompression);
  const double c = SystemStiffnessWeight(body, h);
  const Eigen::Matrix3Xd inverse_diagonal = InverseSystemDiagonal(body, c);
  Eigen::Matrix3Xd stiffness_product(3, body.model->num_nodes());
  body.evaluator.ApplyStiffness(body.state.velocities, &stiffness_product);
  const Eigen::Matrix3Xd b = h * body.forces - (0.5 * h * h) * stiffness_product;
  census.linearize_seconds = SecondsSince(start);
  start = Clock::now();
  internal::ColliderContacts contacts(&world);
  const internal::ImplicitIntegrator integrator(&world, &contacts);
  end->held = integrator.DeepestColliderContacts(body, h);
  SplitContacts(body, &end->held, &end->speculative);
  census.touching = static_cast<int>(end->held.size());
  census.speculative = static_cast<int>(end->speculative.size());
  census.contacts_seconds = SecondsSince(start);
  CensusSolves(body, b, c, h, inverse_diagonal, world.options, &census, end);
  census.held_at_end = static_cast<int>(end->held.size());
  return census;
}

}  // namespace msm_sim::core::bench
