#pragma once
// The lab's dynamics commands: a rigid sphere pressed into a block (issue "Real time at real
// resolution": how fast the dynamics runs, the indentation force against Hertz's) and a block
// held between two jaws (issue "real time": the grip).

#include <ostream>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// `msm_lab realtime`: wall time per simulated second (core::RunRealtimeExperiment). Writes a
/// table, or one JSON object with exactly nodes, springs, integrator, step, substeps,
/// wall_per_simulated_second, real_time_factor, peak_force. Returns 0; throws
/// std::invalid_argument for bad input, std::runtime_error if a step is rejected.
int RunRealtime(const LabArguments& arguments, std::ostream& out);

/// `msm_lab indent`: force against depth and Hertz's force (core::RunIndentationExperiment).
/// Writes a table, or one JSON object with profile ([[depth, force, hertz_force], ...]), nodes
/// and seconds (simulated). Returns 0; throws as RunRealtime.
int RunIndent(const LabArguments& arguments, std::ostream& out);

/// `msm_lab grip`: a block squeezed between two rigid jaws and lifted, mu from the measured
/// normal force (core::RunGripExperiment). Writes a table, or one JSON object with exactly
/// ratio, integrator, nodes, weight, normal_force, lift_normal_force, mu, slip, max_slip,
/// seconds_lifted, held. Returns 0; throws as RunRealtime.
int RunGrip(const LabArguments& arguments, std::ostream& out);

}  // namespace msm_sim::lab
