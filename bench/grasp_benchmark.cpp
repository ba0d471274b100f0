// Google Benchmark of the grasp issue's scene (`msm_lab grasp`, the ROS grasp demo's object): a
// 5 cm silicone bean (meshes/soft_bean.obj scaled by 0.42; E 259 kPa, nu 0.49, rho 1070) in a
// 3 mm node-centred cubic lattice with surface_dispersion 0.25, squeezed by two force-controlled
// pads to 2 mu F_n = 1.5 m g (mu 0.8), held, lifted 5 cm in 1 s and held, on one thread. Each
// iteration is the whole grasp (3.6 s simulated); `real_time_factor` is simulated over wall time
// of its steps, with the experiment's per-step energy and speed bookkeeping (the target is >= 1).
// Arguments: the integrator (0 explicit, 1 implicit, 2 implicit without the solve's early stop,
// docs/physics.md §7.1 "Stopping the solve": the baseline of that stop).
// --benchmark_filter=Grasp --benchmark_repetitions=3
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "msm_sim/experiments/grasp_experiment.h"
#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/lattice/body_recipe.h"

namespace msm_sim::core {
namespace {

std::shared_ptr<const Model> GraspBean() {
  static std::shared_ptr<const Model> bean;
  if (!bean) {
    MeshImportOptions import;
    import.scale = 0.42;
    BodyRecipe recipe(Material::FromYoungsPoisson(259e3, 0.49, 1070.0));
    recipe.solid = std::make_shared<const SolidMesh>(
        ImportSolidMesh(std::string(MSM_SIM_MESH_DIR) + "/soft_bean.obj", import));
    recipe.lattice.spacing = 0.003;
    recipe.surface.surface_dispersion = 0.25;
    bean = std::make_shared<const Model>(BuildModel(recipe));
  }
  return bean;
}

void BM_GraspScene(benchmark::State& state) {
  const auto bean = GraspBean();
  GraspExperimentOptions options;
  options.integrator = state.range(0) == 0 ? Integrator::kExplicit : Integrator::kImplicit;
  if (state.range(0) == 2) options.implicit_energy_tolerance = 0.0;
  GraspExperimentResult result;
  for (auto _ : state) {
    result = RunGraspExperiment(bean, options);
    state.SetIterationTime(result.simulated_time / result.real_time_factor);
  }
  state.counters["nodes"] = result.nodes;
  state.counters["real_time_factor"] = result.real_time_factor;
  state.counters["held"] = result.held ? 1.0 : 0.0;
  state.counters["cg_iterations_per_step"] = result.solver_iterations;
}
BENCHMARK(BM_GraspScene)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace msm_sim::core
