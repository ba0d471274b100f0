#include "msm_sim/model/model_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/binary_file.h"
#include "model/model_file_layout.h"
#include "model/model_file_self_calibration.h"
#include "model/model_file_spring_law.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

using binary_file::AtomicFileWriter;
using binary_file::GetF64;
using binary_file::GetU32;
using binary_file::GetU64;
using binary_file::HashingFileReader;
using binary_file::kChecksumBytes;
using binary_file::kF64Bytes;
using binary_file::kU32Bytes;
using binary_file::PutF64;
using binary_file::PutU32;
using model_file::CorrectionEdges;
using model_file::CorrectionLayout;
using model_file::kMaxCount;
using model_file::kMinFileBytes;
using model_file::NodeLayout;
using model_file::SpringLayout;
using H = model_file::HeaderLayout;

// Names the format in every error message: "model file '<path>': <problem>".
constexpr char kFileKind[] = "model file";

std::string Str(double value) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << value;
  return out.str();
}

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  binary_file::Fail(kFileKind, path, problem);
}

bool Positive(double value) { return std::isfinite(value) && value > 0.0; }
// Dispersion weights may be 0: a face anchor's fixed end disperses nothing (AnchoredPlane).
bool NonNegative(double value) { return std::isfinite(value) && value >= 0.0; }

// --- Saving: every record is encoded at its layout's offsets, then appended whole ------

void WriteHeader(const Model& model, AtomicFileWriter* out) {
  unsigned char record[H::kBytes];
  std::memcpy(record + H::kMagic, kModelFileMagic, kModelFileMagicSize);
  PutU32(kModelFileVersion, record + H::kVersion);
  PutU32(static_cast<std::uint32_t>(model.num_nodes()), record + H::kNodeCount);
  PutU32(static_cast<std::uint32_t>(model.num_springs()), record + H::kSpringCount);
  PutU32(static_cast<std::uint32_t>(model.correction_edges().size()), record + H::kCorrectionCount);
  PutU32(model_file::SpringLawCode(model.spring_law()), record + H::kSpringLaw);
  const Material& material = model.material();
  PutF64(material.youngs_modulus(), record + H::kYoungsModulus);
  PutF64(material.poisson_ratio(), record + H::kPoissonRatio);
  PutF64(material.density(), record + H::kDensity);
  PutF64(model.dispersion_fraction(), record + H::kDispersionFraction);
  PutF64(model.volume(), record + H::kVolume);
  PutF64(model.characteristic_length(), record + H::kCharacteristicLength);
  out->Append(record, sizeof record);
}

void WriteNodes(const Model& model, AtomicFileWriter* out) {
  unsigned char record[NodeLayout::kBytes];
  for (int i = 0; i < model.num_nodes(); ++i) {
    for (int d = 0; d < 3; ++d) {
      PutF64(model.rest_positions()(d, i), record + NodeLayout::kPosition + kF64Bytes * d);
    }
    PutF64(model.masses()[i], record + NodeLayout::kMass);
    PutF64(model.surface_insets()[i], record + NodeLayout::kSurfaceInset);
    out->Append(record, sizeof record);
  }
}

void WriteSprings(const Model& model, AtomicFileWriter* out) {
  using S = SpringLayout;
  unsigned char record[S::kBytes];
  for (int s = 0; s < model.num_springs(); ++s) {
    PutU32(static_cast<std::uint32_t>(model.spring_node_a()[s]), record + S::kNodeA);
    PutU32(static_cast<std::uint32_t>(model.spring_node_b()[s]), record + S::kNodeB);
    PutF64(model.spring_stiffness()[s], record + S::kStiffness);
    PutF64(model.spring_rest_length()[s], record + S::kRestLength);
    PutF64(model.dispersion_weight_a()[s], record + S::kWeightA);
    PutF64(model.dispersion_weight_b()[s], record + S::kWeightB);
    out->Append(record, sizeof record);
  }
}

void WriteCorrections(const Model& model, AtomicFileWriter* out) {
  using C = CorrectionLayout;
  unsigned char record[C::kBytes];
  for (std::size_t e = 0; e < model.correction_edges().size(); ++e) {
    for (std::size_t j = 0; j < C::kEdgeCount; ++j) {
      PutU32(static_cast<std::uint32_t>(model.correction_edges()[e][j]),
             record + C::kEdges + kU32Bytes * j);
    }
    PutF64(model.correction_coefficients()[e], record + C::kCoefficient);
    out->Append(record, sizeof record);
  }
}

