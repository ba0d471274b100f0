#pragma once
// `msm_lab deflection --reference calculix`: the lab's cantilever solved by CalculiX (C3D8I
// hexahedra, core::RunCalculixCantilever) beside the lattice, on the same box, material and force.

#include <optional>
#include <ostream>

#include "lab_arguments.h"
#include "lab_report.h"
#include "msm_sim/experiments/calculix_reference.h"

namespace msm_sim::lab {

/// Seconds after which the lab gives up on ccx (the default mesh solves in about a second).
constexpr double kReferenceTimeoutSeconds = 600.0;

struct LabReference {
  core::CalculixCantilever box;
  core::CalculixCantileverResult result;
};

/// The reference's box: --size, --youngs, --poisson and --force, clamped on x = 0 and loaded on
/// x = L. Its mesh is --reference-elements, or 10 x 10 elements across and along x at least 40
/// and enough that no element is more than twice as long as the section's thinner element side,
/// up to core::kMaxCalculixElements in all.
core::CalculixCantilever ReferenceBox(const LabArguments& arguments);

/// Runs the reference --reference asks for; std::nullopt without --reference. Throws what
/// core::RunCalculixCantilever throws (std::invalid_argument for a box or mesh it refuses,
/// std::runtime_error when ccx is missing or fails).
std::optional<LabReference> RunLabReference(const LabArguments& arguments);

/// Adds reference, reference_elements [nx, ny, nz], reference_tip_deflection (m, mean -u_z of
/// the end face's nodes), reference_profile ([x, deflection] pairs in m from the clamped face)
/// and reference_seconds.
void AddReferenceJson(const LabReference& reference, Json* json);

/// The table's line: the reference's end-face deflection and the lattice's tip against it.
void PrintReference(const LabReference& reference, double end_face_deflection, std::ostream& out);

}  // namespace msm_sim::lab
