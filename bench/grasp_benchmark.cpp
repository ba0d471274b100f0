// Google Benchmark of the grasp issue's scene (`msm_lab grasp`, the ROS grasp demo's object): a
// 5 cm silicone bean (meshes/soft_bean.obj scaled by 0.42; E 259 kPa, nu 0.49, rho 1070) in a
// 3 mm node-centred cubic lattice with surface_dispersion 0.25, squeezed by two force-controlled
// pads to 2 mu F_n = 1.5 m g (mu 0.8), held, lifted 5 cm in 1 s and held, on one thread. Each
// iteration is the whole grasp (3.6 s simulated); `real_time_factor` is simulated over wall time
// of its steps, with the experiment's per-step energy and speed bookkeeping (the target is >= 1).
// Arguments: the integrator (0 explicit, 1 implicit, 2 implicit without the solve's early stop,
// docs/physics.md §7.1 "Stopping the solve": the baseline of that stop).
// BM_GraspSphere and BM_GraspCylinder: the grasp grid's sphere (Ø 5 cm) and cylinder (Ø 4 x 6 cm,
// lying across the pads) in the same material and lattice, Q 1.5 (config/sweeps/grasp.yaml).
// BM_GraspSceneUnscaled: the bean without selective mass scaling (mass_scaling 0,
// docs/physics.md §7), the baseline of that scaling, run interleaved with it.
// --benchmark_filter=Grasp --benchmark_repetitions=3
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "msm_sim/experiments/grasp_experiment.h"
#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/mechanics/stable_time_step.h"

namespace msm_sim::core {
namespace {

// The bean with mass_scaling `bound` (NodeCentredSurfaceOptions::mass_scaling), built once.
std::shared_ptr<const Model> GraspBean(double bound = NodeCentredSurfaceOptions{}.mass_scaling) {
  static std::map<double, std::shared_ptr<const Model>> beans;
  std::shared_ptr<const Model>& bean = beans[bound];
  if (!bean) {
    MeshImportOptions import;
    import.scale = 0.42;
    BodyRecipe recipe(Material::FromYoungsPoisson(259e3, 0.49, 1070.0));
    recipe.solid = std::make_shared<const SolidMesh>(
        ImportSolidMesh(std::string(MSM_SIM_MESH_DIR) + "/soft_bean.obj", import));
    recipe.lattice.spacing = 0.003;
    recipe.surface.surface_dispersion = 0.25;
    recipe.surface.mass_scaling = bound;
    bean = std::make_shared<const Model>(BuildModel(recipe));
  }
  return bean;
}

// A solid of the grasp grid (as `msm_lab grasp` makes it) in the bean's material and lattice.
std::shared_ptr<const Model> GraspPrimitive(const TriangleMesh& surface) {
  BodyRecipe recipe(Material::FromYoungsPoisson(259e3, 0.49, 1070.0));
  recipe.solid = std::make_shared<const SolidMesh>(surface);
  recipe.lattice.spacing = 0.003;
  recipe.surface.surface_dispersion = 0.25;
  return std::make_shared<const Model>(BuildModel(recipe));
}

std::shared_ptr<const Model> GraspSphere() {
  static std::shared_ptr<const Model> sphere;
  if (!sphere) sphere = GraspPrimitive(MakeIcosphereMesh(0.025, 4));
  return sphere;
}

// Lying across the pads: its axis along y (a quarter turn about x), the pads closing along x.
std::shared_ptr<const Model> GraspCylinder() {
  static std::shared_ptr<const Model> cylinder;
  if (!cylinder) {
    TriangleMesh mesh = MakeCylinderMesh(0.02, 0.06, 96);
    const Eigen::Matrix3Xd along_z = mesh.vertices;
    mesh.vertices.row(1) = -along_z.row(2);
    mesh.vertices.row(2) = along_z.row(1);
    cylinder = GraspPrimitive(mesh);
  }
  return cylinder;
}

void RunGrasp(benchmark::State& state, const std::shared_ptr<const Model>& object) {
  GraspExperimentOptions options;
  options.integrator = state.range(0) == 0 ? Integrator::kExplicit : Integrator::kImplicit;
  if (state.range(0) == 2) options.implicit_energy_tolerance = 0.0;
  GraspExperimentResult result;
  for (auto _ : state) {
    result = RunGraspExperiment(object, options);
    state.SetIterationTime(result.simulated_time / result.real_time_factor);
  }
  state.counters["nodes"] = result.nodes;
  state.counters["real_time_factor"] = result.real_time_factor;
  state.counters["held"] = result.held ? 1.0 : 0.0;
  state.counters["cg_iterations_per_step"] = result.solver_iterations;
  state.counters["added_mass_fraction"] = object->added_mass() / object->masses().sum();
  StableTimeStepOptions stability;  // the grasp World's: its dampers, safety 0.8
  stability.damping_beta = options.damping_beta;
  state.counters["substeps_per_step"] =
      std::ceil(options.step / StableTimeStep(*object, stability));
}

void BM_GraspScene(benchmark::State& state) { RunGrasp(state, GraspBean()); }
void BM_GraspSceneUnscaled(benchmark::State& state) { RunGrasp(state, GraspBean(0.0)); }
void BM_GraspSphere(benchmark::State& state) { RunGrasp(state, GraspSphere()); }
void BM_GraspCylinder(benchmark::State& state) { RunGrasp(state, GraspCylinder()); }
BENCHMARK(BM_GraspSceneUnscaled)->Arg(0)->UseManualTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_GraspScene)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK(BM_GraspSphere)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_GraspCylinder)
    ->Arg(0)
    ->Arg(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace msm_sim::core