// --- Loading --------------------------------------------------------------------------------

std::string Truncated(std::uint64_t expected, std::uint64_t actual, bool at_least) {
  return "truncated (expected " + std::string(at_least ? "at least " : "") +
         std::to_string(expected) + " bytes, file has " + std::to_string(actual) + ")";
}

struct Header {
  std::uint32_t version = 0;
  std::uint32_t nodes = 0;
  std::uint32_t springs = 0;
  std::uint32_t corrections = 0;
  std::uint32_t law = 0;
};

// The file size the header's counts describe. Counts are < 2^31, so this cannot overflow 64 bits.
std::uint64_t DescribedFileBytes(const Header& header) {
  return std::uint64_t{H::kBytes} +
         std::uint64_t{model_file::NodeRecordBytes(header.version)} * header.nodes +
         std::uint64_t{SpringLayout::kBytes} * header.springs +
         std::uint64_t{CorrectionLayout::kBytes} * header.corrections +
         model_file::SpringLawParametersBytes(header.version) +
         model_file::SelfCalibrationBlockBytes(header.version) + kChecksumBytes;
}

// Checks magic, version and counts, in the order that gives the most useful message for a
// foreign, newer, truncated or padded file. Returns the header; the reader is left after the
// counts and spring law (the material is read after the checksum is verified).
Header ReadHeader(HashingFileReader& file, const std::string& path) {
  const std::uint64_t size = file.size();
  if (size == 0) Fail(path, "empty file (not an msm_sim model file)");
  unsigned char record[H::kBytes];
  const std::size_t magic_bytes =
      static_cast<std::size_t>(std::min<std::uint64_t>(size, kModelFileMagicSize));
  file.Read(record + H::kMagic, magic_bytes);
  if (std::memcmp(record + H::kMagic, kModelFileMagic, magic_bytes) != 0) {
    Fail(path, "not an msm_sim model file (bad magic)");
  }
  if (size < H::kVersion + kU32Bytes) Fail(path, Truncated(kMinFileBytes, size, true));
  file.Read(record + H::kVersion, kU32Bytes);
  Header header;
  header.version = GetU32(record + H::kVersion);
  // Before the size checks: another version may lay out its header differently.
  if (header.version < kOldestModelFileVersion || header.version > kModelFileVersion) {
    Fail(path, "written by format version " + std::to_string(header.version) +
                   ", this build reads versions " + std::to_string(kOldestModelFileVersion) +
                   " to " + std::to_string(kModelFileVersion));
  }
  if (size < kMinFileBytes) Fail(path, Truncated(kMinFileBytes, size, true));
  file.Read(record + H::kNodeCount, H::kYoungsModulus - H::kNodeCount);
  header.nodes = GetU32(record + H::kNodeCount);
  header.springs = GetU32(record + H::kSpringCount);
  header.corrections = GetU32(record + H::kCorrectionCount);
  header.law = GetU32(record + H::kSpringLaw);
  if (header.nodes == 0) Fail(path, "the model has no nodes");
  if (header.nodes > kMaxCount || header.springs > kMaxCount || header.corrections > kMaxCount) {
    Fail(path, "counts out of range (" + std::to_string(header.nodes) + " nodes, " +
                   std::to_string(header.springs) + " springs, " +
                   std::to_string(header.corrections) + " correction elements)");
  }
  // Checking the size before allocating anything bounds the memory a malicious header can make
  // us take.
  const std::uint64_t expected = DescribedFileBytes(header);
  if (size < expected) Fail(path, Truncated(expected, size, false));
  if (size > expected) {
    Fail(path, "has " + std::to_string(size) + " bytes but its header describes " +
                   std::to_string(expected) + " (trailing data)");
  }
  return header;
}

void VerifyChecksum(HashingFileReader& file, const std::string& path) {
  file.Rewind();
  file.Skip(file.size() - kChecksumBytes);
  unsigned char stored[kChecksumBytes];
  file.Read(stored, sizeof stored, /*hashed=*/false);
  if (GetU64(stored) != file.hash()) Fail(path, "checksum mismatch (file corrupt)");
}

// The header's model-wide values, validated.
struct ModelProperties {
  SpringLaw law;  // its alpha and beta (kPower) come later in the file
  Material material;
  double dispersion_fraction;
  double volume;
  double characteristic_length;
};

