// Google Benchmarks (run with `make bench`): the virtual compression test (issue target: ~16k
// nodes in under 10 s on two cores) and the cost of one force evaluation.
#include <benchmark/benchmark.h>

#include "bench_threads.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.25, 1100.0);

// Node-centred cubic block 2 x 1 x 1 m at a = 1/20 m: 40 x 20 x 20 = 16,000 nodes.
void BM_CompressionCubic16k(benchmark::State& state) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  lattice_options.lattice.spacing = 0.05;
  for (auto _ : state) {
    const Model model = BuildCubicLattice(kMaterial, lattice_options);
    CompressionExperimentOptions options;
    options.body_size = lattice_options.size;
    const CompressionExperimentResult result = RunCompressionExperiment(model, options);
    benchmark::DoNotOptimize(result.youngs_measured);
    state.counters["nodes"] = model.num_nodes();
    state.counters["E_rel_error"] = result.youngs_measured / 1e5 - 1.0;
  }
}
BENCHMARK(BM_CompressionCubic16k)->Unit(benchmark::kSecond)->Iterations(3);

// Random block 4 x 2 x 2 m at l = 0.1 m: 16,000 nodes, <S> ~ 22.
void BM_CompressionRandom16k(benchmark::State& state) {
  RandomLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(4.0, 2.0, 2.0);
  lattice_options.lattice.spacing = 0.1;
  lattice_options.max_distance = 1.9;
  for (auto _ : state) {
    const Model model = BuildRandomLattice(kMaterial, lattice_options);
    CompressionExperimentOptions options;
    options.body_size = lattice_options.size;
    const CompressionExperimentResult result = RunCompressionExperiment(model, options);
    benchmark::DoNotOptimize(result.youngs_measured);
    state.counters["nodes"] = model.num_nodes();
    state.counters["E_rel_error"] = result.youngs_measured / 1e5 - 1.0;
  }
}
BENCHMARK(BM_CompressionRandom16k)->Unit(benchmark::kSecond)->Iterations(3);

// Times AccumulateForces on the model compressed uniformly by 1 %, with spring dampers
// (beta = 1e-4 s, as in a dynamics step) at random velocities when `damped`.
void TimeForceEvaluations(const Model& model, benchmark::State& state,
                          SpringKernels kernels = SpringKernels::kAuto, bool damped = false,
                          SpringPrecision precision = SpringPrecision::kDouble) {
  ForceEvaluator evaluator(model, kernels, BenchThreads());
  evaluator.set_precision(precision);
  const Eigen::Matrix3Xd positions = model.rest_positions() * 0.99;
  const Eigen::Matrix3Xd velocities = 1e-3 * Eigen::Matrix3Xd::Random(3, model.num_nodes());
  Eigen::Matrix3Xd forces(3, model.num_nodes());
  for (auto _ : state) {
    forces.setZero();
    evaluator.AccumulateForces(positions, velocities, damped ? 1e-4 : 0.0, &forces);
    benchmark::DoNotOptimize(forces.data());
    benchmark::ClobberMemory();
  }
  state.counters["nodes"] = model.num_nodes();
  state.counters["springs"] = model.num_springs();
}

// One force evaluation on a node-centred cubic block 2 x 1 x 1 m at a = 1/18 m (11,664 nodes,
// 96,579 springs): plain MSM (nu = 1/4) against the eMSM (nu = 0.45), and the non-linear
// spring law. Issue target: eMSM <= 1.6 x plain.
Model Block12k(double poisson, SpringLaw law = SpringLaw::kLinear) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  lattice_options.lattice.spacing = 1.0 / 18.0;
  lattice_options.lattice.spring_law = law;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1100.0), lattice_options);
}

void BM_ForceEvaluation12k(benchmark::State& state, double poisson, SpringLaw law) {
  TimeForceEvaluations(Block12k(poisson, law), state);
}

