// The self-calibration block of model files (model_file.h, format version 2 on): what a random
// lattice's correction was and what it was measured for (docs/physics.md §2.2), so that a loaded
// model says how it was calibrated and is not measured again.

#include "model/model_file_self_calibration.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "model/model_file_layout.h"
#include "model/model_file_spring_law.h"

namespace msm_sim::core::model_file {
namespace {

using binary_file::GetF64;
using binary_file::GetU32;
using binary_file::GetU64;
using binary_file::PutF64;
using binary_file::PutU32;
using binary_file::PutU64;
using L = SelfCalibrationLayout;
using Conditions = SelfCalibrationConditions;

static_assert(Packed({{L::kPresent, kU32Bytes},
                      {L::kLattice, kU32Bytes},
                      {L::kStiffnessLaw, kU32Bytes},
                      {L::kSpringLaw, kU32Bytes},
                      {L::kIsotropicDispersion, kU32Bytes},
                      {L::kBlockCells, kU32Bytes},
                      {L::kSeed, binary_file::kU64Bytes},
                      {L::kSpacing, kF64Bytes},
                      {L::kPoisson, kF64Bytes},
                      {L::kMinDistance, kF64Bytes},
                      {L::kMaxDistance, kF64Bytes},
                      {L::kStiffnessFactor, kF64Bytes},
                      {L::kDispersionFraction, kF64Bytes},
                      {L::kMeasuredYoungs, kF64Bytes},
                      {L::kMeasuredPoisson, kF64Bytes},
                      {L::kMeasurements, kU32Bytes}},
                     L::kBytes),
              "self-calibration fields must tile the block");

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  binary_file::Fail("model file", path, "self-calibration block: " + problem);
}

// The file holds one (alpha, beta), the model's: conditions of another power law cannot be saved.
void RequireTheModelsPowerLaw(const Conditions& conditions, const Model& model) {
  if (conditions.spring_law != SpringLaw::kPower) return;
  const PowerSpringLaw& law = model.power_spring_law();
  if (model.spring_law() != SpringLaw::kPower || conditions.power_law.alpha != law.alpha ||
      conditions.power_law.beta != law.beta) {
    throw std::runtime_error(
        "SaveModel: the self-calibration was measured with a power law other than the model's");
  }
}

void PutConditions(const Conditions& conditions, unsigned char* record) {
  PutU32(conditions.lattice, record + L::kLattice);
  PutU32(conditions.stiffness_law, record + L::kStiffnessLaw);
  PutU32(SpringLawCode(conditions.spring_law), record + L::kSpringLaw);
  PutU32(conditions.isotropic_dispersion ? 1 : 0, record + L::kIsotropicDispersion);
  PutU32(static_cast<std::uint32_t>(conditions.block_cells), record + L::kBlockCells);
  PutU64(conditions.seed, record + L::kSeed);
  PutF64(conditions.spacing, record + L::kSpacing);
  PutF64(conditions.poisson, record + L::kPoisson);
  PutF64(conditions.min_distance, record + L::kMinDistance);
  PutF64(conditions.max_distance, record + L::kMaxDistance);
}

// The conditions' spring law: a power law only in a power-law model, with its alpha and beta.
void GetSpringLaw(std::uint32_t code, std::uint32_t version, const ModelSpringLaw& model_law,
                  const std::string& path, Conditions* conditions) {
  conditions->spring_law = SpringLawFromCode(code, version, path, "self-calibration block: ");
  if (conditions->spring_law != SpringLaw::kPower) return;
  if (model_law.law != SpringLaw::kPower) {
    Fail(path, "spring law code 2 (power) but the model's springs are not power-law");
  }
  conditions->power_law = model_law.power;
}

// The codes and flags, each one the format knows.
Conditions GetCodes(const unsigned char* record, std::uint32_t version,
                    const ModelSpringLaw& model_law, const std::string& path) {
  Conditions conditions;
  conditions.lattice = GetU32(record + L::kLattice);
  conditions.stiffness_law = GetU32(record + L::kStiffnessLaw);
  const std::uint32_t law = GetU32(record + L::kSpringLaw);
  const std::uint32_t isotropic = GetU32(record + L::kIsotropicDispersion);
  const std::uint32_t cells = GetU32(record + L::kBlockCells);
  if (conditions.lattice != Conditions::kRandomLattice) {
    Fail(path, "unknown lattice code " + std::to_string(conditions.lattice));
  }
  if (conditions.stiffness_law != Conditions::kUniformStiffness &&
      conditions.stiffness_law != Conditions::kInverseSquareStiffness) {
    Fail(path, "unknown stiffness law code " + std::to_string(conditions.stiffness_law));
  }
  if (isotropic > 1) Fail(path, "isotropic dispersion flag " + std::to_string(isotropic));
  if (cells < 1 || cells > static_cast<std::uint32_t>(std::numeric_limits<int>::max())) {
    Fail(path, "representative block of " + std::to_string(cells) + " cells");
  }
  GetSpringLaw(law, version, model_law, path, &conditions);
  conditions.isotropic_dispersion = isotropic == 1;
  conditions.block_cells = static_cast<int>(cells);
  conditions.seed = GetU64(record + L::kSeed);
  return conditions;
}

std::string Str(double value) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << value;
  return out.str();
}

