#pragma once
// `msm_lab fit --tensile`: E and the spring law of docs/physics.md §4.1 for which the lattice's
// uniaxial tension follows a measured tensile curve (issue 49).

#include <ostream>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// Reads the curve (core::ReadTensileCurve with the --strain-column, --stress-column and
/// --stress-unit choices), fits it up to --max-strain (core::FitTensileCurve at --poisson), and
/// writes a table or one JSON object (youngs, alpha, beta, rms_error, max_strain, ...), with
/// --yaml the material as a materials.yaml entry with its provenance, and with --plot a PNG of
/// the curve against the model. Returns 0, or 1 if the plot could not be drawn (reason on
/// `err`); throws std::invalid_argument for an unreadable or bad CSV (naming the line), a bad
/// name or too few points, std::runtime_error if the YAML file cannot be written.
int RunTensileFit(const LabArguments& arguments, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
