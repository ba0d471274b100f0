#pragma once
// The World's private state (src/dynamics/world_state.h) with small lattice blocks, for the
// tests of its collaborators.

#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "dynamics/world_state.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_transform.h"

namespace msm_sim::core::internal {

/// A 10 cm node-centred cubic block of 2.5 cm spacing (4 x 4 x 4 nodes), its lowest node at
/// `corner`.
inline std::shared_ptr<const Model> SmallBlock(const Eigen::Vector3d& corner) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(0.1);
  lattice_options.lattice.spacing = 0.025;
  const Model model =
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), lattice_options);
  const Eigen::Vector3d lowest = model.rest_positions().rowwise().minCoeff();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = corner - lowest;
  return std::make_shared<Model>(TransformedModel(model, pose));
}

/// Adds a body as World::AddBody does (no friction pairs set), its Step records sized.
inline Body& AddBody(WorldState* world, const std::string& name, std::shared_ptr<const Model> model,
                     const BodyOptions& options = {}) {
  world->bodies.emplace_back(name, std::move(model), options, world->options);
  Body& body = world->bodies.back();
  body.pair_friction.assign(world->colliders.size(), -1.0);
  body.impulses.assign(world->colliders.size(), ImpulseSum{});
  return body;
}

/// The lowest z of the body's nodes (m).
inline double LowestZ(const Body& body) { return body.state.positions.row(2).minCoeff(); }

}  // namespace msm_sim::core::internal
