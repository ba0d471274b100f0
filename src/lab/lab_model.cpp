#include "lab_model.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/material/material.h"
#include "msm_sim/material/spring_law.h"

namespace msm_sim::lab {

LabBody LoadLabBody(const ModelArguments& arguments, bool move_to_origin) {
  LabBody body;
  if (arguments.mesh.empty()) {
    body.max = arguments.size;
    body.volume = arguments.size.prod();
    return body;
  }
  core::MeshImportOptions options;
  options.scale = arguments.scale;
  core::SolidMesh solid = core::ImportSolidMesh(arguments.mesh, options);
  if (move_to_origin) {
    solid = core::TransformedSolid(solid, Eigen::Matrix3d::Identity(), -solid.min_corner());
  }
  body.min = solid.min_corner();
  body.max = solid.max_corner();
  body.volume = solid.volume();
  body.solid = std::make_shared<const core::SolidMesh>(std::move(solid));
  return body;
}

namespace {

// --spring, and for power its --alpha and --beta (docs/physics.md §4.1), which apply to it only.
void SetSpringLaw(const ModelArguments& arguments, core::LatticeOptions* lattice) {
  if (!core::ParseSpringLaw(arguments.spring, &lattice->spring_law)) {
    throw std::invalid_argument("unknown spring law '" + arguments.spring +
                                "' (expected linear, nonlinear or power)");
  }
  const bool has_parameters = arguments.alpha || arguments.beta;
  if (lattice->spring_law != core::SpringLaw::kPower) {
    if (has_parameters) throw std::invalid_argument("--alpha and --beta apply to --spring power");
    return;
  }
  if (!arguments.alpha || !arguments.beta) {
    throw std::invalid_argument(
        "--spring power needs --alpha and --beta (the law's parameters, docs/physics.md 4.1; "
        "fit --tensile prints them)");
  }
  if (!std::isfinite(*arguments.alpha) || !std::isfinite(*arguments.beta) ||
      !(*arguments.beta >= 0.0)) {
    throw std::invalid_argument("--alpha must be finite and --beta finite and >= 0, got " +
                                std::to_string(*arguments.alpha) + " and " +
                                std::to_string(*arguments.beta));
  }
  lattice->power_law = core::PowerSpringLaw{*arguments.alpha, *arguments.beta};
}

}  // namespace

core::BodyRecipe LabRecipe(const ModelArguments& arguments, const LabBody& body) {
  core::BodyRecipe recipe(
      core::Material::FromYoungsPoisson(arguments.youngs, arguments.poisson, arguments.density));
  SetSpringLaw(arguments, &recipe.lattice);
  if (!core::ParseLatticeKind(arguments.model, &recipe.lattice_kind)) {
    throw std::invalid_argument("unknown model '" + arguments.model +
                                "' (expected cubic, random or baudet)");
  }
  recipe.solid = body.solid;
  recipe.box_size = arguments.size;
  recipe.lattice.spacing = arguments.spacing;
  recipe.target_nodes = arguments.target_nodes;
  if (arguments.rotate) {
    recipe.lattice.rotation_axis = arguments.rotate->head<3>();
    recipe.lattice.rotation_angle = (*arguments.rotate)[3] * M_PI / 180.0;
  }
  recipe.construction = arguments.construction == "corner" ? core::CubicConstruction::kElementCorner
                                                           : core::CubicConstruction::kNodeCentred;
  recipe.antialias = arguments.antialias;
  recipe.surface.free_face_bending = arguments.free_face_bending;
  recipe.surface.surface_dispersion = arguments.surface_dispersion;
  recipe.surface.mass_scaling = arguments.mass_scaling;
  recipe.seed = arguments.seed;
  recipe.random_min_distance = arguments.min_dist;
  recipe.random_max_distance = arguments.max_dist;
  recipe.stiffness_law = arguments.stiffness == "uniform"
                             ? core::RandomStiffnessLaw::kUniform
                             : core::RandomStiffnessLaw::kInverseSquare;
  recipe.random_self_calibrate = arguments.self_calibrate;
  return recipe;
}

core::Integrator IntegratorNamed(const std::string& name) {
  core::Integrator integrator = core::Integrator::kExplicit;
  if (core::ParseIntegrator(name, &integrator)) return integrator;
  throw std::invalid_argument("unknown integrator '" + name + "' (expected explicit or implicit)");
}

core::Model BuildLabModel(const ModelArguments& arguments, const LabBody& body) {
  return core::BuildModel(LabRecipe(arguments, body));
}

}  // namespace msm_sim::lab
