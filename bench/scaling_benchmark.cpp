// Google Benchmark of how one dynamics step scales with the node count (issue "Real time at real
// resolution": cost linear in the node count from 1k to 1M nodes, reported as microseconds per
// node-step). Cubes of n^3 nodes at a = 1 cm (n = 10, 20, 40, 80, 100: 1k to 1M nodes) resting
// on the ground, E = 200 kPa, rho = 1100 kg/m^3, dampers beta = 1e-4 s, at nu = 0.25 (plain MSM)
// and nu = 0.49 (eMSM, two-pass dispersion). A fixed spacing keeps the stable step and the work
// per node the same at every size; only the share of border nodes (the ones tested against the
// ground) shrinks, from 49 % of the nodes at n = 10 to 6 % at n = 100.
//
// Each model and its settled World are built once per (n, nu) and kept for the repetitions and
// the iteration-count estimates Google Benchmark runs (a 1M-node model takes seconds to build:
// see the counter build_s). Counters: us_per_node_step (wall time per step / nodes),
// substep_us (msm_sim's stable step), nodes, springs, border nodes, ground contacts, build_s.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>

#include <benchmark/benchmark.h>

#include "bench_threads.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

constexpr double kSpacing = 0.01;  // m
constexpr int kSettleSteps = 20;   // the bottom layer is in contact from the first step

// The spring passes may use BenchThreads() threads (MSM_SIM_THREADS picks the column), as the
// README's figures were measured; a World's default is one.
WorldOptions ThreadedWorld() {
  WorldOptions options;
  options.threads = BenchThreads();
  return options;
}

struct ScalingScene {
  ScalingScene(int side, double poisson) {
    const auto start = std::chrono::steady_clock::now();
    CubicLatticeOptions lattice_options;
    lattice_options.size = Eigen::Vector3d::Constant(side * kSpacing);
    lattice_options.lattice.spacing = kSpacing;
    model = std::make_shared<const Model>(
        BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), lattice_options));
    BodyOptions options;
    options.damping_beta = 1e-4;
    body = world.AddBody("block", model, options);
    world.AddCollider(GroundTouching(model->rest_positions(), world.border(body)));
    step = world.stable_time_step();
    build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (int settle = 0; settle < kSettleSteps; ++settle) world.Step(step);
  }
  std::shared_ptr<const Model> model;
  World world{ThreadedWorld()};
  int body = 0;
  double step = 0.0;           // s
  double build_seconds = 0.0;  // model, border and stable step
};

// One scene per (side, nu in percent), built on first use. Only the latest is kept: the 1M-node
// scenes are large, and Google Benchmark runs each benchmark's repetitions one after the other
// (unless --benchmark_enable_random_interleaving, which then rebuilds as it alternates).
ScalingScene& Scene(int side, int poisson_percent) {
  static std::pair<int, int> key{0, 0};
  static std::unique_ptr<ScalingScene> scene;
  if (!scene || key != std::make_pair(side, poisson_percent)) {
    scene.reset();  // free the previous scene before building the next
    scene = std::make_unique<ScalingScene>(side, poisson_percent / 100.0);
    key = {side, poisson_percent};
  }
  return *scene;
}

void BM_ScalingStep(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  ScalingScene& scene = Scene(side, static_cast<int>(state.range(1)));
  int contacts = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const StepReport report = scene.world.Step(scene.step);
    contacts = report.microcollisions;
    benchmark::DoNotOptimize(report.accepted);
  }
  const double wall_us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  const double nodes = scene.model->num_nodes();
  state.counters["nodes"] = nodes;
  state.counters["springs"] = scene.model->num_springs();
  state.counters["border"] = static_cast<double>(scene.world.border(scene.body).nodes.size());
  state.counters["ground_contacts"] = contacts;
  state.counters["substep_us"] = scene.step * 1e6;
  state.counters["us_per_node_step"] = wall_us / (static_cast<double>(state.iterations()) * nodes);
  state.counters["build_s"] = scene.build_seconds;
}
BENCHMARK(BM_ScalingStep)
    ->ArgNames({"side", "nu_percent"})
    ->ArgsProduct({{10, 20, 40, 80, 100}, {25, 49}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(1.0)
    ->UseRealTime();

}  // namespace
}  // namespace msm_sim::core
