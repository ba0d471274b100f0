// Google Benchmarks of the mesh path (issue "Any mesh in": a closed mesh of several thousand
// triangles into a ~12k-node model in under 2 s), and of skinning, which runs every frame.
#include <cmath>
#include <string>

#include <benchmark/benchmark.h>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/surface_skin.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"

namespace msm_sim::core {
namespace {

const Material kSilicone = Material::FromYoungsPoisson(1e5, 0.45, 1100.0);
const std::string kBean = std::string(MSM_SIM_MESH_DIR) + "/soft_bean.obj";  // 5,120 triangles
constexpr double kTargetNodes = 12000.0;

// From the file to the calibrated model: import, inside tests, exact-clipping anti-aliasing.
void BM_BuildCubicFromMesh12k(benchmark::State& state) {
  for (auto _ : state) {
    const SolidMesh solid = ImportSolidMesh(kBean);
    MeshCubicLatticeOptions options;
    options.lattice.spacing = std::cbrt(solid.volume() / kTargetNodes);
    options.antialias = state.range(0) != 0;
    const Model model = BuildCubicLatticeInSolid(kSilicone, solid, options);
    state.counters["triangles"] = solid.surface().num_triangles();
    state.counters["nodes"] = model.num_nodes();
    state.counters["springs"] = model.num_springs();
  }
}
BENCHMARK(BM_BuildCubicFromMesh12k)->Arg(1)->Arg(0)->ArgName("antialias")->Unit(benchmark::kSecond);

void BM_BuildRandomFromMesh12k(benchmark::State& state) {
  for (auto _ : state) {
    const SolidMesh solid = ImportSolidMesh(kBean);
    RandomLatticeOptions options;
    options.lattice.spacing = std::cbrt(solid.volume() / kTargetNodes);
    options.max_distance = 1.9;
    const Model model = BuildRandomLatticeInSolid(kSilicone, solid, options);
    state.counters["nodes"] = model.num_nodes();
    state.counters["springs"] = model.num_springs();
  }
}
BENCHMARK(BM_BuildRandomFromMesh12k)->Unit(benchmark::kSecond);

// Embedding the bean's own surface in its 12k-node model, and one frame of skinning.
void BM_Skin12k(benchmark::State& state) {
  const SolidMesh solid = ImportSolidMesh(kBean);
  MeshCubicLatticeOptions options;
  options.lattice.spacing = std::cbrt(solid.volume() / kTargetNodes);
  const Model model = BuildCubicLatticeInSolid(kSilicone, solid, options);
  const bool embed = state.range(0) != 0;
  const SurfaceSkin skin = SurfaceSkin::Embed(model, solid.surface());
  for (auto _ : state) {
    if (embed) {
      benchmark::DoNotOptimize(SurfaceSkin::Embed(model, solid.surface()).num_vertices());
    } else {
      const Eigen::Matrix3Xd vertices = skin.DeformedVertices(model.rest_positions());
      benchmark::DoNotOptimize(skin.DeformedNormals(vertices).data());
    }
  }
  state.counters["vertices"] = skin.num_vertices();
}
BENCHMARK(BM_Skin12k)->Arg(1)->Arg(0)->ArgName("embed")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace msm_sim::core
