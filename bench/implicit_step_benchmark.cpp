// Google Benchmark of where the implicit step's time goes (issue 46, must-show 1: "report the
// cost of each part"), on the real-time block of `msm_lab realtime` (10 x 10 x 5 cm, E 200 kPa,
// rho 1100, dampers beta 1e-4 s, on the ground, a 1 cm sphere pressing at 1 cm/s, 1 ms steps,
// one thread, float springs as the World's default), for (nu, spacing) = (0.49, 4 mm),
// (0.49, 3 mm), (0.25, 3 mm), (0.49, 5 mm).
//
// The unit is one explicit force pass, ForceEvaluator::AccumulateForces with dampers at the
// explicit integrator's default precision ("OnePass"); every other benchmark reports `pass_eq`,
// its time over that pass's. "ExplicitStep" and "ImplicitStep" are whole World steps of 1 ms
// (counters: substeps, CG iterations per step). The parts are timed each on its own, on a copy of
// the implicit scene's state after kWarmSteps steps, half-drifted to the next kick's
// mid-substep positions (restored before every iteration): "Kick" (stages 3-4 whole),
// "ComputeForces", "Linearize", "StiffnessDiagonal" (the preconditioner), "ApplyStiffness" in
// float and double, "OperatorWrap" (the solve's operator beyond K x: c K x + M x through its
// std::function), "PcgIterationWork" (one masked-PCG iteration without its product: vector
// operations, projection, preconditioner), "DeepestContacts", "ContactHolds" (one re-solve's
// hold updates and the response to the held contacts), "ContactStage" (stages 5-6) and
// "Drifts" (stages 1 and 7). "Kick" also censuses its solves (contact_solves: 1 + re-solves)
// with a mirror of SolveKick, whose iteration count must equal the real kick's
// (census_matches = 1). Times are the thread's CPU time (manual time), so that other processes
// on a shared machine do not count. Run: msm_sim_benchmarks --benchmark_filter=ImplicitStepCost
// --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "dynamics/node_stages.h"
#include "implicit_step_scene.h"

namespace msm_sim::core::bench {
namespace {

constexpr int kWarmSteps = 30;  // 30 ms: resting on the ground, the sphere pressed in

// A scene per (case, integrator), stepped kWarmSteps from rest when first asked for.
RealtimeScene& WarmScene(const BlockCase& block_case, Integrator integrator) {
  static std::map<std::tuple<double, double, int>, std::unique_ptr<RealtimeScene>> scenes;
  auto& scene = scenes[{block_case.poisson, block_case.spacing, static_cast<int>(integrator)}];
  if (!scene) {
    scene = std::make_unique<RealtimeScene>(RealtimeBlock(block_case), integrator);
    for (int k = 0; k < kWarmSteps; ++k) scene->Step();
  }
  return *scene;
}

// One pass (s): the median of 31 AccumulateForces at the warm explicit scene's state, after 5
// untimed.
double PassSeconds(const BlockCase& block_case) {
  static std::map<std::pair<double, double>, double> passes;
  double& pass = passes[{block_case.poisson, block_case.spacing}];
  if (pass == 0.0) {
    internal::Body& body = WarmScene(block_case, Integrator::kExplicit).block();
    Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, body.model->num_nodes());
    std::vector<double> times;
    for (int k = 0; k < 5; ++k) {  // untimed: the arrays allocated and in the cache
      body.evaluator.AccumulateForces(body.state.positions, body.state.velocities,
                                      body.options.damping_beta, &forces);
    }
    for (int k = 0; k < 31; ++k) {
      const auto start = Clock::now();
      body.evaluator.AccumulateForces(body.state.positions, body.state.velocities,
                                      body.options.damping_beta, &forces);
      times.push_back(SecondsSince(start));
    }
    std::nth_element(times.begin(), times.begin() + 15, times.end());
    pass = times[15];
  }
  return pass;
}

KickState& WarmKickState(const BlockCase& block_case) {
  static std::map<std::pair<double, double>, std::unique_ptr<KickState>> states;
  auto& kick = states[{block_case.poisson, block_case.spacing}];
  if (!kick) {
    kick = std::make_unique<KickState>(WarmScene(block_case, Integrator::kImplicit).world());
  }
  return *kick;
}

// Times work() per iteration after an untimed prepare() (manual time); pass_eq is the mean
// over one pass.
void TimeEach(benchmark::State& state, const BlockCase& block_case,
              const std::function<void()>& prepare, const std::function<void()>& work) {
  const double pass = PassSeconds(block_case);
  double total = 0.0;
  for (auto _ : state) {
    prepare();
    const auto start = Clock::now();
    work();
    const double seconds = SecondsSince(start);
    state.SetIterationTime(seconds);
    total += seconds;
  }
  state.counters["pass_eq"] = total / static_cast<double>(state.iterations()) / pass;
}

void OnePass(benchmark::State& state, const BlockCase& block_case) {
  internal::Body& body = WarmScene(block_case, Integrator::kExplicit).block();
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, body.model->num_nodes());
  TimeEach(
      state, block_case, [] {},
      [&] {
        body.evaluator.AccumulateForces(body.state.positions, body.state.velocities,
                                        body.options.damping_beta, &forces);
      });
  state.counters["nodes"] = body.model->num_nodes();
  state.counters["springs"] = body.model->num_springs();
}

