#pragma once
// `msm_lab material`: Young's modulus from a datasheet's Shore hardness (issue "Hardness →
// modulus", docs/materials.md).

#include <ostream>

#include "lab_arguments.h"

namespace msm_sim::lab {

/// Writes E with the conversion used, its validity range and its expected uncertainty: a table,
/// or one JSON object with exactly command, shore_a (the Shore A reading or the 00 reading's
/// equivalent by the comparison table; null below it), shore_00 (null for a Shore A input),
/// youngs (Pa), poisson and shear_modulus (null without --poisson), conversion, valid_range
/// ({scale, min, max}) and uncertainty. Returns 0. Throws std::out_of_range (exit 1) for a
/// reading outside the conversion's range, std::invalid_argument for a Poisson's ratio outside
/// (-1, 0.5).
int RunMaterial(const LabArguments& arguments, std::ostream& out);

}  // namespace msm_sim::lab
