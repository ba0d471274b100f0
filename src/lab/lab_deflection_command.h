#pragma once
// `msm_lab deflection`: a cantilever clamped at x = 0 and loaded at its end (thesis 3.2.6),
// against Euler-Bernoulli and optionally CalculiX.

#include <ostream>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// Builds the box, solves the loaded cantilever statically and writes the deflection profile (a
/// table, or one JSON object). Returns 0, or 1 if the solver did not converge (reason on `err`);
/// throws std::invalid_argument for bad input.
int RunDeflection(const LabArguments& arguments, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
