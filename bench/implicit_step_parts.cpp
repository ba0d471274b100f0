// The implicit step's parts, each timed on its own on the warm implicit scene's kick state
// (implicit_step_benchmark.cpp explains them and registers them): forces, linearisation,
// preconditioner, stiffness products, the solve's own work, contacts and drifts.
#include <algorithm>
#include <vector>

#include <benchmark/benchmark.h>

#include "dynamics/node_stages.h"
#include "implicit_step_timing.h"

namespace msm_sim::core::bench {

void ComputeForcesPart(benchmark::State& state, const BlockCase& block_case) {
  KickState& kick = WarmKickState(block_case);
  TimeEach(
      state, block_case, [] {}, [&] { internal::ComputeForces(&kick.body()); });
}

void LinearizePart(benchmark::State& state, const BlockCase& block_case) {
  internal::Body& body = WarmKickState(block_case).body();
  TimeEach(
      state, block_case, [] {},
      [&] {
        body.evaluator.Linearize(body.state.positions, GeometricStiffness::kDropCompression);
      });
}

void StiffnessDiagonalPart(benchmark::State& state, const BlockCase& block_case) {
  internal::Body& body = WarmKickState(block_case).body();
  body.evaluator.Linearize(body.state.positions, GeometricStiffness::kDropCompression);
  const double c = SystemStiffnessWeight(body, RealtimeScene::kStep);
  TimeEach(
      state, block_case, [] {},
      [&] {
        Eigen::Matrix3Xd inverse = InverseSystemDiagonal(body, c);
        benchmark::DoNotOptimize(inverse.data());
      });
}

namespace {

// One product K x, x the body's velocities, in the evaluator's float or in double.
void ApplyStiffnessPart(benchmark::State& state, const BlockCase& block_case,
                        SpringPrecision precision) {
  internal::Body& body = WarmKickState(block_case).body();
  ForceEvaluator evaluator = body.evaluator;
  evaluator.set_precision(precision);
  evaluator.Linearize(body.state.positions, GeometricStiffness::kDropCompression);
  Eigen::Matrix3Xd product(3, body.model->num_nodes());
  TimeEach(
      state, block_case, [] {}, [&] { evaluator.ApplyStiffness(body.state.velocities, &product); });
}

}  // namespace

void ApplyStiffnessFloat(benchmark::State& state, const BlockCase& block_case) {
  ApplyStiffnessPart(state, block_case, SpringPrecision::kSingle);
}

void ApplyStiffnessDouble(benchmark::State& state, const BlockCase& block_case) {
  ApplyStiffnessPart(state, block_case, SpringPrecision::kDouble);
}

void OperatorWrap(benchmark::State& state, const BlockCase& block_case) {
  internal::Body& body = WarmKickState(block_case).body();
  const Eigen::VectorXd& m = body.model->masses();
  const double c = SystemStiffnessWeight(body, RealtimeScene::kStep);
  const Eigen::Matrix3Xd stiffness_product = body.state.velocities;
  const NodeArrayOperator wrap = [&](const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* out) {
    *out = c * stiffness_product;
    *out += x * m.asDiagonal();
  };
  Eigen::Matrix3Xd out(3, body.model->num_nodes());
  TimeEach(
      state, block_case, [] {}, [&] { wrap(body.state.velocities, &out); });
}

// One masked-PCG iteration without its product: a solve of a diagonal system (the kick's
// preconditioner, its inverse scaled by 0.5-2 at random so that CG does not converge at once)
// with the kick's projection (the free DOFs and the touching contacts' normals), its time less
// that of its diagonal products, per iteration.
void PcgIterationWork(benchmark::State& state, const BlockCase& block_case) {
  KickState& kick = WarmKickState(block_case);
  internal::Body& body = kick.body();
  body.evaluator.Linearize(body.state.positions, GeometricStiffness::kDropCompression);
  const double h = RealtimeScene::kStep;
  const Eigen::Matrix3Xd inverse_diagonal =
      InverseSystemDiagonal(body, SystemStiffnessWeight(body, h));
  const Eigen::Index n = body.model->num_nodes();
  const Eigen::Matrix3Xd diagonal = inverse_diagonal.cwiseInverse().cwiseProduct(
      (Eigen::Matrix3Xd::Random(3, n).array() * 0.75 + 1.25).matrix());
  const NodeArrayOperator apply = [&](const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* out) {
    *out = x.cwiseProduct(diagonal);
  };
  internal::ColliderContacts contacts(&kick.world);
  const internal::ImplicitIntegrator integrator(&kick.world, &contacts);
  std::vector<internal::ContactNormal> held = integrator.DeepestColliderContacts(body, h);
  std::vector<internal::ContactNormal> speculative;
  SplitContacts(body, &held, &speculative);
  DofProjection projection;
  projection.free = FreeDofs(body);
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, n), residual(3, n), product(3, n);
  internal::ImplicitIntegrator::HoldContacts(body.state.velocities, held, &projection, &x);
  MaskedPcgOptions options;
  options.relative_tolerance = 1e-300;
  options.max_iterations = 50;
  const Eigen::Matrix3Xd b = h * body.forces;
  const double pass = PassSeconds(block_case);
  double total = 0.0;
  int iterations = 0;
  for (auto _ : state) {
    x.setZero();
    auto start = Clock::now();
    iterations =
        SolveMaskedPcg(apply, b, projection, inverse_diagonal, options, &x, &residual).iterations;
    const double solve = SecondsSince(start);
    start = Clock::now();
    for (int k = 0; k <= iterations; ++k) apply(x, &product);
    const double products = SecondsSince(start);
    const double per_iteration = (solve - products) / std::max(1, iterations);
    state.SetIterationTime(per_iteration);
    total += per_iteration;
  }
  state.counters["pass_eq"] = total / static_cast<double>(state.iterations()) / pass;
  state.counters["iterations_timed"] = iterations;
  state.counters["contact_normals"] = static_cast<double>(projection.normals.size());
}

