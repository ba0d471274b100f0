// The spring law in model files (model_file.h): its code, and from format version 3 the power
// law's alpha and beta (docs/physics.md §4.1), so that a fitted material's model saves and loads
// with its law.

#include "model/model_file_spring_law.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "model/model_file_layout.h"

namespace msm_sim::core::model_file {
namespace {

using binary_file::GetF64;
using binary_file::PutF64;
using L = SpringLawParametersLayout;

static_assert(Packed({{L::kAlpha, kF64Bytes}, {L::kBeta, kF64Bytes}}, L::kBytes),
              "spring-law parameter fields must tile the record");

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  binary_file::Fail("model file", path, problem);
}

std::string Str(double value) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << value;
  return out.str();
}

// The (alpha, beta) that the linear and carrier laws are (Model::power_spring_law).
PowerSpringLaw OwnParameters(SpringLaw law) {
  return PowerSpringLaw{law == SpringLaw::kLinear ? 1.0 : -1.0, 0.0};
}

}  // namespace

std::uint32_t SpringLawCode(SpringLaw law) {
  switch (law) {
    case SpringLaw::kLinear:
      return kLinearLawCode;
    case SpringLaw::kNonlinear:
      return kNonlinearLawCode;
    case SpringLaw::kPower:
      return kPowerLawCode;
  }
  return kLinearLawCode;  // unreachable: every law is listed
}

SpringLaw SpringLawFromCode(std::uint32_t code, std::uint32_t version, const std::string& path,
                            const std::string& where) {
  if (code == kLinearLawCode) return SpringLaw::kLinear;
  if (code == kNonlinearLawCode) return SpringLaw::kNonlinear;
  if (code == kPowerLawCode && version >= kSpringLawParametersSinceVersion) {
    return SpringLaw::kPower;
  }
  if (code == kPowerLawCode) {
    Fail(path, where + "spring law code 2 (power) in a format version " + std::to_string(version) +
                   " file, which has no alpha and beta");
  }
  Fail(path, where + "unknown spring law code " + std::to_string(code));
}

void WriteSpringLawParameters(const Model& model, binary_file::AtomicFileWriter* out) {
  unsigned char record[L::kBytes];
  PutF64(model.power_spring_law().alpha, record + L::kAlpha);
  PutF64(model.power_spring_law().beta, record + L::kBeta);
  out->Append(record, sizeof record);
}

PowerSpringLaw ReadSpringLawParameters(binary_file::HashingFileReader& file, SpringLaw law,
                                       const std::string& path) {
  unsigned char record[L::kBytes];
  file.Read(record, sizeof record);
  const PowerSpringLaw parameters{GetF64(record + L::kAlpha), GetF64(record + L::kBeta)};
  const std::string values =
      "spring-law parameters alpha " + Str(parameters.alpha) + ", beta " + Str(parameters.beta);
  if (law == SpringLaw::kPower) {
    if (!std::isfinite(parameters.alpha) || !std::isfinite(parameters.beta) ||
        !(parameters.beta >= 0.0)) {
      Fail(path, values + " (need a finite alpha and a finite beta >= 0)");
    }
    return parameters;
  }
  const PowerSpringLaw own = OwnParameters(law);
  if (parameters.alpha != own.alpha || parameters.beta != own.beta) {
    Fail(path, values + " but the header's law is " +
                   (law == SpringLaw::kLinear ? "linear (1, 0)" : "nonlinear (-1, 0)"));
  }
  return parameters;
}

}  // namespace msm_sim::core::model_file