// Reads the header from the start of the file again, hashing it, and validates its values.
ModelProperties ReadProperties(HashingFileReader& file, const Header& header,
                               const std::string& path) {
  file.Rewind();
  file.Skip(H::kYoungsModulus);
  unsigned char record[H::kBytes];
  file.Read(record + H::kYoungsModulus, H::kBytes - H::kYoungsModulus);
  const double youngs = GetF64(record + H::kYoungsModulus);
  const double poisson = GetF64(record + H::kPoissonRatio);
  const double density = GetF64(record + H::kDensity);
  const double q = GetF64(record + H::kDispersionFraction);
  const double volume = GetF64(record + H::kVolume);
  const double characteristic_length = GetF64(record + H::kCharacteristicLength);

  const SpringLaw law = model_file::SpringLawFromCode(header.law, header.version, path);
  Material material = [&] {
    try {
      return Material::FromYoungsPoisson(youngs, poisson, density);
    } catch (const std::exception& e) {
      Fail(path, std::string("invalid material: ") + e.what());
    }
  }();
  if (!std::isfinite(q) || !(q > -0.5)) {
    Fail(path, "dispersion fraction q = " + Str(q) + " (must be finite and > -0.5)");
  }
  if (!Positive(volume) || !Positive(characteristic_length)) {
    Fail(path, "volume " + Str(volume) + " and characteristic length " +
                   Str(characteristic_length) + " must be finite and > 0");
  }
  return {law, material, q, volume, characteristic_length};
}

void ReadNodes(HashingFileReader& file, const Header& header, const std::string& path,
               ModelBuilder* builder) {
  unsigned char record[NodeLayout::kBytes] = {};  // a version-1 record leaves the inset 0
  for (std::uint32_t i = 0; i < header.nodes; ++i) {
    file.Read(record, model_file::NodeRecordBytes(header.version));
    const unsigned char* position_bytes = record + NodeLayout::kPosition;
    const Eigen::Vector3d position(GetF64(position_bytes), GetF64(position_bytes + kF64Bytes),
                                   GetF64(position_bytes + 2 * kF64Bytes));
    const double mass = GetF64(record + NodeLayout::kMass);
    const double inset = GetF64(record + NodeLayout::kSurfaceInset);
    const std::string node = "node " + std::to_string(i);
    if (!position.allFinite()) Fail(path, node + " has a non-finite position");
    if (!Positive(mass)) Fail(path, node + " has mass " + Str(mass) + " (must be finite and > 0)");
    if (!NonNegative(inset)) Fail(path, node + " has inset " + Str(inset) + " (must be >= 0)");
    builder->AddNode(position, mass, inset);  // cannot throw: its preconditions were checked
  }
}

// Returns the stored rest lengths, to compare with those the builder derives from the positions.
std::vector<double> ReadSprings(HashingFileReader& file, const Header& header,
                                const std::string& path, ModelBuilder* builder) {
  using S = SpringLayout;
  std::vector<double> stored_rest_length(header.springs);
  unsigned char record[S::kBytes];
  for (std::uint32_t s = 0; s < header.springs; ++s) {
    file.Read(record, sizeof record);
    const std::uint32_t a = GetU32(record + S::kNodeA);
    const std::uint32_t b = GetU32(record + S::kNodeB);
    const double stiffness = GetF64(record + S::kStiffness);
    const double rest_length = GetF64(record + S::kRestLength);
    const double weight_a = GetF64(record + S::kWeightA);
    const double weight_b = GetF64(record + S::kWeightB);
    const std::string spring = "spring " + std::to_string(s);
    if (a >= header.nodes || b >= header.nodes) {
      Fail(path, spring + " joins node " + std::to_string(a) + " to node " + std::to_string(b) +
                     " but the model has " + std::to_string(header.nodes) + " nodes");
    }
    if (a == b) Fail(path, spring + " joins node " + std::to_string(a) + " to itself");
    if (!Positive(stiffness) || !Positive(rest_length) || !NonNegative(weight_a) ||
        !NonNegative(weight_b)) {
      Fail(path, spring + " has stiffness " + Str(stiffness) + ", rest length " + Str(rest_length) +
                     ", dispersion weights " + Str(weight_a) + " and " + Str(weight_b) +
                     " (all must be finite, stiffness and rest length > 0, weights >= 0)");
    }
    try {
      builder->AddSpring(static_cast<NodeIndex>(a), static_cast<NodeIndex>(b), stiffness);
    } catch (const std::exception& e) {
      Fail(path, spring + ": " + e.what());
    }
    // a != b, so each call sets the weight at the intended end.
    builder->SetDispersionWeight(static_cast<SpringIndex>(s), static_cast<NodeIndex>(a), weight_a);
    builder->SetDispersionWeight(static_cast<SpringIndex>(s), static_cast<NodeIndex>(b), weight_b);
    stored_rest_length[s] = rest_length;
  }
  return stored_rest_length;
}

