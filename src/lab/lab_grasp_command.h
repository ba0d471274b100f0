#pragma once
// msm_lab grasp: a parallel gripper closes on an object resting on the ground, holds and lifts it
// (core::RunGraspExperiment).

#include <ostream>

#include "lab_arguments.h"
#include "lab_model.h"

namespace msm_sim::lab {

/// The object --shape names (grasp and squeeze), centred on the origin (a mesh where its file
/// puts it): box and ellipsoid of --size, sphere of --radius, cylinder of --radius and --length
/// lying along y, or --mesh.
LabBody GraspBody(const LabArguments& arguments);

/// Builds the object --shape names (box and ellipsoid of --size, sphere of --radius, cylinder
/// of --radius and --length lying along y, or --mesh) and runs the grasp. Writes a table, or
/// one JSON object with exactly nodes, squeeze_force, rise, slip, held, max_node_speed,
/// energy_max, real_time_factor (and the inputs shape, friction, force_ratio, integrator).
/// Returns 0; throws std::invalid_argument for bad input, std::runtime_error if a step is
/// rejected.
int RunGrasp(const LabArguments& arguments, std::ostream& out);

}  // namespace msm_sim::lab
