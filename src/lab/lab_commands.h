#pragma once

#include <ostream>

#include "lab_arguments.h"
#include "msm_sim/core/model.h"

namespace msm_sim::lab {

/// Builds the model the arguments describe. Throws std::invalid_argument for an invalid
/// material, geometry or option combination, with a message meant for the user.
core::Model BuildLabModel(const ModelArguments& arguments);

/// Runs the command and writes its table (or one JSON object with arguments.json) to `out`.
/// Returns the process exit code: 0 on success, 1 if the experiment failed (e.g. the solver did
/// not converge; the reason is written to `err`). Throws std::invalid_argument for bad input.
int RunLabCommand(const LabArguments& arguments, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