void ReadCorrections(HashingFileReader& file, const Header& header, const std::string& path,
                     ModelBuilder* builder) {
  using C = CorrectionLayout;
  unsigned char record[C::kBytes];
  for (std::uint32_t e = 0; e < header.corrections; ++e) {
    file.Read(record, sizeof record);
    CorrectionEdges edges;
    for (std::size_t j = 0; j < C::kEdgeCount; ++j) {
      const std::uint32_t spring = GetU32(record + C::kEdges + kU32Bytes * j);
      if (spring >= header.springs) {
        Fail(path, "correction element " + std::to_string(e) + " refers to spring " +
                       std::to_string(spring) + " but the model has " +
                       std::to_string(header.springs) + " springs");
      }
      edges[j] = static_cast<SpringIndex>(spring);
    }
    const double coefficient = GetF64(record + C::kCoefficient);
    if (!std::isfinite(coefficient)) {
      Fail(path, "correction element " + std::to_string(e) + " has a non-finite coefficient");
    }
    builder->AddCorrectionElement(edges, coefficient);
  }
}

// The second pass has hashed every byte before the checksum again: a file that changed between
// the checksum pass and this one is caught here.
void VerifyUnchanged(HashingFileReader& file, const std::string& path) {
  const std::uint64_t parsed_hash = file.hash();
  unsigned char stored[kChecksumBytes];
  file.Read(stored, sizeof stored, /*hashed=*/false);
  if (GetU64(stored) != parsed_hash) Fail(path, "changed while being read");
}

// Builds the model, then checks the stored rest lengths against those derived from the positions.
Model Assemble(const ModelBuilder& builder, const ModelProperties& properties,
               const std::vector<double>& stored_rest_length, const std::string& path) {
  Model model = [&] {
    try {
      return builder.Build(properties.volume, properties.characteristic_length);
    } catch (const std::exception& e) {
      Fail(path, e.what());
    }
  }();
  // The builder derives rest lengths from the positions; a different result than at save time
  // (another platform's sqrt or FMA contraction) would silently change every spring's force.
  for (std::size_t s = 0; s < stored_rest_length.size(); ++s) {
    const double derived = model.spring_rest_length()[s];
    if (std::abs(derived - stored_rest_length[s]) > 1e-12 * stored_rest_length[s]) {
      Fail(path, "spring " + std::to_string(s) + " has stored rest length " +
                     Str(stored_rest_length[s]) + " but its nodes are " + Str(derived) + " apart");
    }
  }
  return model;
}

}  // namespace

void SaveModel(const Model& model, const std::string& path) {
  AtomicFileWriter out(kFileKind, path);
  WriteHeader(model, &out);
  WriteNodes(model, &out);
  WriteSprings(model, &out);
  WriteCorrections(model, &out);
  model_file::WriteSpringLawParameters(model, &out);
  model_file::WriteSelfCalibration(model, &out);
  out.Commit();
}

Model LoadModel(const std::string& path) {
  HashingFileReader file(kFileKind, path);
  const Header header = ReadHeader(file, path);
  // The checksum is verified before any value is used, so that a corrupt file is reported as
  // corrupt rather than as whatever nonsense the flipped bits happen to spell.
  VerifyChecksum(file, path);
  // Then a second pass reads the values, hashing them again.
  const ModelProperties properties = ReadProperties(file, header, path);
  ModelBuilder builder(properties.material);
  builder.SetDispersionFraction(properties.dispersion_fraction);
  ReadNodes(file, header, path, &builder);
  const std::vector<double> stored_rest_length = ReadSprings(file, header, path, &builder);
  ReadCorrections(file, header, path, &builder);
  const PowerSpringLaw power_law =
      header.version >= model_file::kSpringLawParametersSinceVersion
          ? model_file::ReadSpringLawParameters(file, properties.law, path)
          : PowerSpringLaw{};
  builder.SetSpringLaw(properties.law, power_law);  // validated as it requires: cannot throw
  if (header.version >= model_file::kSelfCalibrationSinceVersion) {
    builder.SetSelfCalibration(model_file::ReadSelfCalibration(
        file, header.version, properties.dispersion_fraction, {properties.law, power_law}, path));
  }
  VerifyUnchanged(file, path);
  return Assemble(builder, properties, stored_rest_length, path);
}

}  // namespace msm_sim::core
