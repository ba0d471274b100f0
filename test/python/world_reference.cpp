// The scene test/python/scene.py builds from Python, built and stepped here by the C++ World
// alone: a cube of silicone-like material dropped on the ground while a sphere presses down.
// Usage: msm_world_reference explicit|implicit SPACING STEPS OUT
// Writes the final node positions to OUT as (nodes, 3) doubles, row-major, native byte order,
// and prints the wall-clock seconds the steps took (bench/python_step_benchmark.py reads them).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/model/model_transform.h"

namespace {

using msm_sim::core::Collider;
using msm_sim::core::ColliderShape;

// The values of test/python/scene.py: change both together.
std::shared_ptr<const msm_sim::core::Model> Cube(double spacing) {
  msm_sim::core::BodyShape shape;
  shape.kind = msm_sim::core::BodyShape::Kind::kBox;
  shape.size = Eigen::Vector3d::Constant(0.04);
  msm_sim::core::BodyRecipe recipe(msm_sim::core::Material::FromYoungsPoisson(5e4, 0.3, 1000.0));
  recipe.solid =
      std::make_shared<const msm_sim::core::SolidMesh>(msm_sim::core::MakeBodySolid(shape));
  recipe.lattice.spacing = spacing;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.021);
  return std::make_shared<const msm_sim::core::Model>(
      msm_sim::core::TransformedModel(msm_sim::core::BuildModel(recipe), pose));
}

void AddColliders(msm_sim::core::World* world) {
  Collider ground;
  ground.name = "ground";
  world->AddCollider(ground);
  Collider finger;
  finger.name = "finger";
  finger.shape = ColliderShape::Sphere(0.01);
  finger.pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.052);
  finger.linear_velocity = Eigen::Vector3d(0.0, 0.0, -0.05);
  world->AddCollider(finger);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: msm_world_reference explicit|implicit SPACING STEPS OUT\n";
    return 2;
  }
  msm_sim::core::WorldOptions options;
  if (!msm_sim::core::ParseIntegrator(argv[1], &options.integrator)) {
    std::cerr << "msm_world_reference: unknown integrator " << argv[1] << "\n";
    return 2;
  }
  msm_sim::core::World world(options);
  msm_sim::core::BodyOptions body;
  body.damping_beta = 0.001;
  world.AddBody("cube", Cube(std::stod(argv[2])), body);
  AddColliders(&world);
  const int steps = std::stoi(argv[3]);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) world.Step(1e-3);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Eigen::MatrixX3d positions = world.state(0).positions.transpose();
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = positions;
  std::ofstream out(argv[4], std::ios::binary);
  out.write(reinterpret_cast<const char*>(rows.data()),
            static_cast<std::streamsize>(sizeof(double) * rows.size()));
  std::printf("%.9f\n", seconds);
  return out ? 0 : 1;
}
