// Google Benchmark of the real-time issue's scene (`msm_lab realtime`): the 10 x 10 x 5 cm block
// (E = 200 kPa, rho = 1100, dampers beta = 1e-4 s) on the ground, a 1 cm sphere pressing into
// its top at 1 cm/s, 1 ms World steps, explicit integrator. Each iteration runs
// 0.1 s of simulated time through RunRealtimeExperiment and counts only its stepping (manual
// time, the World's set-up and stable-step estimate excluded); `real_time_factor` is simulated
// over stepping time. Variants: node spacing, Poisson's ratio, the spring loops' precision
// (WorldOptions::spring_precision) and the threads (WorldOptions::threads: 1, or 2 for the
// single-precision loops, whose node shares then run the per-node stages too) and the outer
// layer's share of the eMSM bulk (NodeCentredSurfaceOptions::surface_dispersion, in per cent: 100
// is off, 50 and 25 the softer outer layer of docs/physics.md §7). Compare variants interleaved:
// --benchmark_filter=Realtime
// --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
#include <map>
#include <memory>
#include <tuple>
#include <utility>

#include <benchmark/benchmark.h>

#include "msm_sim/experiments/realtime_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

// Built once per (spacing, nu, surface dispersion): a 4,000-node block takes a few tenths of a
// second.
std::shared_ptr<const Model> RealtimeBlock(double spacing, double poisson,
                                           double surface_dispersion) {
  static std::map<std::tuple<double, double, double>, std::shared_ptr<const Model>> blocks;
  auto& block = blocks[{spacing, poisson, surface_dispersion}];
  if (!block) {
    CubicLatticeOptions lattice_options;
    lattice_options.size = Eigen::Vector3d(0.1, 0.1, 0.05);
    lattice_options.lattice.spacing = spacing;
    lattice_options.surface.surface_dispersion = surface_dispersion;
    block = std::make_shared<const Model>(
        BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), lattice_options));
  }
  return block;
}

// Arguments: spacing (um), nu (per mille), precision (0 double, 1 single), threads, surface
// dispersion (per cent).
RealtimeExperimentResult RunRealtime(benchmark::State& state,
                                     const RealtimeExperimentOptions& options) {
  const auto block =
      RealtimeBlock(state.range(0) * 1e-6, state.range(1) * 1e-3, state.range(4) * 1e-2);
  RealtimeExperimentResult result;
  for (auto _ : state) {
    result = RunRealtimeExperiment(block, options);
    state.SetIterationTime(result.wall_seconds);
  }
  state.counters["nodes"] = result.nodes;
  state.counters["substeps"] = result.substeps;
  state.counters["real_time_factor"] = result.real_time_factor;
  state.counters["peak_force_N"] = result.peak_force;
  state.counters["iterations_per_step"] = result.solver_iterations_per_step;
  return result;
}

void BM_RealtimeBlock(benchmark::State& state) {
  RealtimeExperimentOptions options;
  options.seconds = 0.1;
  options.spring_precision =
      state.range(2) == 1 ? SpringPrecision::kSingle : SpringPrecision::kDouble;
  options.threads = static_cast<int>(state.range(3));
  RunRealtime(state, options);
}
BENCHMARK(BM_RealtimeBlock)
    ->ArgNames({"spacing_um", "nu_permille", "single", "threads", "surface_pct"})
    ->ArgsProduct({{5000, 4000}, {250, 490}, {0}, {1}, {100}})
    ->ArgsProduct({{5000, 4000}, {250, 490}, {1}, {1, 2}, {100}})
    ->ArgsProduct({{5000, 4000}, {490}, {1}, {1, 2}, {50, 25}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// The implicit integrator (one 1 ms substep a step) on the same blocks.
void BM_RealtimeBlockImplicit(benchmark::State& state) {
  RealtimeExperimentOptions options;
  options.seconds = 0.1;
  options.integrator = Integrator::kImplicit;
  options.spring_precision =
      state.range(2) == 1 ? SpringPrecision::kSingle : SpringPrecision::kDouble;
  options.threads = static_cast<int>(state.range(3));
  RunRealtime(state, options);
}
BENCHMARK(BM_RealtimeBlockImplicit)
    ->ArgNames({"spacing_um", "nu_permille", "single", "threads", "surface_pct"})
    ->ArgsProduct({{5000, 4000, 3000}, {250, 490}, {1}, {1}, {100}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace msm_sim::core
