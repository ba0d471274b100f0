// Deterministic mutation fuzzing of the readers of user files: small valid files (a cube as ascii
// and binary STL, OBJ, OFF, ascii and binary PLY, glTF, glb, and a model file) damaged by byte
// flips, truncation, header counts inflated to huge values and appended garbage. Each mutant is
// read in a forked child limited to 1 GB of address space and 5 s: it must load or be refused
// with the reader's error, never end by a signal (a crash, an abort, the alarm).
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <new>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "forked_run.h"
#include "mesh_files.h"
#include "model/binary_file.h"
#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_file.h"

namespace msm_sim::core {
namespace {

constexpr int kMutantsPerFile = 250;
constexpr std::uint64_t kAddressSpaceBytes = std::uint64_t{1} << 30;
constexpr unsigned kAlarmSeconds = 5;
// Exit codes of the child.
constexpr int kLoaded = 0;
constexpr int kRefused = 1;

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A small model file written by the package's own writer.
std::string ModelFileBytes() {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.2, 0.2, 0.2);
  options.lattice.spacing = 0.1;
  const std::string path = ::testing::TempDir() + "fuzz_base.msm";
  SaveModel(BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), options), path);
  return ReadBytes(path);
}

// Numbers a header could declare that no small file can back: 32-bit edges, OutOfMemory.off's.
const char* const kHugeDecimals[] = {"4294967295",          "4294967296",           "2147483647",
                                     "353535235358",        "18446744073709551615", "1000000000",
                                     "99999999999999999999"};
const std::uint32_t kHugeWords[] = {0xffffffffu, 0x7fffffffu, 0x80000000u, 0x10000000u,
                                    0x80000000u + 12};  // + 12: the cube STL's count, wrapped

// Replaces a decimal number (or, 1 in 2, a 32-bit word) near the start of the file by a huge
// value: the counts of text and binary headers.
void InflateCount(std::mt19937& rng, std::string* bytes) {
  const std::size_t window = std::min<std::size_t>(bytes->size(), 1024);
  std::vector<std::size_t> numbers;
  for (std::size_t i = 0; i < window; ++i) {
    const bool digit = std::isdigit(static_cast<unsigned char>((*bytes)[i])) != 0;
    if (digit && (i == 0 || !std::isdigit(static_cast<unsigned char>((*bytes)[i - 1])))) {
      numbers.push_back(i);
    }
  }
  if (!numbers.empty() && rng() % 2 == 0) {
    const std::size_t start = numbers[rng() % numbers.size()];
    std::size_t end = start;
    while (end < bytes->size() && std::isdigit(static_cast<unsigned char>((*bytes)[end]))) ++end;
    bytes->replace(start, end - start, kHugeDecimals[rng() % std::size(kHugeDecimals)]);
    return;
  }
  if (bytes->size() < 4) return;
  const std::size_t offset = 4 * (rng() % (std::min<std::size_t>(bytes->size(), 128) / 4));
  const std::uint32_t word = kHugeWords[rng() % std::size(kHugeWords)];
  for (int i = 0; i < 4; ++i) (*bytes)[offset + i] = static_cast<char>(word >> (8 * i));
}

// One mutant of `base`: the mutation is picked by `index` so that every kind gets its share.
std::string Mutate(const std::string& base, int index, std::mt19937& rng) {
  std::string bytes = base;
  switch (index % 4) {
    case 0: {  // flip 1 to 8 bits or bytes
      const int flips = 1 + static_cast<int>(rng() % 8);
      for (int f = 0; f < flips; ++f) {
        char& byte = bytes[rng() % bytes.size()];
        byte = rng() % 2 ? static_cast<char>(byte ^ (1 << (rng() % 8))) : static_cast<char>(rng());
      }
      break;
    }
    case 1:  // truncate (to at least one byte: the empty file has its own test)
      bytes.resize(1 + rng() % (bytes.size() - 1));
      break;
    case 2:
      InflateCount(rng, &bytes);
      break;
    default: {  // append garbage: random bytes, or the file's own tail again
      const std::size_t extra = 1 + rng() % 4096;
      if (rng() % 2) {
        for (std::size_t i = 0; i < extra; ++i) bytes += static_cast<char>(rng());
      } else {
        bytes += base.substr(base.size() - std::min(extra, base.size()));
      }
    }
  }
  return bytes;
}

