#include "object_builder.h"

#include <stdexcept>
#include <utility>

#include "msm_sim/build/body_recipe.h"
#include "msm_sim/build/body_shape.h"
#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::ros_interface {
namespace {

// The recipe of the object's model in its own frame. Cubic and random lattices fill the shape's
// solid; Baudet's bricks fill the box [0, size] (the shape is a box), centred like the solid, and
// a target node count divides the solid's volume whichever lattice fills it. Random lattices take
// the recipe's minL 0.8, maxL 1.9 and inverse-square stiffness.
core::BodyRecipe ObjectRecipe(const ObjectConfig& config, const core::Material& material,
                              std::shared_ptr<const core::SolidMesh> solid) {
  core::BodyRecipe recipe(material);
  recipe.lattice = config.model;
  if (config.model == core::LatticeKind::kBaudet) {
    recipe.box_size = config.shape.size;
    recipe.centre_box = true;
    recipe.target_volume = solid->volume();
  } else {
    recipe.solid = std::move(solid);
  }
  recipe.spacing = config.spacing;
  recipe.target_nodes = config.target_nodes;
  recipe.spring_law = config.spring;
  recipe.antialias = config.antialias;
  recipe.free_face_bending = config.free_face_bending;
  recipe.seed = config.seed;
  return recipe;
}

// The object's model in the world frame.
std::shared_ptr<const core::Model> PlacedModel(const ObjectConfig& config,
                                               const core::Material& material,
                                               std::shared_ptr<const core::SolidMesh> solid) {
  return std::make_shared<const core::Model>(core::TransformedModel(
      core::BuildModel(ObjectRecipe(config, material, std::move(solid))), config.pose));
}

// The object's clamps; a clamp that holds no node is refused at its own parameter.
void AddClamps(const ObjectConfig& config, const std::string& path, BuiltObject* object) {
  for (std::size_t c = 0; c < config.clamps.size(); ++c) {
    const ClampConfig& clamp = config.clamps[c];
    std::vector<core::NodeIndex> nodes =
        clamp.is_box ? core::NodesInBox(*object->model, clamp.min, clamp.max)
                     : core::NodesInHalfSpace(*object->model, clamp.point, clamp.normal);
    if (nodes.empty()) {
      throw ConfigError("parameter " + path + "/clamps[" + std::to_string(c) + "]: clamp '" +
                        clamp.name + "' holds no node of object '" + config.name + "'");
    }
    object->clamps.emplace_back(clamp.name, std::move(nodes));
  }
}

}  // namespace

std::shared_ptr<const core::Model> BuildObjectModel(const ObjectConfig& config,
                                                    const core::Material& material) {
  return PlacedModel(config, material,
                     std::make_shared<const core::SolidMesh>(core::MakeBodySolid(config.shape)));
}

BuiltObject BuildObject(const ObjectConfig& config, const std::string& path) {
  try {
    const core::Material material =
        core::Material::FromYoungsPoisson(config.youngs, config.poisson, config.density);
    const auto solid = std::make_shared<const core::SolidMesh>(core::MakeBodySolid(config.shape));
    BuiltObject object;
    object.model = PlacedModel(config, material, solid);
    if (!config.visual_mesh_path.empty()) {
      core::MeshImportOptions options;
      options.scale = config.visual_scale;
      object.surface = core::ImportTriangleMesh(config.visual_mesh_path, options).mesh;
    } else {
      object.surface = solid->surface();
    }
    object.surface.vertices = config.pose * object.surface.vertices;
    AddClamps(config, path, &object);
    return object;
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError("parameter " + path + " (object '" + config.name + "'): " + e.what());
  }
}

}  // namespace msm_sim::ros_interface
