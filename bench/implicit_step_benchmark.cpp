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
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "implicit_step_timing.h"

namespace msm_sim::core::bench {
namespace {

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
