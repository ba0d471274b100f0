#include "object_builder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::ros_interface {
namespace {

// Where a half-space clamp holds a box object's face: the clamp's plane, in the object's frame,
// is one of the box's faces and the held side is outside it (the body in front). The face must
// lie half a spacing beyond the outer node layer (whole cells along its normal) so that the
// anchors sit half a spring out (docs/physics.md §2.1 "Face anchors").
enum class FaceFit { kNotAFace, kFace, kFaceWithoutWholeCells };

struct ClampFace {
  FaceFit fit = FaceFit::kNotAFace;
  core::AnchoredPlane plane;  ///< object frame, outward normal (kFace only)
};

ClampFace FaceOfClamp(const ObjectConfig& config, const ClampConfig& clamp, double spacing) {
  ClampFace face;
  if (clamp.is_box || config.model != core::LatticeKind::kCubic ||
      config.shape.kind != core::BodyShape::Kind::kBox || !(spacing > 0.0)) {
    return face;
  }
  const Eigen::Vector3d point = config.pose.inverse() * clamp.point;
  const Eigen::Vector3d held_normal =
      (config.pose.linear().transpose() * clamp.normal).normalized();
  const Eigen::Vector3d half = 0.5 * config.shape.size;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {-1.0, 1.0}) {
      // The face at side * half[axis], outward normal side * e_axis, held from outside.
      if (-side * held_normal[axis] < 1.0 - 1e-9) continue;
      if (std::abs(point[axis] - side * half[axis]) > 1e-6 * spacing) continue;
      const double cells = config.shape.size[axis] / spacing;
      if (std::abs(cells - std::round(cells)) > 1e-6) {
        face.fit = FaceFit::kFaceWithoutWholeCells;
        return face;
      }
      face.fit = FaceFit::kFace;
      face.plane.point = Eigen::Vector3d::Zero();
      face.plane.point[axis] = side * half[axis];
      face.plane.normal = Eigen::Vector3d::Zero();
      face.plane.normal[axis] = side;
      return face;
    }
  }
  return face;
}

// The recipe of the object's model in its own frame. Cubic and random lattices fill the shape's
// solid; Baudet's bricks fill the box [0, size] (the shape is a box), centred like the solid, and
// a target node count divides the solid's volume whichever lattice fills it. Random lattices take
// the recipe's minL 0.8, maxL 1.9 and inverse-square stiffness, and self-calibrate with
// self_calibrate (docs/physics.md §2.2). A half-space clamp on a face of a cubic box anchors that
// face (FaceOfClamp).
core::BodyRecipe ObjectRecipe(const ObjectConfig& config, const core::Material& material,
                              std::shared_ptr<const core::SolidMesh> solid) {
  core::BodyRecipe recipe(material);
  recipe.lattice_kind = config.model;
  if (config.model == core::LatticeKind::kBaudet) {
    recipe.box_size = config.shape.size;
    recipe.centre_box = true;
    recipe.target_volume = solid->volume();
  } else {
    recipe.solid = std::move(solid);
  }
  recipe.lattice = config.lattice;
  recipe.target_nodes = config.target_nodes;
  recipe.antialias = config.antialias;
  recipe.surface = config.surface;
  recipe.seed = config.seed;
  recipe.random_self_calibrate = config.self_calibrate;
  for (const ClampConfig& clamp : config.clamps) {
    const ClampFace face = FaceOfClamp(config, clamp, core::RecipeSpacing(recipe));
    if (face.fit == FaceFit::kFace) recipe.surface.anchored_planes.push_back(face.plane);
  }
  return recipe;
}

// The recipe's model in the world frame.
std::shared_ptr<const core::Model> PlacedModel(const ObjectConfig& config,
                                               const core::BodyRecipe& recipe) {
  return std::make_shared<const core::Model>(
      core::TransformedModel(core::BuildModel(recipe), config.pose));
}

// The object's clamps; a clamp that holds no node is refused at its own parameter. A face clamp
// holds the face's anchors (and whatever nodes lie behind its plane).
void AddClamps(const ObjectConfig& config, double spacing, const std::string& path,
               BuiltObject* object) {
  for (std::size_t c = 0; c < config.clamps.size(); ++c) {
    const ClampConfig& clamp = config.clamps[c];
    std::vector<core::NodeIndex> nodes =
        clamp.is_box ? core::NodesInBox(*object->model, clamp.min, clamp.max)
                     : core::NodesInHalfSpace(*object->model, clamp.point, clamp.normal);
    const ClampFace face = FaceOfClamp(config, clamp, spacing);
    if (face.fit == FaceFit::kFace) {
      // The face itself (the clamp's plane may sit up to 1e-6 spacings off it), in the world.
      const core::AnchoredPlane world_face{config.pose * face.plane.point,
                                           config.pose.linear() * face.plane.normal};
      const std::vector<core::NodeIndex> anchors = core::AnchorNodes(*object->model, world_face);
      nodes.insert(nodes.end(), anchors.begin(), anchors.end());
      std::sort(nodes.begin(), nodes.end());
      nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    }
    if (nodes.empty()) {
      const std::string hint =
          face.fit == FaceFit::kFaceWithoutWholeCells
              ? " (its plane is a face of the box, but the box is not a whole number of spacings "
                "across it, so the face cannot be anchored: make that size a multiple of the "
                "spacing, or move the plane half a spacing inside to hold the outer node layer)"
              : "";
      throw ConfigError("parameter " + path + "/clamps[" + std::to_string(c) + "]: clamp '" +
                        clamp.name + "' holds no node of object '" + config.name + "'" + hint);
    }
    object->clamps.emplace_back(clamp.name, std::move(nodes));
  }
}

}  // namespace

std::shared_ptr<const core::Model> BuildObjectModel(
    const ObjectConfig& config, const core::Material& material,
    const std::optional<core::SelfCalibration>& measured) {
  core::BodyRecipe recipe = ObjectRecipe(
      config, material, std::make_shared<const core::SolidMesh>(core::MakeBodySolid(config.shape)));
  recipe.random_calibration = measured;
  return PlacedModel(config, recipe);
}

BuiltObject BuildObject(const ObjectConfig& config, const std::string& path) {
  try {
    const core::Material material =
        core::Material::FromYoungsPoisson(config.youngs, config.poisson, config.density);
    const auto solid = std::make_shared<const core::SolidMesh>(core::MakeBodySolid(config.shape));
    const core::BodyRecipe recipe = ObjectRecipe(config, material, solid);
    BuiltObject object;
    object.model = PlacedModel(config, recipe);
    if (!config.visual_mesh_path.empty()) {
      core::MeshImportOptions options;
      options.scale = config.visual_scale;
      object.surface = core::ImportTriangleMesh(config.visual_mesh_path, options).mesh;
    } else {
      object.surface = solid->surface();
    }
    object.surface.vertices = config.pose * object.surface.vertices;
    AddClamps(config, core::RecipeSpacing(recipe), path, &object);
    return object;
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError("parameter " + path + " (object '" + config.name + "'): " + e.what());
  }
}

}  // namespace msm_sim::ros_interface
