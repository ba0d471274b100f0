#pragma once
// Private to msm_sim's binary file formats: little-endian fields, the FNV-1a 64 checksum, an
// atomic writer (temporary file, fsync, rename) that appends the checksum, and a bounds-checked
// reader that hashes what it reads. POSIX only (open/read/write/fsync/rename).
//
// Every error is a std::runtime_error of one line, "<kind> '<path>': <problem>", where `kind`
// names the format for the user (e.g. "model file").

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace msm_sim::core::binary_file {

/// Sizes of the fields on disk.
inline constexpr std::size_t kU32Bytes = 4;
inline constexpr std::size_t kU64Bytes = 8;
inline constexpr std::size_t kF64Bytes = 8;
/// The checksum every file ends with: the FNV-1a 64 of every byte before it, as a uint64.
inline constexpr std::size_t kChecksumBytes = kU64Bytes;

inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ULL;
inline constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

/// FNV-1a 64 of `size` bytes at `data`, continuing from `hash` (kFnvOffsetBasis for a start).
inline std::uint64_t Fnv1a(std::uint64_t hash, const unsigned char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * kFnvPrime;
  return hash;
}

// Explicit byte order, so files move between hosts whatever their endianness. `out` and `in`
// point at (at least) the field's size in bytes.
inline void PutU32(std::uint32_t value, unsigned char* out) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<unsigned char>(value >> (8 * i));
}
inline void PutU64(std::uint64_t value, unsigned char* out) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<unsigned char>(value >> (8 * i));
}
inline std::uint32_t GetU32(const unsigned char* in) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= static_cast<std::uint32_t>(in[i]) << (8 * i);
  return value;
}
inline std::uint64_t GetU64(const unsigned char* in) {
  std::uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value |= static_cast<std::uint64_t>(in[i]) << (8 * i);
  return value;
}
/// Doubles are stored as the uint64 of their IEEE-754 bits.
inline void PutF64(double value, unsigned char* out) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  PutU64(bits, out);
}
inline double GetF64(const unsigned char* in) {
  const std::uint64_t bits = GetU64(in);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

/// Throws std::runtime_error("<kind> '<path>': <problem>").
[[noreturn]] void Fail(const std::string& kind, const std::string& path,
                       const std::string& problem);

/// Writes through a temporary file in the destination's directory, renamed over the destination
/// by Commit(); the destructor removes the temporary file if Commit() was not reached, so a crash
/// or a full disk never leaves a half-written file under the real name.
class AtomicFileWriter {
 public:
  /// Creates the temporary file next to `path`. `kind` names the format in error messages.
  /// Throws std::runtime_error if it cannot be created (e.g. the directory does not exist).
  AtomicFileWriter(const std::string& kind, const std::string& path);
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter();

  /// Appends `size` bytes (buffered, hashed as they go to disk). Precondition: Commit() was not
  /// called. Throws std::runtime_error if a write fails.
  void Append(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    buffer_.insert(buffer_.end(), bytes, bytes + size);
    if (buffer_.size() >= kBufferBytes) Flush();
  }

  /// Appends the checksum, makes the data durable (fsync) and publishes the file under its real
  /// name. Precondition: called once. Throws std::runtime_error if any step fails; the temporary
  /// file is then removed and an existing file at the destination survives.
  void Commit();

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  void Flush();
  void WriteAll(const unsigned char* data, std::size_t size);
  [[noreturn]] void Fail(const std::string& problem) const;

  std::string kind_;
  std::string path_;
  std::string temp_path_;
  int fd_ = -1;
  bool committed_ = false;
  std::vector<unsigned char> buffer_;
  std::uint64_t hash_ = kFnvOffsetBasis;
};

/// Sequential buffered reader of a regular file that hashes every byte it hands out (unless
/// told otherwise), for files that end with a checksum.
class HashingFileReader {
 public:
  /// Opens `path` without blocking (a FIFO is rejected, not waited on). `kind` names the format
  /// in error messages. Throws std::runtime_error if it cannot be opened or is not a regular file.
  HashingFileReader(const std::string& kind, const std::string& path);
  HashingFileReader(const HashingFileReader&) = delete;
  HashingFileReader& operator=(const HashingFileReader&) = delete;
  ~HashingFileReader();

  /// The file's size when it was opened (bytes).
  std::uint64_t size() const { return size_; }
  /// FNV-1a 64 of the hashed bytes read since the start (or the last Rewind).
  std::uint64_t hash() const { return hash_; }

  /// Back to the file's first byte, with the hash restarted.
  void Rewind();

  /// Reads exactly `size` bytes into `out`, adding them to the hash if `hashed`. Precondition:
  /// the callers have checked the file is long enough, so running out means the file shrank
  /// while being read: throws std::runtime_error then, and if reading fails.
  void Read(unsigned char* out, std::size_t size, bool hashed = true) {
    while (size > 0) {
      if (begin_ == end_) Fill();
      const std::size_t n = std::min(size, end_ - begin_);
      std::memcpy(out, buffer_.data() + begin_, n);
      if (hashed) hash_ = Fnv1a(hash_, out, n);
      begin_ += n;
      out += n;
      size -= n;
    }
  }
  /// Reads (and hashes) `size` bytes, discarding them. Precondition as for Read.
  void Skip(std::uint64_t size);

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  void Fill();
  [[noreturn]] void Fail(const std::string& problem) const;

  std::string kind_;
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::vector<unsigned char> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  std::uint64_t hash_ = kFnvOffsetBasis;
};

}  // namespace msm_sim::core::binary_file
