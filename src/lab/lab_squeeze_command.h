#pragma once
// msm_lab squeeze: an object between two rigid flat plates closing on it
// (core::RunSqueezeExperiment).

#include <ostream>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// Builds the object --shape names (GraspBody) and squeezes it. Writes a table, or one JSON
/// object whose `profile` holds [approach_m, force_N, contact_radius_m] rows and `area` the
/// contact areas (m^2) of the same rows. Returns 0, or 1 with one line on `err` if a lattice
/// cell turned inside out (no force is printed then); throws std::invalid_argument for bad
/// input (an approach that makes the plates meet among it), std::runtime_error if a step is
/// rejected.
int RunSqueeze(const LabArguments& arguments, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
