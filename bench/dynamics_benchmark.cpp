// Google Benchmark of one dynamics step (issue "Dynamics": <= 1 ms for ~12k nodes and ~100k
// springs on two cores; the thesis needed 10 ms on four cores for 12k nodes).
#include <memory>

#include <benchmark/benchmark.h>

#include "bench_threads.h"
#include "msm_sim/dynamics/contact_point_average.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

// 40 x 20 x 15 = 12,000 nodes at a = 1 cm, about 99k springs, resting on the ground: every
// step evaluates the eMSM forces (two-pass, nu = 0.45) with dampers, integrates, and resolves
// the ground's microcollisions of the bottom layer; with `record_contact_points`, also keeps them
// (World::contact_points) and averages them as the node does for ~contact_points; with
// `orientation_threshold` > 0, also evaluates the orientation barrier's 8 corners per node
// (BodyOptions::orientation_threshold; none is below it at rest, so it adds no force).
void DynamicsStep12k(benchmark::State& state, bool record_contact_points,
                     double orientation_threshold = 0.0) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.4, 0.2, 0.15);
  lattice_options.lattice.spacing = 0.01;
  const auto model = std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1100.0), lattice_options));
  WorldOptions world_options;
  world_options.threads = BenchThreads();  // MSM_SIM_THREADS, else every core, as measured
  world_options.record_contact_points = record_contact_points;
  World world(world_options);
  BodyOptions options;
  options.damping_beta = 1e-4;
  options.orientation_threshold = orientation_threshold;
  const int body = world.AddBody("block", model, options);
  world.AddCollider(GroundTouching(model->rest_positions(), world.border(body)));
  const double step = world.stable_time_step();
  for (int settle = 0; settle < 200; ++settle) world.Step(step);  // in contact, loaded
  ContactPointAverage points;
  int contacts = 0, steps = 0;
  for (auto _ : state) {
    const StepReport report = world.Step(step);
    contacts = report.microcollisions;
    benchmark::DoNotOptimize(report.accepted);
    if (record_contact_points) {
      points.AddStep(step);
      points.Add(body, model->num_nodes(), world.contact_points(body));
      if (++steps % 33 == 0) points.Reset();  // a 30 Hz publication at 1 ms steps
    }
  }
  state.counters["nodes"] = model->num_nodes();
  state.counters["springs"] = model->num_springs();
  state.counters["ground_contacts"] = contacts;
  state.counters["dt_us"] = step * 1e6;
}

void BM_DynamicsStep12k(benchmark::State& state) { DynamicsStep12k(state, false); }
void BM_DynamicsStep12kContactPoints(benchmark::State& state) { DynamicsStep12k(state, true); }
BENCHMARK(BM_DynamicsStep12k)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
BENCHMARK(BM_DynamicsStep12kContactPoints)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
void BM_DynamicsStep12kOrientationBarrier(benchmark::State& state) {
  DynamicsStep12k(state, false, 0.2);
}
BENCHMARK(BM_DynamicsStep12kOrientationBarrier)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

}  // namespace
}  // namespace msm_sim::core