// Implicit: before each timed step, a census of its kick (on a copy, untimed) counts its
// solves (census_cg_iterations equals cg_iterations when the census follows the step's kick).
void WholeStep(benchmark::State& state, const BlockCase& block_case, Integrator integrator) {
  RealtimeScene& scene = WarmScene(block_case, integrator);
  const bool implicit = integrator == Integrator::kImplicit;
  long substeps = 0, iterations = 0, solves = 0, most_solves = 0, census_iterations = 0;
  const auto census = [&] {
    if (!implicit) return;
    KickState next(scene.world());
    CensusEnd end;
    const KickCensus kick = CensusKick(&next, &end);
    solves += kick.solves;
    most_solves = std::max<long>(most_solves, kick.solves);
    census_iterations += kick.iterations;
  };
  TimeEach(state, block_case, census, [&] {
    const StepReport report = scene.Step();
    if (!report.accepted) state.SkipWithError(report.reason.c_str());
    substeps += report.substeps;
    iterations += report.solver_iterations;
  });
  const double steps = static_cast<double>(state.iterations());
  state.counters["substeps"] = substeps / steps;
  if (implicit) {
    state.counters["cg_iterations"] = iterations / steps;
    state.counters["contact_solves"] = solves / steps;
    state.counters["contact_solves_most"] = most_solves;
    state.counters["census_cg_iterations"] = census_iterations / steps;
  }
}

void ExplicitStep(benchmark::State& state, const BlockCase& block_case) {
  WholeStep(state, block_case, Integrator::kExplicit);
}

void ImplicitStep(benchmark::State& state, const BlockCase& block_case) {
  WholeStep(state, block_case, Integrator::kImplicit);
}

void Kick(benchmark::State& state, const BlockCase& block_case) {
  KickState& kick = WarmKickState(block_case);
  internal::ColliderContacts contacts(&kick.world);
  internal::ImplicitIntegrator integrator(&kick.world, &contacts);
  int iterations = 0;
  TimeEach(
      state, block_case, [&] { kick.Restore(); },
      [&] { iterations = integrator.Kick(&kick.body(), RealtimeScene::kStep, kick.world.time); });
  kick.Restore();
  CensusEnd end;
  const KickCensus census = CensusKick(&kick, &end);
  kick.Restore();
  const double pass = PassSeconds(block_case);
  state.counters["cg_iterations"] = iterations;
  state.counters["census_matches"] = census.iterations == iterations ? 1 : 0;
  state.counters["contact_solves"] = census.solves;
  state.counters["touching"] = census.touching;
  state.counters["speculative"] = census.speculative;
  state.counters["held_at_end"] = census.held_at_end;
  state.counters["in_kick_forces_pass_eq"] = census.forces_seconds / pass;
  state.counters["in_kick_linearize_pass_eq"] = census.linearize_seconds / pass;
  state.counters["in_kick_contacts_pass_eq"] = census.contacts_seconds / pass;
  state.counters["in_kick_solves_pass_eq"] = census.solve_seconds / pass;
}

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

// Registered per case in this order: the scenes are warmed on first use, the whole steps (which
// advance their scene) after the parts (which restore theirs).
bool RegisterImplicitStepCosts() {
  using Part = void (*)(benchmark::State&, const BlockCase&);
  const std::vector<std::tuple<const char*, Part, int>> parts = {
      {"OnePass", OnePass, 40},
      {"ExplicitStep", ExplicitStep, 20},
      {"Kick", Kick, 10},
      {"ComputeForces", ComputeForcesPart, 40},
      {"Linearize", LinearizePart, 20},
      {"StiffnessDiagonal", StiffnessDiagonalPart, 20},
      {"ApplyStiffnessFloat", ApplyStiffnessFloat, 40},
      {"ApplyStiffnessDouble", ApplyStiffnessDouble, 40},
      {"OperatorWrap", OperatorWrap, 40},
      {"PcgIterationWork", PcgIterationWork, 20},
      {"DeepestContacts", DeepestContacts, 40},
      {"ContactHolds", ContactHolds, 40},
      {"ContactStage", ContactStage, 40},
      {"Drifts", Drifts, 40},
      {"ImplicitStep", ImplicitStep, 10},
  };
  const std::vector<std::pair<BlockCase, std::string>> cases = {
      {{0.49, 0.004}, "nu490/4mm"},
      {{0.49, 0.003}, "nu490/3mm"},
      {{0.25, 0.003}, "nu250/3mm"},
      {{0.49, 0.005}, "nu490/5mm"},
  };
  for (const auto& [block_case, case_name] : cases) {
    for (const auto& [part_name, part, iterations] : parts) {
      const BlockCase captured = block_case;
      const Part run = part;
      benchmark::RegisterBenchmark(
          ("ImplicitStepCost/" + case_name + "/" + part_name).c_str(),
          [captured, run](benchmark::State& state) { run(state, captured); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(iterations);
    }
  }
  return true;
}

const bool kRegistered = RegisterImplicitStepCosts();

}  // namespace
}  // namespace msm_sim::core::bench