void DeepestContacts(benchmark::State& state, const BlockCase& block_case) {
  KickState& kick = WarmKickState(block_case);
  internal::ColliderContacts contacts(&kick.world);
  const internal::ImplicitIntegrator integrator(&kick.world, &contacts);
  std::size_t found = 0;
  TimeEach(
      state, block_case, [] {},
      [&] {
        found = integrator.DeepestColliderContacts(kick.body(), RealtimeScene::kStep).size();
      });
  state.counters["contacts"] = static_cast<double>(found);
}

// One re-solve's hold updates (the start's holds, the pulling, friction and reaching contacts)
// after a census's last solve, and the response to the held contacts once.
void ContactHolds(benchmark::State& state, const BlockCase& block_case) {
  using internal::ImplicitIntegrator;
  KickState& kick = WarmKickState(block_case);
  kick.Restore();
  CensusEnd end;
  CensusKick(&kick, &end);
  kick.Restore();
  internal::Body& body = kick.body();
  internal::ColliderContacts contacts(&kick.world);
  ImplicitIntegrator integrator(&kick.world, &contacts);
  const Eigen::Matrix3Xd& v = body.state.velocities;
  std::vector<internal::ContactNormal> held, speculative;
  Eigen::Matrix3Xd dv;
  TimeEach(
      state, block_case,
      [&] {
        kick.Restore();
        held = end.held;
        speculative = end.speculative;
        dv = end.dv;
      },
      [&] {
        DofProjection projection;
        projection.free = FreeDofs(body);
        ImplicitIntegrator::HoldContacts(v, held, &projection, &dv);
        projection.Apply(&dv);
        ImplicitIntegrator::HoldContacts(v, held, nullptr, &dv);
        ImplicitIntegrator::ReleasePullingContacts(end.residual, &held);
        ImplicitIntegrator::UpdateFrictionHolds(v, dv, end.residual, &held);
        ImplicitIntegrator::HoldReachingContacts(v, dv, &speculative, &held);
        integrator.RespondToHeldContacts(&body, held, end.residual);
      });
  kick.Restore();
  state.counters["held"] = static_cast<double>(end.held.size());
}

void ContactStage(benchmark::State& state, const BlockCase& block_case) {
  KickState& kick = WarmKickState(block_case);
  internal::ColliderContacts contacts(&kick.world);
  int microcollisions = 0;
  TimeEach(
      state, block_case, [&] { kick.Restore(); },
      [&] {
        microcollisions = 0;
        contacts.CollideWithColliders(&kick.body(), &microcollisions);
      });
  kick.Restore();
  state.counters["microcollisions"] = microcollisions;
}

void Drifts(benchmark::State& state, const BlockCase& block_case) {
  KickState& kick = WarmKickState(block_case);
  internal::Body& body = kick.body();
  const double h = RealtimeScene::kStep;
  TimeEach(
      state, block_case, [&] { kick.Restore(); },
      [&] {
        internal::DriftHalf(&body, h, {}, 0, body.model->num_nodes());
        internal::DriftHalfNotingFastest(&body, h, kick.world.time, kick.world.options.max_speed);
      });
  kick.Restore();
}

}  // namespace msm_sim::core::bench
