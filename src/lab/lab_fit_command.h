#pragma once
// `msm_lab fit`: the Young's modulus for which `msm_lab indent` on the sample's geometry
// reproduces a measured indentation curve (issue "Materials the way users know them").

#include <ostream>
#include <string>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// Reads the curve (core::ReadIndentationCurve), fits E with core::FitYoungsModulus, simulating
/// core::RunIndentationExperiment on the --size block to the curve's deepest depth, and writes a
/// table or one JSON object (youngs, poisson, hertz_youngs, residual, simulations, converged,
/// tried, nodes, deepest_depth) and, with --yaml, the material as a materials.yaml entry.
/// Returns 0, or 1 (reason on `err`) if the search did not converge; throws
/// std::invalid_argument for a bad CSV, name or geometry, std::runtime_error if the YAML file
/// cannot be written or a simulation fails.
/// With --tensile, runs RunTensileFit (lab_fit_tensile.h) instead.
int RunFit(const LabArguments& arguments, std::ostream& out, std::ostream& err);

/// Throws std::invalid_argument unless `name` is a parameter-server name (a letter, then
/// letters, digits and underscores), as a materials.yaml entry's name must be.
void CheckMaterialName(const std::string& name);

}  // namespace msm_sim::lab
