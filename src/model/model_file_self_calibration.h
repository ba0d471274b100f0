#pragma once
// Private to the model file code: the self-calibration block of format version 2 (model_file.h),
// a fixed-size record after the correction elements (and from version 3 the spring-law
// parameters) that holds Model::self_calibration. Kept in its own layout and functions, apart
// from the records of version 1.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "model/binary_file.h"
#include "msm_sim/material/power_spring_law.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/model.h"
#include "msm_sim/model/self_calibration.h"

namespace msm_sim::core::model_file {

/// The first format version whose files carry the block; older files have none.
inline constexpr std::uint32_t kSelfCalibrationSinceVersion = 2;

// A presence flag, then SelfCalibration's fields: the conditions, then the correction.
struct SelfCalibrationLayout {
  static constexpr std::size_t kPresent = 0;       // uint32: 0 none (the rest written 0), 1 present
  static constexpr std::size_t kLattice = 4;       // uint32 SelfCalibrationConditions::lattice
  static constexpr std::size_t kStiffnessLaw = 8;  // uint32
  static constexpr std::size_t kSpringLaw = 12;    // uint32 spring-law code
  static constexpr std::size_t kIsotropicDispersion = 16;  // uint32 0 or 1
  static constexpr std::size_t kBlockCells = 20;           // uint32
  static constexpr std::size_t kSeed = 24;                 // uint64
  static constexpr std::size_t kSpacing = 32;              // doubles from here on
  static constexpr std::size_t kPoisson = 40;
  static constexpr std::size_t kMinDistance = 48;
  static constexpr std::size_t kMaxDistance = 56;
  static constexpr std::size_t kStiffnessFactor = 64;
  static constexpr std::size_t kDispersionFraction = 72;
  static constexpr std::size_t kMeasuredYoungs = 80;
  static constexpr std::size_t kMeasuredPoisson = 88;
  static constexpr std::size_t kMeasurements = 96;  // uint32
  static constexpr std::size_t kBytes = 100;
};

/// The block's size in a file of `version`: 0 before kSelfCalibrationSinceVersion.
inline std::uint64_t SelfCalibrationBlockBytes(std::uint32_t version) {
  return version >= kSelfCalibrationSinceVersion ? SelfCalibrationLayout::kBytes : 0;
}

/// Appends the block for model.self_calibration() (absent: the flag and zeros). Conditions of the
/// power law store its code only: their alpha and beta must be the model's, which the file holds
/// (docs/physics.md §4.1); otherwise throws std::runtime_error.
void WriteSelfCalibration(const Model& model, binary_file::AtomicFileWriter* out);

/// The model's spring law as its file gives it, which a power-law block's conditions take.
struct ModelSpringLaw {
  SpringLaw law = SpringLaw::kLinear;
  PowerSpringLaw power;  ///< alpha and beta for kPower
};

/// Reads the block of a file of `version` and validates it: flag 0 or 1, known codes (power only
/// in a power-law model, whose alpha and beta the conditions then take), conditions in range
/// (spacing > 0, nu in (-1, 1/2), 0 < minL < maxL, block cells >= 1), a positive finite
/// stiffness factor and a dispersion fraction equal to the model's q. Throws std::runtime_error
/// naming `path`.
std::optional<SelfCalibration> ReadSelfCalibration(binary_file::HashingFileReader& file,
                                                   std::uint32_t version,
                                                   double model_dispersion_fraction,
                                                   const ModelSpringLaw& model_law,
                                                   const std::string& path);

}  // namespace msm_sim::core::model_file
