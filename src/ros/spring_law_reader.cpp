#include "spring_law_reader.h"

#include <optional>
#include <set>
#include <string>

#include "parameter_tree.h"

namespace msm_sim::ros_interface {
namespace {

using XmlRpc::XmlRpcValue;

// The keys of a tensile_law, as `msm_lab fit --tensile` writes them (rms_error is its fit's).
const std::set<std::string> kTensileLawKeys = {"alpha", "beta", "rms_error"};

// parent/tensile_law's alpha and beta, checked, if parent has one.
std::optional<core::PowerSpringLaw> ReadTensileLaw(XmlRpcValue& parent,
                                                   const std::string& parent_path) {
  if (!param::Has(parent, "tensile_law")) return std::nullopt;
  XmlRpcValue& law = parent["tensile_law"];
  const std::string path = parent_path + "/tensile_law";
  param::KnownKeys(law, kTensileLawKeys, path);
  for (const char* key : {"alpha", "beta"}) {
    if (!param::Has(law, key)) {
      param::Fail(path + "/" + key, "missing (the power law's parameters, docs/physics.md 4.1)");
    }
  }
  core::PowerSpringLaw power;
  power.alpha = param::Number(law, "alpha", 1.0, path);
  power.beta = param::NonNegative(law, "beta", 0.0, path);
  return power;
}

}  // namespace

void ReadSpringLaw(XmlRpcValue& object, const NamedMaterial& material, const std::string& path,
                   core::LatticeOptions* lattice) {
  const std::optional<core::PowerSpringLaw> own = ReadTensileLaw(object, path);
  const std::optional<core::PowerSpringLaw> fitted =
      own ? own : (material.entry ? ReadTensileLaw(*material.entry, material.path) : std::nullopt);
  const std::string name = param::Text(object, "spring", fitted ? "power" : "linear", path);
  if (!core::ParseSpringLaw(name, &lattice->spring_law)) {
    param::FailNotOneOf(name, {"linear", "nonlinear", "power"}, path + "/spring");
  }
  if (lattice->spring_law != core::SpringLaw::kPower) {
    if (own) {
      param::Fail(path + "/tensile_law",
                  "applies to spring: power, but spring is " + name + " (drop one of them)");
    }
    return;
  }
  if (!fitted) {
    param::Fail(path + "/spring",
                "power needs tensile_law: {alpha: A, beta: B} on the object or its material "
                "(msm_lab fit --tensile writes it)");
  }
  lattice->power_law = *fitted;
}

}  // namespace msm_sim::ros_interface
