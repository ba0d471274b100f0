#pragma once

#include <ostream>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// Runs the command and writes its table (or one JSON object with arguments.json) to `out`.
/// Returns the process exit code: 0 on success, 1 if the experiment failed (e.g. the solver did
/// not converge; the reason is written to `err`). Throws std::invalid_argument for bad input.
/// The models come from lab_model.h (BuildLabModel), the shared report lines from lab_report.h.
int RunLabCommand(const LabArguments& arguments, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