bool Positive(double value) { return std::isfinite(value) && value > 0.0; }

// The conditions' and the correction's doubles, validated.
void GetValues(const unsigned char* record, double model_q, const std::string& path,
               SelfCalibration* calibration) {
  Conditions& conditions = calibration->conditions;
  conditions.spacing = GetF64(record + L::kSpacing);
  conditions.poisson = GetF64(record + L::kPoisson);
  conditions.min_distance = GetF64(record + L::kMinDistance);
  conditions.max_distance = GetF64(record + L::kMaxDistance);
  calibration->stiffness_factor = GetF64(record + L::kStiffnessFactor);
  calibration->dispersion_fraction = GetF64(record + L::kDispersionFraction);
  calibration->measured_youngs = GetF64(record + L::kMeasuredYoungs);
  calibration->measured_poisson = GetF64(record + L::kMeasuredPoisson);
  if (!Positive(conditions.spacing) || !(conditions.poisson > -1.0 && conditions.poisson < 0.5) ||
      !Positive(conditions.min_distance) || !std::isfinite(conditions.max_distance) ||
      !(conditions.min_distance < conditions.max_distance)) {
    Fail(path, "conditions spacing " + Str(conditions.spacing) + ", nu " + Str(conditions.poisson) +
                   ", minL " + Str(conditions.min_distance) + ", maxL " +
                   Str(conditions.max_distance) +
                   " (need spacing > 0, nu in (-1, 0.5), 0 < minL < maxL)");
  }
  if (!Positive(calibration->stiffness_factor) || calibration->dispersion_fraction != model_q ||
      !std::isfinite(calibration->measured_youngs) ||
      !std::isfinite(calibration->measured_poisson)) {
    Fail(path, "stiffness factor " + Str(calibration->stiffness_factor) + ", q " +
                   Str(calibration->dispersion_fraction) + " (the model's q is " + Str(model_q) +
                   "), measured E " + Str(calibration->measured_youngs) + " and nu " +
                   Str(calibration->measured_poisson) +
                   " (need a finite factor > 0, the model's q and finite readings)");
  }
}

}  // namespace

void WriteSelfCalibration(const Model& model, binary_file::AtomicFileWriter* out) {
  unsigned char record[L::kBytes] = {};
  if (const std::optional<SelfCalibration>& calibration = model.self_calibration()) {
    RequireTheModelsPowerLaw(calibration->conditions, model);
    PutU32(1, record + L::kPresent);
    PutConditions(calibration->conditions, record);
    PutF64(calibration->stiffness_factor, record + L::kStiffnessFactor);
    PutF64(calibration->dispersion_fraction, record + L::kDispersionFraction);
    PutF64(calibration->measured_youngs, record + L::kMeasuredYoungs);
    PutF64(calibration->measured_poisson, record + L::kMeasuredPoisson);
    PutU32(static_cast<std::uint32_t>(calibration->measurements), record + L::kMeasurements);
  }
  out->Append(record, sizeof record);
}

std::optional<SelfCalibration> ReadSelfCalibration(binary_file::HashingFileReader& file,
                                                   std::uint32_t version,
                                                   double model_dispersion_fraction,
                                                   const ModelSpringLaw& model_law,
                                                   const std::string& path) {
  unsigned char record[L::kBytes];
  file.Read(record, sizeof record);
  const std::uint32_t present = GetU32(record + L::kPresent);
  if (present == 0) return std::nullopt;
  if (present != 1) Fail(path, "presence flag " + std::to_string(present) + " (0 or 1)");
  SelfCalibration calibration;
  calibration.conditions = GetCodes(record, version, model_law, path);
  GetValues(record, model_dispersion_fraction, path, &calibration);
  const std::uint32_t measurements = GetU32(record + L::kMeasurements);
  if (measurements > 1000) Fail(path, std::to_string(measurements) + " measurements");
  calibration.measurements = static_cast<int>(measurements);
  return calibration;
}

}  // namespace msm_sim::core::model_file
