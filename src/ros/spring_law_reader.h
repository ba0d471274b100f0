#pragma once
// An object's spring law (README "msm_sim_node", docs/materials.md): `spring` and the fitted
// power law's `tensile_law` (docs/physics.md §4.1), on the object or on the material it names.

#include <string>

#include <xmlrpcpp/XmlRpcValue.h>

#include "msm_sim/lattice/lattice_options.h"

namespace msm_sim::ros_interface {

/// A ~materials entry an object names, and its parameter path ("~materials/<name>").
struct NamedMaterial {
  XmlRpc::XmlRpcValue* entry = nullptr;  ///< nullptr: the object names none
  std::string path;
};

/// Sets lattice->spring_law (and power_law for kPower) from the object at `path`:
///  - `spring: linear | nonlinear | power`; without `spring`, power when the object or its
///    material has a tensile_law, else linear;
///  - `tensile_law: {alpha: A, beta: B}` (rms_error allowed and ignored, as `msm_lab fit
///    --tensile` writes it) on the object, else on its material, gives the power law's
///    parameters: alpha finite, beta finite and >= 0;
///  - `spring: power` without a tensile_law fails at <path>/spring naming the missing key; an
///    object's own tensile_law with `spring: linear | nonlinear` fails at <path>/tensile_law (the
///    law would not be used); a material's tensile_law is ignored by those laws.
/// Throws ConfigError naming the parameter.
void ReadSpringLaw(XmlRpc::XmlRpcValue& object, const NamedMaterial& material,
                   const std::string& path, core::LatticeOptions* lattice);

}  // namespace msm_sim::ros_interface
