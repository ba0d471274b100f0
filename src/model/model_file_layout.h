#pragma once
// Private to the model file code: the records of msm_sim model files (model_file.h) that every
// format version has, as named record layouts, checked at compile time to tile their records
// without gaps.

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <type_traits>
#include <utility>

#include "model/binary_file.h"
#include "msm_sim/model/model.h"
#include "msm_sim/model/model_file.h"

namespace msm_sim::core::model_file {

using binary_file::kChecksumBytes;
using binary_file::kF64Bytes;
using binary_file::kU32Bytes;

static_assert(sizeof(kModelFileMagic) == kModelFileMagicSize + 1, "magic is 16 bytes plus NUL");
static_assert(std::numeric_limits<double>::is_iec559, "the format stores IEEE-754 doubles");

// Record layouts (the table in model_file.h): the byte offset of every field within its record,
// and the record's size. A file is a header, N node, S spring and C correction records (counts
// in the header) and the checksum.

// Magic, format version, counts, spring-law code (uint32), then the model-wide doubles.
struct HeaderLayout {
  static constexpr std::size_t kMagic = 0;  // kModelFileMagicSize bytes
  static constexpr std::size_t kVersion = 16;
  static constexpr std::size_t kNodeCount = 20;
  static constexpr std::size_t kSpringCount = 24;
  static constexpr std::size_t kCorrectionCount = 28;
  static constexpr std::size_t kSpringLaw = 32;
  static constexpr std::size_t kYoungsModulus = 36;
  static constexpr std::size_t kPoissonRatio = 44;
  static constexpr std::size_t kDensity = 52;
  static constexpr std::size_t kDispersionFraction = 60;
  static constexpr std::size_t kVolume = 68;
  static constexpr std::size_t kCharacteristicLength = 76;
  static constexpr std::size_t kBytes = 84;
};
// Per node: rest position, mass and surface inset (doubles).
struct NodeLayout {
  static constexpr std::size_t kPosition = 0;  // x, y, z
  static constexpr std::size_t kMass = 24;
  static constexpr std::size_t kSurfaceInset = 32;  // from kSurfaceInsetSinceVersion on
  static constexpr std::size_t kBytes = 40;
};
// Format version 1's node records end before the surface inset (its nodes have none).
inline constexpr std::uint32_t kSurfaceInsetSinceVersion = 2;
inline constexpr std::size_t NodeRecordBytes(std::uint32_t version) {
  return version >= kSurfaceInsetSinceVersion ? NodeLayout::kBytes : NodeLayout::kSurfaceInset;
}
// Per spring: its two node indices (uint32), then stiffness, rest length and the two dispersion
// weights (doubles).
struct SpringLayout {
  static constexpr std::size_t kNodeA = 0;
  static constexpr std::size_t kNodeB = 4;
  static constexpr std::size_t kStiffness = 8;
  static constexpr std::size_t kRestLength = 16;
  static constexpr std::size_t kWeightA = 24;
  static constexpr std::size_t kWeightB = 32;
  static constexpr std::size_t kBytes = 40;
};
// Per Baudet correction element: its 12 edge spring indices (uint32) and coefficient (double).
struct CorrectionLayout {
  static constexpr std::size_t kEdgeCount = 12;
  static constexpr std::size_t kEdges = 0;  // kEdgeCount spring indices
  static constexpr std::size_t kCoefficient = 48;
  static constexpr std::size_t kBytes = 56;
};

// A field of a record: its offset and size.
struct Field {
  std::size_t offset;
  std::size_t bytes;
};
// True if the fields, in order, each start where the previous one ends, from offset 0 to the
// record's end: no gap, no overlap, nothing left out of the record's size.
constexpr bool Packed(std::initializer_list<Field> fields, std::size_t record_bytes) {
  std::size_t next = 0;
  for (const Field& field : fields) {
    if (field.offset != next) return false;
    next += field.bytes;
  }
  return next == record_bytes;
}

static_assert(Packed({{HeaderLayout::kMagic, kModelFileMagicSize},
                      {HeaderLayout::kVersion, kU32Bytes},
                      {HeaderLayout::kNodeCount, kU32Bytes},
                      {HeaderLayout::kSpringCount, kU32Bytes},
                      {HeaderLayout::kCorrectionCount, kU32Bytes},
                      {HeaderLayout::kSpringLaw, kU32Bytes},
                      {HeaderLayout::kYoungsModulus, kF64Bytes},
                      {HeaderLayout::kPoissonRatio, kF64Bytes},
                      {HeaderLayout::kDensity, kF64Bytes},
                      {HeaderLayout::kDispersionFraction, kF64Bytes},
                      {HeaderLayout::kVolume, kF64Bytes},
                      {HeaderLayout::kCharacteristicLength, kF64Bytes}},
                     HeaderLayout::kBytes),
              "header fields must tile the header");
static_assert(Packed({{NodeLayout::kPosition, 3 * kF64Bytes},
                      {NodeLayout::kMass, kF64Bytes},
                      {NodeLayout::kSurfaceInset, kF64Bytes}},
                     NodeLayout::kBytes),
              "node fields must tile the node record");
static_assert(Packed({{SpringLayout::kNodeA, kU32Bytes},
                      {SpringLayout::kNodeB, kU32Bytes},
                      {SpringLayout::kStiffness, kF64Bytes},
                      {SpringLayout::kRestLength, kF64Bytes},
                      {SpringLayout::kWeightA, kF64Bytes},
                      {SpringLayout::kWeightB, kF64Bytes}},
                     SpringLayout::kBytes),
              "spring fields must tile the spring record");
static_assert(Packed({{CorrectionLayout::kEdges, (CorrectionLayout::kEdgeCount * kU32Bytes)},
                      {CorrectionLayout::kCoefficient, kF64Bytes}},
                     CorrectionLayout::kBytes),
              "correction fields must tile the correction record");
using CorrectionEdges = std::array<SpringIndex, CorrectionLayout::kEdgeCount>;
static_assert(
    std::is_same_v<std::decay_t<decltype(std::declval<const Model&>().correction_edges()[0])>,
                   CorrectionEdges>,
    "a correction record holds one Model correction element");

// The smallest valid file: a header, one node (a Model has at least one) and the checksum.
constexpr std::uint64_t kMinFileBytes = HeaderLayout::kBytes + NodeRecordBytes(1) + kChecksumBytes;
// Node and spring indices are int32 in Model, so no count may exceed this.
constexpr std::uint32_t kMaxCount = static_cast<std::uint32_t>(std::numeric_limits<int>::max());

}  // namespace msm_sim::core::model_file
