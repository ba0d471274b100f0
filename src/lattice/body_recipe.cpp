#include "msm_sim/lattice/body_recipe.h"

#include <array>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/model/model_transform.h"

namespace msm_sim::core {
namespace {

constexpr std::array<LatticeKind, 3> kLatticeKinds = {LatticeKind::kCubic, LatticeKind::kRandom,
                                                      LatticeKind::kBaudet};

bool AntiAliasesTheBox(const BodyRecipe& recipe);

void Validate(const BodyRecipe& recipe) {
  if (recipe.solid && (recipe.lattice_kind == LatticeKind::kBaudet ||
                       recipe.construction == CubicConstruction::kElementCorner)) {
    // Worded for the lab, whose --mesh is the only way a user meets this.
    throw std::invalid_argument(
        "--mesh builds node-centred cubic or random lattices (Baudet bricks and element-corner "
        "lattices fill boxes only)");
  }
  if (recipe.solid && recipe.centre_box) {
    throw std::invalid_argument("centre_box moves a box region; a solid stays in its own frame");
  }
  if (!recipe.surface.anchored_planes.empty() &&
      (recipe.lattice_kind != LatticeKind::kCubic ||
       recipe.construction != CubicConstruction::kNodeCentred ||
       recipe.lattice.rotation_angle != 0.0)) {
    // Face anchors are built by the node-centred builders (BuildCubicLattice,
    // BuildCubicLatticeInSolid) on a lattice aligned with the body.
    throw std::invalid_argument(
        "anchored planes (face clamps) need a node-centred cubic lattice aligned with the body "
        "(not rotated)");
  }
  if (recipe.surface.free_face_bending &&
      (recipe.lattice_kind != LatticeKind::kCubic ||
       recipe.construction != CubicConstruction::kNodeCentred)) {
    throw std::invalid_argument(
        "the free faces' bending correction is for node-centred cubic lattices (the "
        "element-corner, Baudet and random lattices have their own surface)");
  }
  if (recipe.surface.surface_dispersion != 1.0 &&
      (recipe.lattice_kind != LatticeKind::kCubic ||
       recipe.construction != CubicConstruction::kNodeCentred)) {
    throw std::invalid_argument(
        "surface_dispersion is for node-centred cubic lattices (the element-corner, Baudet and "
        "random lattices have their own surface)");
  }
  if (recipe.target_nodes < 0) throw std::invalid_argument("target_nodes must be >= 0");
  if (!(recipe.target_volume >= 0.0)) throw std::invalid_argument("target_volume must be >= 0");
  if (recipe.target_nodes > kMaxBodyNodes) {
    throw std::invalid_argument("target_nodes " + std::to_string(recipe.target_nodes) +
                                " is more than the limit of " + std::to_string(kMaxBodyNodes) +
                                " nodes");
  }
}

// Refuses a spacing that would fill the region's bounding box with more than kMaxBodyNodes
// lattice sites, before a builder allocates them. Non-positive spacings are the builders' to
// report.
void CheckSiteCount(const BodyRecipe& recipe, double spacing) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) return;
  const Eigen::Vector3d extent =
      recipe.solid ? Eigen::Vector3d(recipe.solid->max_corner() - recipe.solid->min_corner())
                   : recipe.box_size;
  const double sites = (extent.array() / spacing + 1.0).prod();
  if (sites > kMaxBodyNodes) {
    std::ostringstream text;
    text << "spacing " << spacing << " m gives about " << sites << " lattice sites in a "
         << extent.x() << " x " << extent.y() << " x " << extent.z()
         << " m region, more than the limit of " << kMaxBodyNodes << " nodes; use a larger spacing";
    throw std::invalid_argument(text.str());
  }
}

RandomLatticeOptions RandomOptions(const BodyRecipe& recipe, double spacing) {
  RandomLatticeOptions options;
  options.size = recipe.box_size;
  options.lattice = recipe.lattice;
  options.lattice.spacing = spacing;
  options.seed = recipe.seed;
  options.min_distance = recipe.random_min_distance;
  options.max_distance = recipe.random_max_distance;
  options.stiffness_law = recipe.stiffness_law;
  options.self_calibrate = recipe.random_self_calibrate;
  // A correction measured for the same conditions is the one a measurement would give (it is
  // deterministic): reuse it.
  if (recipe.random_self_calibrate && recipe.random_calibration &&
      recipe.random_calibration->conditions ==
          RandomSelfCalibrationConditions(recipe.material, options)) {
    options.calibration = recipe.random_calibration;
  }
  return options;
}

