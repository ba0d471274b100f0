// Google Benchmark of a mesh object's spring passes against a box lattice's, per spring (issue
// "Real-time grasps", must-show 4: a mesh object's passes within 1.5x of the box's cost per
// spring). The objects are the grasp benchmark's material and lattice (E 259 kPa, nu 0.49,
// rho 1070, 3 mm node-centred cubic, surface_dispersion 0.25): a box of 4.2 cm (about the
// sphere's node count), the sphere Ø 5 cm and the bean scaled to 5 cm. Each is held at its rest
// shape strained by a seeded random displacement of 2 % of the spacing and moving at a seeded
// random velocity, in the World's default precision (float springs), one thread.
// BM_SpringForcePass times the explicit integrator's pass (forces with dampers, SetForces);
// BM_SpringStiffnessProduct the implicit solve's K v (ApplyStiffness after Linearize). Counter
// `time_per_spring` (s): the pass's time over the model's springs; compare the mesh rows with the
// box's of the same benchmark. Arguments: 0 box, 1 sphere, 2 bean.
#include <memory>
#include <random>
#include <string>

#include <benchmark/benchmark.h>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

constexpr double kSpacing = 0.003;

// The object of argument `which` (0 box, 1 sphere, 2 bean), built once.
const Model& PassObject(int which) {
  static std::shared_ptr<const Model> objects[3];
  std::shared_ptr<const Model>& object = objects[which];
  if (!object) {
    BodyRecipe recipe(Material::FromYoungsPoisson(259e3, 0.49, 1070.0));
    recipe.lattice.spacing = kSpacing;
    recipe.surface.surface_dispersion = 0.25;
    if (which == 0) {
      recipe.box_size = Eigen::Vector3d::Constant(0.042);
    } else if (which == 1) {
      recipe.solid = std::make_shared<const SolidMesh>(MakeIcosphereMesh(0.025, 4));
    } else {
      MeshImportOptions import;
      import.scale = 0.42;
      recipe.solid = std::make_shared<const SolidMesh>(
          ImportSolidMesh(std::string(MSM_SIM_MESH_DIR) + "/soft_bean.obj", import));
    }
    object = std::make_shared<const Model>(BuildModel(recipe));
  }
  return *object;
}

// The rest shape displaced by up to `amplitude` per coordinate, seeded.
Eigen::Matrix3Xd Perturbed(const Eigen::Matrix3Xd& base, double amplitude, unsigned seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> uniform(-amplitude, amplitude);
  Eigen::Matrix3Xd out = base;
  for (Eigen::Index i = 0; i < out.size(); ++i) out.data()[i] += uniform(generator);
  return out;
}

struct PassScene {
  explicit PassScene(const Model& model)
      : evaluator(model),
        positions(Perturbed(model.rest_positions(), 0.02 * kSpacing, 1)),
        velocities(Perturbed(Eigen::Matrix3Xd::Zero(3, model.num_nodes()), 0.01, 2)),
        out(3, model.num_nodes()) {
    evaluator.set_precision(SpringPrecision::kSingle);
  }
  ForceEvaluator evaluator;
  Eigen::Matrix3Xd positions, velocities, out;
};

void Count(benchmark::State& state, const Model& model) {
  state.counters["nodes"] = model.num_nodes();
  state.counters["springs"] = model.num_springs();
  state.counters["time_per_spring"] = benchmark::Counter(
      static_cast<double>(model.num_springs()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_SpringForcePass(benchmark::State& state) {
  const Model& model = PassObject(static_cast<int>(state.range(0)));
  PassScene scene(model);
  for (auto _ : state) {
    scene.evaluator.SetForces(scene.positions, scene.velocities, 1e-3, &scene.out);
    benchmark::DoNotOptimize(scene.out.data());
  }
  Count(state, model);
}
BENCHMARK(BM_SpringForcePass)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

void BM_SpringStiffnessProduct(benchmark::State& state) {
  const Model& model = PassObject(static_cast<int>(state.range(0)));
  PassScene scene(model);
  scene.evaluator.Linearize(scene.positions, GeometricStiffness::kDropCompression);
  for (auto _ : state) {
    scene.evaluator.ApplyStiffness(scene.velocities, &scene.out);
    benchmark::DoNotOptimize(scene.out.data());
  }
  Count(state, model);
}
BENCHMARK(BM_SpringStiffnessProduct)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace msm_sim::core