// Model files end with a checksum; half the mutants get a valid one so that the values are
// validated rather than just the checksum.
void ResignModelFile(std::string* bytes) {
  using binary_file::kChecksumBytes;
  if (bytes->size() < kChecksumBytes) return;
  const std::size_t body = bytes->size() - kChecksumBytes;
  const std::uint64_t hash = binary_file::Fnv1a(
      binary_file::kFnvOffsetBasis, reinterpret_cast<const unsigned char*>(bytes->data()), body);
  binary_file::PutU64(hash, reinterpret_cast<unsigned char*>(&(*bytes)[body]));
}

// Reads the file at `path` as a mesh or a model file; the child's exit code.
int ReadFile(const std::string& path, bool model) {
  try {
    if (model) {
      LoadModel(path);
    } else {
      ImportTriangleMesh(path);
    }
    return kLoaded;
  } catch (const MeshImportError&) {
    return model ? testing::kUnexpectedException : kRefused;
  } catch (const std::bad_alloc&) {
    return testing::kUnexpectedException;
  } catch (const std::runtime_error&) {
    return model ? kRefused : testing::kUnexpectedException;
  }
}

struct FuzzStats {
  int mutants = 0, loaded = 0, refused = 0, failed = 0;
  double worst_seconds = 0, worst_rss_mb = 0;
  std::string slowest, largest;
};

TEST(MeshFuzz, DamagedFilesLoadOrAreRefusedWithoutASignal) {
  std::vector<testing::MeshFile> bases = testing::CubeFiles();
  bases.push_back({"msm", ModelFileBytes()});
  std::mt19937 rng(20240615);
  FuzzStats stats;
  for (std::size_t b = 0; b < bases.size(); ++b) {
    const bool model = bases[b].extension == "msm";
    const std::string path = ::testing::TempDir() + "fuzz_mutant." + bases[b].extension;
    for (int m = 0; m < kMutantsPerFile; ++m) {
      std::string bytes = Mutate(bases[b].bytes, m, rng);
      if (model && rng() % 2) ResignModelFile(&bytes);
      std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
      const testing::ChildRun run = testing::RunInChild([&] { return ReadFile(path, model); },
                                                        kAddressSpaceBytes, kAlarmSeconds);
      const std::string name =
          "base " + std::to_string(b) + " (" + bases[b].extension + ") mutant " + std::to_string(m);
      ++stats.mutants;
      const bool ok = run.exited && (run.exit_code == kLoaded || run.exit_code == kRefused);
      if (!ok && ++stats.failed <= 10) {
        const std::string kept = ::testing::TempDir() + "fuzz_failure_" + std::to_string(b) + "_" +
                                 std::to_string(m) + "." + bases[b].extension;
        std::ofstream(kept, std::ios::binary) << bytes;
        ADD_FAILURE() << name << ": " << run.Describe() << " (kept as " << kept << ")";
      }
      stats.loaded += ok && run.exit_code == kLoaded;
      stats.refused += ok && run.exit_code == kRefused;
      if (run.seconds > stats.worst_seconds) {
        stats.worst_seconds = run.seconds;
        stats.slowest = name;
      }
      if (run.bounded_rss_mb() > stats.worst_rss_mb) {
        stats.worst_rss_mb = run.bounded_rss_mb();
        stats.largest = name;
      }
    }
  }
  std::printf(
      "fuzz: %d mutants of %zu files: %d loaded, %d refused, %d failed; worst time %.3f s "
      "(%s), worst peak RSS %.1f MB (%s)\n",
      stats.mutants, bases.size(), stats.loaded, stats.refused, stats.failed, stats.worst_seconds,
      stats.slowest.c_str(), stats.worst_rss_mb, stats.largest.c_str());
  EXPECT_GE(stats.mutants, 2000);
  EXPECT_EQ(stats.failed, 0);
  EXPECT_GT(stats.loaded, 0);   // the mutations leave some files readable...
  EXPECT_GT(stats.refused, 0);  // ...and damage others
}

}  // namespace
}  // namespace msm_sim::core
