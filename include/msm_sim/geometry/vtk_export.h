#pragma once

#include <string>

#include "msm_sim/model/model.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core {

/// Writes `state` of `model` as a VTK XML UnstructuredGrid (.vtu, ASCII, file version 0.1) for
/// ParaView: one point per node at its current position and one VTK_LINE cell per spring, in
/// model order, with
///   PointData "mass" (kg), "displacement" (3 components, m), "velocity" (3 components, m/s);
///   CellData "stiffness" (N/m), "rest_length" (m), "strain" (current length / rest length - 1).
/// Values are written with 17 significant digits, so they read back bit-identical.
///
/// Preconditions: state.positions and state.velocities have model.num_nodes() columns and are
/// finite. Throws std::invalid_argument if not (naming the first node with a non-finite position
/// or velocity: a "nan" in the file would make it unreadable or silently wrong), and
/// std::runtime_error naming `path` if the file cannot be written. On failure a partial file may
/// remain at `path`.
void WriteVtu(const Model& model, const State& state, const std::string& path);

}  // namespace msm_sim::core