Model BuildInSolid(const BodyRecipe& recipe, double spacing) {
  if (recipe.lattice_kind == LatticeKind::kRandom) {
    return BuildRandomLatticeInSolid(recipe.material, *recipe.solid,
                                     RandomOptions(recipe, spacing));
  }
  MeshCubicLatticeOptions options;
  options.lattice = recipe.lattice;
  options.lattice.spacing = spacing;
  options.antialias = recipe.antialias;
  options.surface = recipe.surface;
  return BuildCubicLatticeInSolid(recipe.material, *recipe.solid, options);
}

Model BuildCubicInBox(const BodyRecipe& recipe, double spacing) {
  CubicLatticeOptions options;
  options.size = recipe.box_size;
  options.lattice = recipe.lattice;
  options.lattice.spacing = spacing;
  options.construction = recipe.construction;
  options.surface = recipe.surface;
  return BuildCubicLattice(recipe.material, options);
}

Model BuildBaudetInBox(const BodyRecipe& recipe, double spacing) {
  BaudetLatticeOptions options;
  options.size = recipe.box_size;
  options.lattice = recipe.lattice;
  options.lattice.spacing = spacing;
  return BuildBaudetLattice(recipe.material, options);
}

// A lattice rotated against the box cuts its faces through cells: built through the box as a
// solid, those cells are weighted by the fraction inside (docs/physics.md §5), as a mesh's are.
// The box lattice keeps whole cells or none, which reads E too low on a rotated lattice
// (docs/meshes.md).
bool AntiAliasesTheBox(const BodyRecipe& recipe) {
  return recipe.antialias && recipe.lattice.rotation_angle != 0.0 &&
         recipe.construction == CubicConstruction::kNodeCentred;
}

Model BuildCubicInBoxSolid(const BodyRecipe& recipe, double spacing) {
  TriangleMesh box = MakeBoxMesh(recipe.box_size);
  box.vertices.colwise() += 0.5 * recipe.box_size;  // the box region is [0, box_size]
  BodyRecipe through_solid = recipe;
  through_solid.solid = std::make_shared<const SolidMesh>(box);
  return BuildInSolid(through_solid, spacing);
}

Model BuildInBox(const BodyRecipe& recipe, double spacing) {
  switch (recipe.lattice_kind) {
    case LatticeKind::kCubic:
      if (AntiAliasesTheBox(recipe)) return BuildCubicInBoxSolid(recipe, spacing);
      return BuildCubicInBox(recipe, spacing);
    case LatticeKind::kBaudet:
      return BuildBaudetInBox(recipe, spacing);
    case LatticeKind::kRandom:
      break;
  }
  return BuildRandomLattice(recipe.material, RandomOptions(recipe, spacing));
}

}  // namespace

bool ParseLatticeKind(const std::string& name, LatticeKind* kind) {
  for (const LatticeKind candidate : kLatticeKinds) {
    if (name == LatticeKindName(candidate)) {
      *kind = candidate;
      return true;
    }
  }
  return false;
}

const char* LatticeKindName(LatticeKind kind) {
  switch (kind) {
    case LatticeKind::kCubic:
      return "cubic";
    case LatticeKind::kRandom:
      return "random";
    case LatticeKind::kBaudet:
      return "baudet";
  }
  return "unknown";
}

const std::vector<std::string>& LatticeKindNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const LatticeKind kind : kLatticeKinds) list.emplace_back(LatticeKindName(kind));
    return list;
  }();
  return names;
}

// A target node count fixes the spacing: N = V / a^3.
double RecipeSpacing(const BodyRecipe& recipe) {
  if (recipe.target_nodes <= 0) return recipe.lattice.spacing;
  const double volume = recipe.target_volume > 0.0 ? recipe.target_volume
                        : recipe.solid             ? recipe.solid->volume()
                                                   : recipe.box_size.prod();
  return std::cbrt(volume / recipe.target_nodes);
}

Model BuildModel(const BodyRecipe& recipe) {
  Validate(recipe);
  const double spacing = RecipeSpacing(recipe);
  if (recipe.target_nodes == 0) CheckSiteCount(recipe, spacing);
  if (recipe.solid) return BuildInSolid(recipe, spacing);
  if (!recipe.centre_box) return BuildInBox(recipe, spacing);
  Eigen::Isometry3d centre = Eigen::Isometry3d::Identity();
  centre.translation() = -0.5 * recipe.box_size;
  return TransformedModel(BuildInBox(recipe, spacing), centre);
}

}  // namespace msm_sim::core
