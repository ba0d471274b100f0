#pragma once
// The lab's bodies and models: command-line arguments turned into the core's BodyRecipe.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "lab_arguments.h"
#include "msm_sim/dynamics/integrator.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/model/model.h"

namespace msm_sim::lab {

/// The body a lab model fills: the --size box [0, size] or the solid bounded by --mesh.
struct LabBody {
  std::shared_ptr<const core::SolidMesh> solid;  ///< --mesh only
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  double volume = 0.0;  ///< m^3
};

/// Loads the body. move_to_origin translates a mesh so that its bounding box starts at the
/// origin, the frame the experiments expect. Throws core::MeshImportError for a bad mesh file.
LabBody LoadLabBody(const ModelArguments& arguments, bool move_to_origin);

/// The recipe of the model the arguments describe in the body. Throws std::invalid_argument for
/// an invalid material, spring law or model name, with a message meant for the user.
core::BodyRecipe LabRecipe(const ModelArguments& arguments, const LabBody& body);

/// The integrator an --integrator argument names. Throws std::invalid_argument, with a message
/// meant for the user, for any other name than explicit and implicit.
core::Integrator IntegratorNamed(const std::string& name);

/// Builds the model the arguments describe in the body: core::BuildModel(LabRecipe(...)).
/// Throws std::invalid_argument for an invalid material, geometry or option combination, with a
/// message meant for the user.
core::Model BuildLabModel(const ModelArguments& arguments, const LabBody& body);

}  // namespace msm_sim::lab
