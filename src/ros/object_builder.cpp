#include "object_builder.h"

#include <cmath>
#include <stdexcept>

#include "msm_sim/build/baudet_lattice_builder.h"
#include "msm_sim/build/mesh_lattice_builder.h"
#include "msm_sim/build/random_lattice_builder.h"
#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::ros_interface {
namespace {

// The object's solid in its own frame.
core::SolidMesh Solid(const ShapeConfig& shape) {
  if (shape.type == "box") return core::SolidMesh(core::MakeBoxMesh(shape.size));
  if (shape.type == "sphere") return core::SolidMesh(core::MakeIcosphereMesh(shape.radius, 4));
  if (shape.type == "cylinder") {
    return core::SolidMesh(core::MakeCylinderMesh(shape.radius, shape.length, 64));
  }
  core::MeshImportOptions options;
  options.scale = shape.scale;
  return core::ImportSolidMesh(shape.mesh_path, options);
}

core::SpringLaw Law(const std::string& name) {
  core::SpringLaw law = core::SpringLaw::kLinear;
  core::ParseSpringLaw(name, &law);
  return law;
}

core::Model BuildInObjectFrame(const ObjectConfig& config, const core::SolidMesh& solid,
                               const core::Material& material) {
  const double spacing =
      config.target_nodes > 0 ? std::cbrt(solid.volume() / config.target_nodes) : config.spacing;
  if (config.model == "cubic") {
    core::MeshCubicLatticeOptions options;
    options.spacing = spacing;
    options.antialias = config.antialias;
    options.spring_law = Law(config.spring);
    return core::BuildCubicLatticeInSolid(material, solid, options);
  }
  if (config.model == "random") {
    core::RandomLatticeOptions options;
    options.spacing = spacing;
    options.max_distance = 1.9;
    options.seed = config.seed;
    options.spring_law = Law(config.spring);
    return core::BuildRandomLatticeInSolid(material, solid, options);
  }
  // Baudet's bricks fill the box [0, size]; centre it like the other shapes.
  core::BaudetLatticeOptions options;
  options.size = config.shape.size;
  options.spacing = spacing;
  options.spring_law = Law(config.spring);
  Eigen::Isometry3d centre = Eigen::Isometry3d::Identity();
  centre.translation() = -0.5 * config.shape.size;
  return core::TransformedModel(core::BuildBaudetLattice(material, options), centre);
}

}  // namespace

std::shared_ptr<const core::Model> BuildObjectModel(const ObjectConfig& config,
                                                    const core::Material& material) {
  const core::SolidMesh solid = Solid(config.shape);
  return std::make_shared<const core::Model>(
      core::TransformedModel(BuildInObjectFrame(config, solid, material), config.pose));
}

BuiltObject BuildObject(const ObjectConfig& config, const std::string& path) {
  try {
    const core::Material material =
        core::Material::FromYoungsPoisson(config.youngs, config.poisson, config.density);
    const core::SolidMesh solid = Solid(config.shape);
    BuiltObject object;
    object.model = std::make_shared<const core::Model>(
        core::TransformedModel(BuildInObjectFrame(config, solid, material), config.pose));
    if (!config.visual_mesh_path.empty()) {
      core::MeshImportOptions options;
      options.scale = config.visual_scale;
      object.surface = core::ImportTriangleMesh(config.visual_mesh_path, options).mesh;
    } else {
      object.surface = solid.surface();
    }
    object.surface.vertices = config.pose * object.surface.vertices;
    for (const ClampConfig& clamp : config.clamps) {
      std::vector<core::NodeIndex> nodes =
          clamp.is_box ? core::NodesInBox(*object.model, clamp.min, clamp.max)
                       : core::NodesInHalfSpace(*object.model, clamp.point, clamp.normal);
      if (nodes.empty()) {
        throw std::invalid_argument("clamp '" + clamp.name + "' holds no node of the object");
      }
      object.clamps.emplace_back(clamp.name, std::move(nodes));
    }
    return object;
  } catch (const std::exception& e) {
    throw ConfigError("parameter " + path + " (object '" + config.name + "'): " + e.what());
  }
}

}  // namespace msm_sim::ros_interface
