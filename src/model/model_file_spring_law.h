#pragma once
// Private to the model file code: the spring-law codes of the header and the self-calibration
// block, and the spring-law parameters record of format version 3 (model_file.h), which holds
// Model::power_spring_law (docs/physics.md §4.1) after the correction elements.

#include <cstddef>
#include <cstdint>
#include <string>

#include "model/binary_file.h"
#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core::model_file {

/// The first format version whose files carry the record and may use the power-law code.
inline constexpr std::uint32_t kSpringLawParametersSinceVersion = 3;

// Spring-law codes are part of the file format: never renumber them.
inline constexpr std::uint32_t kLinearLawCode = 0;
inline constexpr std::uint32_t kNonlinearLawCode = 1;
inline constexpr std::uint32_t kPowerLawCode = 2;

// The law's alpha and beta (doubles).
struct SpringLawParametersLayout {
  static constexpr std::size_t kAlpha = 0;
  static constexpr std::size_t kBeta = 8;
  static constexpr std::size_t kBytes = 16;
};

/// The record's size in a file of `version`: 0 before kSpringLawParametersSinceVersion.
inline std::uint64_t SpringLawParametersBytes(std::uint32_t version) {
  return version >= kSpringLawParametersSinceVersion ? SpringLawParametersLayout::kBytes : 0;
}

/// The code of `law`.
std::uint32_t SpringLawCode(SpringLaw law);

/// The law of `code` in a file of `version` (kPower from kSpringLawParametersSinceVersion on).
/// Throws std::runtime_error naming `path` and `where` ("" or "self-calibration block: ") for an
/// unknown code or a power-law code in an older file.
SpringLaw SpringLawFromCode(std::uint32_t code, std::uint32_t version, const std::string& path,
                            const std::string& where = "");

/// Appends the record: model.power_spring_law() (for kLinear (1, 0), for kNonlinear (-1, 0)).
void WriteSpringLawParameters(const Model& model, binary_file::AtomicFileWriter* out);

/// Reads the record of a model whose header gives `law` and validates it: for kPower a finite
/// alpha and a finite beta >= 0, for the other laws exactly their own (alpha, beta). Throws
/// std::runtime_error naming `path`.
PowerSpringLaw ReadSpringLawParameters(binary_file::HashingFileReader& file, SpringLaw law,
                                       const std::string& path);

}  // namespace msm_sim::core::model_file
