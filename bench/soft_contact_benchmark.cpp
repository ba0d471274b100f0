// Google Benchmark of soft-soft contact (issue 62): one World step of two of the node's default
// blocks (config/default.yaml: 8 x 6 x 3 cm, cubic at 5 mm, 1,152 nodes each, Ecoflex 00-30
// E = 100 kPa, nu = 0.49, rho = 1070, dampers 2e-4 s, friction 0.6, explicit, one thread, 1 ms
// steps), the lower one clamped at its bottom layer on the ground as the node clamps it, the
// other resting either on top of it (every node of the lower face in pair contact) or on the
// ground beside it (no pair contact). The stacked step should cost no more than about twice the
// apart one: the pair contacts' cost should follow the nodes in contact (docs/design/
// soft-contact-cost.md). Compare the two interleaved:
// --benchmark_filter=SoftContact --benchmark_repetitions=5
// --benchmark_enable_random_interleaving=true
#include <algorithm>
#include <memory>

#include <benchmark/benchmark.h>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

// The node's default object (src/ros/object_builder.cpp on config/default.yaml) at its pose,
// resting on z = 0; built once.
std::shared_ptr<const Model> DefaultBlock() {
  static const std::shared_ptr<const Model> block = [] {
    BodyRecipe recipe(Material::FromYoungsPoisson(1e5, 0.49, 1070.0));
    BodyShape shape;
    shape.size = Eigen::Vector3d(0.08, 0.06, 0.03);
    recipe.solid = std::make_shared<const SolidMesh>(MakeBodySolid(shape));
    recipe.lattice.spacing = 0.005;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.015);
    return std::make_shared<const Model>(TransformedModel(BuildModel(recipe), pose));
  }();
  return block;
}

// Moves the body by `offset` (m).
void Shift(World* world, int body, const Eigen::Vector3d& offset) {
  State state = world->state(body);
  state.positions.colwise() += offset;
  world->SetState(body, state);
}

// The highest top of a body's collision spheres (m).
double HighestSphereTop(const World& world, int body) {
  const BorderNodes& border = world.border(body);
  double top = -1e300;
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    top = std::max(top, world.state(body).positions(2, border.nodes[k]) + border.radii[k]);
  }
  return top;
}

// The two default blocks on the ground, the lower one clamped as the node's table_clamp does;
// the other on top of it (its lowest collision spheres just touching the lower block's highest),
// or on the ground 4 cm beside it. Settled for 0.3 s.
World TwoDefaultBlocks(bool stacked) {
  WorldOptions world_options;
  world_options.threads = 1;
  world_options.record_contact_points = true;  // as the node records them
  World world(world_options);
  BodyOptions options;
  options.damping_beta = 2e-4;
  options.friction = 0.6;
  const int lower = world.AddBody("lower", DefaultBlock(), options);
  world.AddKinematicGroup(
      lower, KinematicGroup{"table_clamp",
                            NodesInHalfSpace(world.model(lower), Eigen::Vector3d(0, 0, 0.005),
                                             Eigen::Vector3d::UnitZ()),
                            {}});
  const int upper = world.AddBody("upper", DefaultBlock(), options);
  const double lift = LowestSphereBottom(world.state(upper).positions, world.border(upper));
  Collider ground;
  ground.name = "ground";
  ground.friction = 0.6;
  world.AddCollider(ground);
  if (stacked) {
    Shift(&world, upper, Eigen::Vector3d(0.0, 0.0, HighestSphereTop(world, lower) - lift));
  } else {
    Shift(&world, upper, Eigen::Vector3d(0.12, 0.0, -lift));
  }
  for (int settle = 0; settle < 300; ++settle) world.Step(1e-3);
  return world;
}

void BM_SoftContactStep(benchmark::State& state) {
  World world = TwoDefaultBlocks(state.range(0) != 0);
  StepReport report;
  int refined = 0;
  for (auto _ : state) {
    report = world.Step(1e-3);
    benchmark::DoNotOptimize(report.accepted);
    refined += report.refined_because.empty() ? 0 : 1;
  }
  state.counters["substeps"] = report.substeps;
  state.counters["refinement"] = report.substep_refinement;
  state.counters["refined_steps"] = refined;
  state.counters["microcollisions"] = report.microcollisions;
}
// Argument: 1 stacked, 0 apart.
BENCHMARK(BM_SoftContactStep)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

}  // namespace
}  // namespace msm_sim::core