// The run kernels against the per-spring loops on the same block, with dampers as in a step
// (run with --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true to compare).
void BM_SpringKernels12k(benchmark::State& state, double poisson, SpringKernels kernels) {
  TimeForceEvaluations(Block12k(poisson), state, kernels, true);
}
// The single-precision loops (the dynamics' default, WorldOptions::spring_precision) on the same
// block with dampers: plain MSM against the two-pass eMSM (issue target: eMSM <= 1.6 x plain).
void BM_SingleSpringLoops12k(benchmark::State& state, double poisson) {
  TimeForceEvaluations(Block12k(poisson), state, SpringKernels::kAuto, true,
                       SpringPrecision::kSingle);
}
BENCHMARK_CAPTURE(BM_SingleSpringLoops12k, plain, 0.25)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SingleSpringLoops12k, emsm, 0.45)->Unit(benchmark::kMicrosecond);
// One stiffness product (the implicit integrator's CG iteration) on the block linearised at 1 %
// compression, run kernels against per-spring loops, and the run kernels in single precision
// (the dynamics' default since 2026-11-26) on one thread against them in double. Each side does
// the same: round or copy v into the kernels' layout, the direct and the dispersed pass, the
// sum back into a 3 x N product.
void BM_StiffnessProduct12k(benchmark::State& state, double poisson, SpringKernels kernels,
                            SpringPrecision precision = SpringPrecision::kDouble) {
  const Model model = Block12k(poisson);
  ForceEvaluator evaluator(model, kernels, precision == SpringPrecision::kSingle ? 1 : 64);
  evaluator.set_precision(precision);
  evaluator.Linearize(model.rest_positions() * 0.99, GeometricStiffness::kDropCompression);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Random(3, model.num_nodes());
  Eigen::Matrix3Xd product;
  for (auto _ : state) {
    evaluator.ApplyStiffness(v, &product);
    benchmark::DoNotOptimize(product.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK_CAPTURE(BM_StiffnessProduct12k, emsm_per_spring, 0.49, SpringKernels::kPerSpring)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StiffnessProduct12k, emsm_runs, 0.49, SpringKernels::kAuto)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_StiffnessProduct12k, emsm_runs_single, 0.49, SpringKernels::kAuto,
                  SpringPrecision::kSingle)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SpringKernels12k, plain_per_spring, 0.25, SpringKernels::kPerSpring)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SpringKernels12k, plain_runs, 0.25, SpringKernels::kAuto)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SpringKernels12k, emsm_per_spring, 0.45, SpringKernels::kPerSpring)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SpringKernels12k, emsm_runs, 0.45, SpringKernels::kAuto)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ForceEvaluation12k, plain, 0.25, SpringLaw::kLinear)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ForceEvaluation12k, emsm_two_pass, 0.45, SpringLaw::kLinear)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ForceEvaluation12k, plain_nonlinear, 0.25, SpringLaw::kNonlinear)
    ->Unit(benchmark::kMicrosecond);

// The same block as an element-corner cubic lattice (37 x 19 x 19 corner nodes, as Baudet's
// bricks below), and both cubic constructions with the single-precision loops the dynamics use:
// the README's model table compares the models' cost per evaluation (nu = 0.45, two-pass, no
// dampers).
void BM_ForceEvaluationCubic12k(benchmark::State& state, CubicConstruction construction,
                                SpringPrecision precision) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  lattice_options.lattice.spacing = 1.0 / 18.0;
  lattice_options.construction = construction;
  const Model model =
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1100.0), lattice_options);
  TimeForceEvaluations(model, state, SpringKernels::kAuto, false, precision);
}
BENCHMARK_CAPTURE(BM_ForceEvaluationCubic12k, corner_double, CubicConstruction::kElementCorner,
                  SpringPrecision::kDouble)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ForceEvaluationCubic12k, corner_single, CubicConstruction::kElementCorner,
                  SpringPrecision::kSingle)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ForceEvaluationCubic12k, node_single, CubicConstruction::kNodeCentred,
                  SpringPrecision::kSingle)
    ->Unit(benchmark::kMicrosecond);

// Baudet's bricks on the same block: 37 x 19 x 19 corner nodes (13,357), 12 edges and 4 inner
// diagonals per brick plus the correction elements, at nu = 0.45.
void BM_ForceEvaluationBaudet12k(benchmark::State& state) {
  BaudetLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  lattice_options.lattice.spacing = 1.0 / 18.0;
  const Model model =
      BuildBaudetLattice(Material::FromYoungsPoisson(1e5, 0.45, 1100.0), lattice_options);
  TimeForceEvaluations(model, state);
}
BENCHMARK(BM_ForceEvaluationBaudet12k)->Unit(benchmark::kMicrosecond);

// A random eMSM block 3 x 2 x 2 m at l = 0.1 m (12,000 nodes, <S> ~ 22), nu = 0.45, two-pass.
void BM_ForceEvaluationRandom12k(benchmark::State& state) {
  RandomLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(3.0, 2.0, 2.0);
  lattice_options.lattice.spacing = 0.1;
  lattice_options.max_distance = 1.9;
  const Model model =
      BuildRandomLattice(Material::FromYoungsPoisson(1e5, 0.45, 1100.0), lattice_options);
  TimeForceEvaluations(model, state);
}
BENCHMARK(BM_ForceEvaluationRandom12k)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace msm_sim::core

BENCHMARK_MAIN();
