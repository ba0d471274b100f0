#pragma once

#include <cstdint>
#include <string>

#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// Binary model files (".msm"): a built Model saved once and reloaded at every start, so that a
/// large lattice is not rebuilt (random sequential addition, stiffness calibration) each time.
///
/// Format version 3, every integer and IEEE-754 double little-endian, no padding:
///
///   offset  size  field
///   0       16    magic kModelFileMagic
///   16      4     uint32 format version (kModelFileVersion)
///   20      4     uint32 node count N (1 .. 2^31 - 1)
///   24      4     uint32 spring count S (0 .. 2^31 - 1)
///   28      4     uint32 correction element count C (0 .. 2^31 - 1)
///   32      4     uint32 spring law: 0 = linear, 1 = nonlinear (carrier), 2 = power (version 3 on)
///   36      48    double E (Pa), nu, density (kg/m^3), dispersion fraction q, volume (m^3),
///                 characteristic length (m)
///   84      40 N  per node: double x, y, z (m), mass (kg), surface inset (m)
///           40 S  per spring: uint32 node a, uint32 node b, double stiffness (N/m),
///                 rest length (m), dispersion weight at a, dispersion weight at b
///           56 C  per correction element: 12 x uint32 spring index, double coefficient (N/m)
///           16    spring-law parameters (version 3 on; Model::power_spring_law): double alpha,
///                 beta of docs/physics.md §4.1 (for the linear and carrier laws their own
///                 (1, 0) and (-1, 0))
///           100   self-calibration block (version 2 on; Model::self_calibration), offsets
///                 within the block: 0 uint32 present (0: none, the rest written 0; 1), 4 uint32
///                 lattice code (1 random), 8 uint32 stiffness law (0 uniform, 1 inverse
///                 square), 12 uint32 spring law code (2, power, only in a power-law model, whose
///                 alpha and beta it was measured with), 16 uint32 isotropic dispersion (0, 1),
///                 20 uint32 representative block cells, 24 uint64 calibration seed, 32 double
///                 spacing l (m), nu, minL / l, maxL / l, stiffness factor, dispersion fraction
///                 (the model's q), measured E (Pa), measured nu, 96 uint32 measurements
///   end-8   8     uint64 FNV-1a 64 of every byte before it
///
/// Version 2 is version 3 without the spring-law parameters (and so without the power law);
/// version 1 is version 2 without the surface insets (32-byte node records, read as insets of 0)
/// and without the self-calibration block. LoadModel reads all three.
///
/// Rest lengths are derived from the node positions when the file is loaded; the stored ones only
/// guard against a platform computing them differently.
inline constexpr char kModelFileMagic[] = "\x89MSMSIMMODEL\r\n\x1a\n";
inline constexpr int kModelFileMagicSize = 16;
inline constexpr std::uint32_t kModelFileVersion = 3;
/// The oldest format version LoadModel reads.
inline constexpr std::uint32_t kOldestModelFileVersion = 1;

/// Writes `model` to `path` in the format above. The file is written next to `path` under a
/// temporary name and renamed over `path` only when complete and flushed to disk, so a crash or a
/// full disk never leaves a half-written model behind (an existing file at `path` survives a
/// failed save). POSIX only (open/fsync/rename).
///
/// Precondition: none beyond a valid Model (every Model satisfies its invariants).
/// Throws std::runtime_error, one line naming `path`, if the file cannot be created, written,
/// flushed or renamed; the temporary file is removed in that case. Also throws, writing nothing,
/// for a self-calibration measured with a power law other than the model's (the file holds one
/// alpha and beta).
void SaveModel(const Model& model, const std::string& path);

/// Reads a model written by SaveModel. The model is rebuilt through ModelBuilder, so every
/// invariant of Model holds for the result whatever the file contains.
///
/// Precondition: none; any file may be passed. A foreign, truncated, corrupt or malicious file
/// never crashes, hangs or allocates more memory than its own size warrants: counts are checked
/// against the file size before anything is allocated and the checksum before any value is used.
/// Throws std::runtime_error with one line naming `path` and the problem: cannot open, not a
/// regular file, bad magic, format version outside [kOldestModelFileVersion, kModelFileVersion],
/// truncated or over-long, checksum mismatch, or an invalid value (index out of range, self-loop,
/// non-finite or non-positive value, inadmissible material, rest length that does not match the
/// node positions, spring-law parameters or a self-calibration block that are not ones SaveModel
/// writes).
Model LoadModel(const std::string& path);

}  // namespace msm_sim::core
