#pragma once
// Model files as bytes, for the model-file tests (test_model_file*.cpp): little-endian fields
// read and written in place, the trailing checksum recomputed so that a test hands LoadModel a
// file whose only defect is the one it planted, and a fixture with a temporary directory.
#include <sys/stat.h>
#include <sys/types.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/model/model_file.h"

namespace msm_sim::core {

using Bytes = std::vector<unsigned char>;

/// The trailing FNV-1a 64 checksum of every format version (model_file.h).
constexpr std::size_t kChecksumBytes = 8;

inline std::uint32_t GetU32(const Bytes& bytes, std::size_t offset) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= std::uint32_t{bytes[offset + i]} << (8 * i);
  return value;
}
// The writes are bounds-checked: an edit past the end of a file is the test's own error.
inline void PutU32(Bytes* bytes, std::size_t offset, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes->at(offset + i) = static_cast<unsigned char>(value >> (8 * i));
}
inline void PutU64(Bytes* bytes, std::size_t offset, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes->at(offset + i) = static_cast<unsigned char>(value >> (8 * i));
}
inline double GetF64(const Bytes& bytes, std::size_t offset) {
  std::uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= std::uint64_t{bytes[offset + i]} << (8 * i);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
inline void PutF64(Bytes* bytes, std::size_t offset, double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  PutU64(bytes, offset, bits);
}

/// Recomputes the trailing checksum.
inline void Reseal(Bytes* bytes) {
  std::uint64_t hash = 14695981039346656037ULL;
  for (std::size_t i = 0; i + kChecksumBytes < bytes->size(); ++i) {
    hash = (hash ^ (*bytes)[i]) * 1099511628211ULL;
  }
  PutU64(bytes, bytes->size() - kChecksumBytes, hash);
}

inline Bytes ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
inline void WriteBytes(const std::string& path, const unsigned char* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  ASSERT_TRUE(out.good());
}
inline void WriteBytes(const std::string& path, const Bytes& bytes) {
  WriteBytes(path, bytes.data(), bytes.size());
}

/// A test with its own temporary directory, removed afterwards.
class ModelFileDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "msm_model_file_XXXXXX";
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  /// The file SaveModel writes for `model` (as saved.msm).
  Bytes Saved(const Model& model) {
    const std::string path = Path("saved.msm");
    SaveModel(model, path);
    return ReadBytes(path);
  }
  /// LoadModel of `bytes` as they are (written to edited.msm).
  Model Loaded(const Bytes& bytes) {
    const std::string path = Path("edited.msm");
    WriteBytes(path, bytes);
    return LoadModel(path);
  }
  /// LoadModel's message for `bytes` (written to edited.msm); fails the test unless it throws
  /// std::runtime_error with a one-line message.
  std::string LoadError(const Bytes& bytes) {
    try {
      Loaded(bytes);
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      return e.what();
    }
    ADD_FAILURE() << "LoadModel accepted the file";
    return "";
  }

  std::string dir_;
};

}  // namespace msm_sim::core

// Expects `text` to contain `part`, printing `text` if it does not.
#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)
