#include "lab_reference.h"

#include <algorithm>
#include <cmath>

namespace msm_sim::lab {

core::CalculixCantilever ReferenceBox(const LabArguments& arguments) {
  core::CalculixCantilever box;
  const Eigen::Vector3d& size = arguments.model.size;
  box.length = size.x();
  box.width = size.y();
  box.height = size.z();
  box.youngs = arguments.model.youngs;
  box.poisson = arguments.model.poisson;
  box.force = arguments.force;
  box.timeout_seconds = kReferenceTimeoutSeconds;
  if (arguments.reference_elements != Eigen::Vector3i::Zero()) {
    box.elements_x = arguments.reference_elements.x();
    box.elements_y = arguments.reference_elements.y();
    box.elements_z = arguments.reference_elements.z();
    return box;
  }
  // Ten elements across resolve the section's bending; along x, elements at most twice as long
  // as the section's thinner element side, at least 40 (40 x 10 x 10 on the 4 : 1 : 1
  // box) and at most 500 (the element limit); finer meshes along x barely move the deflection
  // (docs/design/free-face-bending.md). Invalid sizes are left to the core's checks, which say
  // what is wrong.
  box.elements_y = 10;
  box.elements_z = 10;
  const double thinnest = std::min(size.y(), size.z()) / 10.0;
  const double along = std::ceil(size.x() / (2.0 * thinnest));
  const double most = static_cast<double>(core::kMaxCalculixElements / 100);
  box.elements_x = std::isfinite(along) ? static_cast<int>(std::clamp(along, 40.0, most)) : 40;
  return box;
}

std::optional<LabReference> RunLabReference(const LabArguments& arguments) {
  if (arguments.reference.empty()) return std::nullopt;
  LabReference reference;
  reference.box = ReferenceBox(arguments);
  reference.result = core::RunCalculixCantilever(reference.box);
  return reference;
}

void AddReferenceJson(const LabReference& reference, Json* json) {
  Json profile = Json::array();
  for (const core::CalculixProfileSample& sample : reference.result.profile) {
    profile.push_back({sample.x, sample.deflection});
  }
  const core::CalculixCantilever& box = reference.box;
  (*json)["reference"] = "calculix";
  (*json)["reference_elements"] = {box.elements_x, box.elements_y, box.elements_z};
  (*json)["reference_tip_deflection"] = reference.result.end_face_deflection;
  (*json)["reference_profile"] = profile;
  (*json)["reference_seconds"] = reference.result.seconds;
}

void PrintReference(const LabReference& reference, double end_face_deflection, std::ostream& out) {
  const core::CalculixCantilever& box = reference.box;
  const double end_face = reference.result.end_face_deflection;
  out << "CalculiX C3D8I   " << box.elements_x << " x " << box.elements_y << " x " << box.elements_z
      << ", clamped face x = 0: end-face deflection " << end_face << " m (lattice end face "
      << 100.0 * (end_face_deflection / end_face - 1.0) << " %), ccx " << reference.result.seconds
      << " s\n";
}

}  // namespace msm_sim::lab
