#pragma once

#include <optional>
#include <ostream>

#include <Eigen/Core>

#include "lab_arguments.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/model/model.h"

namespace msm_sim::lab {

/// The body a lab model fills: the --size box [0, size] or the solid bounded by --mesh.
struct LabBody {
  std::optional<core::SolidMesh> solid;  ///< --mesh only
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  double volume = 0.0;  ///< m^3
};

/// Loads the body. move_to_origin translates a mesh so that its bounding box starts at the
/// origin, the frame the experiments expect. Throws core::MeshImportError for a bad mesh file.
LabBody LoadLabBody(const ModelArguments& arguments, bool move_to_origin);

/// Builds the model the arguments describe in the body. Throws std::invalid_argument for an
/// invalid material, geometry or option combination, with a message meant for the user.
core::Model BuildLabModel(const ModelArguments& arguments, const LabBody& body);

/// Runs the command and writes its table (or one JSON object with arguments.json) to `out`.
/// Returns the process exit code: 0 on success, 1 if the experiment failed (e.g. the solver did
/// not converge; the reason is written to `err`). Throws std::invalid_argument for bad input.
int RunLabCommand(const LabArguments& arguments, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
