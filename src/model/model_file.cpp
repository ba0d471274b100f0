#include "msm_sim/model/model_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

static_assert(sizeof(kModelFileMagic) == kModelFileMagicSize + 1, "magic is 16 bytes plus NUL");
static_assert(std::numeric_limits<double>::is_iec559, "the format stores IEEE-754 doubles");

// Record sizes of format version 1 (see model_file.h).
constexpr std::uint64_t kHeaderBytes = 84;
constexpr std::uint64_t kNodeBytes = 32;
constexpr std::uint64_t kSpringBytes = 40;
constexpr std::uint64_t kCorrectionBytes = 56;
constexpr std::uint64_t kChecksumBytes = 8;
// The smallest valid file: a header, one node (a Model has at least one) and the checksum.
constexpr std::uint64_t kMinFileBytes = kHeaderBytes + kNodeBytes + kChecksumBytes;
// Node and spring indices are int32 in Model, so no count may exceed this.
constexpr std::uint32_t kMaxCount = static_cast<std::uint32_t>(std::numeric_limits<int>::max());

// Spring-law codes are part of the file format: never renumber them.
constexpr std::uint32_t kLinearLawCode = 0;
constexpr std::uint32_t kNonlinearLawCode = 1;

std::uint32_t SpringLawCode(SpringLaw law) {
  switch (law) {
    case SpringLaw::kLinear:
      return kLinearLawCode;
    case SpringLaw::kNonlinear:
      return kNonlinearLawCode;
  }
  throw std::logic_error("SaveModel: spring law without a file code");
}

constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ULL;
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

std::uint64_t Fnv1a(std::uint64_t hash, const unsigned char* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * kFnvPrime;
  return hash;
}

// Explicit byte order, so files move between hosts whatever their endianness.
void PutU32(std::uint32_t value, unsigned char* out) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<unsigned char>(value >> (8 * i));
}
void PutU64(std::uint64_t value, unsigned char* out) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<unsigned char>(value >> (8 * i));
}
std::uint32_t GetU32(const unsigned char* in) {
  std::uint32_t value = 0;
  for (int i = 0; i < 4; ++i) value |= static_cast<std::uint32_t>(in[i]) << (8 * i);
  return value;
}
std::uint64_t GetU64(const unsigned char* in) {
  std::uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value |= static_cast<std::uint64_t>(in[i]) << (8 * i);
  return value;
}
double GetF64(const unsigned char* in) {
  const std::uint64_t bits = GetU64(in);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::string ErrnoMessage(int error) { return std::generic_category().message(error); }

std::string Str(double value) {
  std::ostringstream out;
  out.precision(std::numeric_limits<double>::max_digits10);
  out << value;
  return out.str();
}

[[noreturn]] void Fail(const std::string& path, const std::string& problem) {
  throw std::runtime_error("model file '" + path + "': " + problem);
}

// Writes through a temporary file in the destination's directory, renamed over the destination
// by Commit(); the destructor removes the temporary file if Commit() was not reached.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::string& path) : path_(path) {
    // Process id plus a counter make the name unique among concurrent saves; O_EXCL guarantees
    // we never write into somebody else's file. Mode 0666 lets the umask decide, like fopen.
    static std::atomic<unsigned> counter{0};
    for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
      temp_path_ = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
      fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ < 0 && errno != EEXIST) {
        Fail(path_, "cannot create temporary file '" + temp_path_ + "': " + ErrnoMessage(errno));
      }
    }
    if (fd_ < 0) Fail(path_, "cannot create a temporary file next to it (all names taken)");
    buffer_.reserve(kBufferBytes);
  }
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  ~AtomicFileWriter() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(temp_path_.c_str());
  }

  void U32(std::uint32_t value) {
    unsigned char bytes[4];
    PutU32(value, bytes);
    Append(bytes, sizeof bytes);
  }
  void F64(double value) {
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    unsigned char bytes[8];
    PutU64(bits, bytes);
    Append(bytes, sizeof bytes);
  }
  void Append(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    buffer_.insert(buffer_.end(), bytes, bytes + size);
    if (buffer_.size() >= kBufferBytes) Flush();
  }

  // Appends the checksum, makes the data durable and publishes the file under its real name.
  void Commit() {
    Flush();
    unsigned char checksum[8];
    PutU64(hash_, checksum);
    WriteAll(checksum, sizeof checksum);
    // Without fsync a power cut after the rename could leave an empty file under the real name.
    if (::fsync(fd_) != 0) Fail(path_, "cannot flush to disk: " + ErrnoMessage(errno));
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) Fail(path_, "cannot close: " + ErrnoMessage(errno));
    if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
      Fail(path_, "cannot rename '" + temp_path_ + "' to it: " + ErrnoMessage(errno));
    }
    committed_ = true;
  }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  void Flush() {
    hash_ = Fnv1a(hash_, buffer_.data(), buffer_.size());
    WriteAll(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
  void WriteAll(const unsigned char* data, std::size_t size) {
    while (size > 0) {
      const ssize_t written = ::write(fd_, data, size);
      if (written < 0) {
        if (errno == EINTR) continue;
        Fail(path_, "cannot write: " + ErrnoMessage(errno));
      }
      data += written;
      size -= static_cast<std::size_t>(written);
    }
  }

  std::string path_;
  std::string temp_path_;
  int fd_ = -1;
  bool committed_ = false;
  std::vector<unsigned char> buffer_;
  std::uint64_t hash_ = kFnvOffsetBasis;
};

// Sequential buffered reader of a regular file that hashes every byte it hands out.
class HashingFileReader {
 public:
  explicit HashingFileReader(const std::string& path) : path_(path) {
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever.
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd_ < 0) Fail(path_, "cannot open: " + ErrnoMessage(errno));
    struct stat info;
    if (::fstat(fd_, &info) != 0) {
      const int error = errno;
      ::close(fd_);
      Fail(path_, "cannot stat: " + ErrnoMessage(error));
    }
    if (!S_ISREG(info.st_mode)) {
      ::close(fd_);
      Fail(path_, S_ISDIR(info.st_mode) ? "is a directory" : "not a regular file");
    }
    size_ = static_cast<std::uint64_t>(info.st_size);
    // No larger than the file: a small (or foreign) file should not cost a megabyte to reject.
    buffer_.resize(static_cast<std::size_t>(std::clamp<std::uint64_t>(size_, 1, kBufferBytes)));
  }
  HashingFileReader(const HashingFileReader&) = delete;
  HashingFileReader& operator=(const HashingFileReader&) = delete;
  ~HashingFileReader() { ::close(fd_); }

  std::uint64_t size() const { return size_; }
  std::uint64_t hash() const { return hash_; }

  void Rewind() {
    if (::lseek(fd_, 0, SEEK_SET) != 0) Fail(path_, "cannot seek: " + ErrnoMessage(errno));
    begin_ = end_ = 0;
    hash_ = kFnvOffsetBasis;
  }

  // Reads exactly `size` bytes; the callers have checked the file is long enough, so running
  // out means the file shrank while being read.
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
  void Skip(std::uint64_t size) {
    unsigned char scratch[4096];
    while (size > 0) {
      const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(size, sizeof scratch));
      Read(scratch, n);
      size -= n;
    }
  }

 private:
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  void Fill() {
    for (;;) {
      const ssize_t n = ::read(fd_, buffer_.data(), buffer_.size());
      if (n > 0) {
        begin_ = 0;
        end_ = static_cast<std::size_t>(n);
        return;
      }
      if (n == 0) Fail(path_, "truncated while being read (did the file change?)");
      if (errno != EINTR) Fail(path_, "cannot read: " + ErrnoMessage(errno));
    }
  }

  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::vector<unsigned char> buffer_;
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  std::uint64_t hash_ = kFnvOffsetBasis;
};

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

// Checks magic, version and counts, in the order that gives the most useful message for a
// foreign, newer, truncated or padded file. Returns the header; the reader is left after it.
Header ReadHeader(HashingFileReader& file, const std::string& path) {
  const std::uint64_t size = file.size();
  if (size == 0) Fail(path, "empty file (not an msm_sim model file)");
  unsigned char bytes[kHeaderBytes];
  const std::size_t magic_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(size, 16));
  file.Read(bytes, magic_bytes);
  if (std::memcmp(bytes, kModelFileMagic, magic_bytes) != 0) {
    Fail(path, "not an msm_sim model file (bad magic)");
  }
  if (size < 20) Fail(path, Truncated(kMinFileBytes, size, true));
  file.Read(bytes + 16, 4);
  Header header;
  header.version = GetU32(bytes + 16);
  // Before the size checks: another version may lay out its header differently.
  if (header.version != kModelFileVersion) {
    Fail(path, "written by format version " + std::to_string(header.version) +
                   ", this build reads version " + std::to_string(kModelFileVersion));
  }
  if (size < kMinFileBytes) Fail(path, Truncated(kMinFileBytes, size, true));
  file.Read(bytes + 20, 16);
  header.nodes = GetU32(bytes + 20);
  header.springs = GetU32(bytes + 24);
  header.corrections = GetU32(bytes + 28);
  header.law = GetU32(bytes + 32);
  if (header.nodes == 0) Fail(path, "the model has no nodes");
  if (header.nodes > kMaxCount || header.springs > kMaxCount || header.corrections > kMaxCount) {
    Fail(path, "counts out of range (" + std::to_string(header.nodes) + " nodes, " +
                   std::to_string(header.springs) + " springs, " +
                   std::to_string(header.corrections) + " correction elements)");
  }
  // Counts are < 2^31, so this cannot overflow 64 bits. Checking it against the file size before
  // allocating anything bounds the memory a malicious header can make us take.
  const std::uint64_t expected = kHeaderBytes + kNodeBytes * header.nodes +
                                 kSpringBytes * header.springs +
                                 kCorrectionBytes * header.corrections + kChecksumBytes;
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
  unsigned char stored[8];
  file.Read(stored, sizeof stored, /*hashed=*/false);
  if (GetU64(stored) != file.hash()) Fail(path, "checksum mismatch (file corrupt)");
}

bool Positive(double value) { return std::isfinite(value) && value > 0.0; }

}  // namespace

void SaveModel(const Model& model, const std::string& path) {
  AtomicFileWriter out(path);
  out.Append(kModelFileMagic, kModelFileMagicSize);
  out.U32(kModelFileVersion);
  out.U32(static_cast<std::uint32_t>(model.num_nodes()));
  out.U32(static_cast<std::uint32_t>(model.num_springs()));
  out.U32(static_cast<std::uint32_t>(model.correction_edges().size()));
  out.U32(SpringLawCode(model.spring_law()));
  const Material& material = model.material();
  out.F64(material.youngs_modulus());
  out.F64(material.poisson_ratio());
  out.F64(material.density());
  out.F64(model.dispersion_fraction());
  out.F64(model.volume());
  out.F64(model.characteristic_length());
  for (int i = 0; i < model.num_nodes(); ++i) {
    for (int d = 0; d < 3; ++d) out.F64(model.rest_positions()(d, i));
    out.F64(model.masses()[i]);
  }
  for (int s = 0; s < model.num_springs(); ++s) {
    out.U32(static_cast<std::uint32_t>(model.spring_node_a()[s]));
    out.U32(static_cast<std::uint32_t>(model.spring_node_b()[s]));
    out.F64(model.spring_stiffness()[s]);
    out.F64(model.spring_rest_length()[s]);
    out.F64(model.dispersion_weight_a()[s]);
    out.F64(model.dispersion_weight_b()[s]);
  }
  for (std::size_t e = 0; e < model.correction_edges().size(); ++e) {
    for (const SpringIndex spring : model.correction_edges()[e]) {
      out.U32(static_cast<std::uint32_t>(spring));
    }
    out.F64(model.correction_coefficients()[e]);
  }
  out.Commit();
}

Model LoadModel(const std::string& path) {
  HashingFileReader file(path);
  const Header header = ReadHeader(file, path);
  // The checksum is verified before any value is used, so that a corrupt file is reported as
  // corrupt rather than as whatever nonsense the flipped bits happen to spell.
  VerifyChecksum(file, path);

  file.Rewind();
  file.Skip(36);
  unsigned char bytes[kCorrectionBytes];  // the largest record
  file.Read(bytes, 48);
  const double youngs = GetF64(bytes);
  const double poisson = GetF64(bytes + 8);
  const double density = GetF64(bytes + 16);
  const double q = GetF64(bytes + 24);
  const double volume = GetF64(bytes + 32);
  const double characteristic_length = GetF64(bytes + 40);

  SpringLaw law = SpringLaw::kLinear;
  if (header.law == kLinearLawCode) {
    law = SpringLaw::kLinear;
  } else if (header.law == kNonlinearLawCode) {
    law = SpringLaw::kNonlinear;
  } else {
    Fail(path, "unknown spring law code " + std::to_string(header.law));
  }
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

  ModelBuilder builder(material);
  builder.SetSpringLaw(law);
  builder.SetDispersionFraction(q);
  for (std::uint32_t i = 0; i < header.nodes; ++i) {
    file.Read(bytes, kNodeBytes);
    const Eigen::Vector3d position(GetF64(bytes), GetF64(bytes + 8), GetF64(bytes + 16));
    const double mass = GetF64(bytes + 24);
    if (!position.allFinite())
      Fail(path, "node " + std::to_string(i) + " has a non-finite position");
    if (!Positive(mass)) {
      Fail(path,
           "node " + std::to_string(i) + " has mass " + Str(mass) + " (must be finite and > 0)");
    }
    builder.AddNode(position, mass);  // cannot throw: its preconditions were checked above
  }

  // Kept until Build to compare with the rest lengths the builder derives from the positions.
  std::vector<double> stored_rest_length(header.springs);
  for (std::uint32_t s = 0; s < header.springs; ++s) {
    file.Read(bytes, kSpringBytes);
    const std::uint32_t a = GetU32(bytes);
    const std::uint32_t b = GetU32(bytes + 4);
    const double stiffness = GetF64(bytes + 8);
    const double rest_length = GetF64(bytes + 16);
    const double weight_a = GetF64(bytes + 24);
    const double weight_b = GetF64(bytes + 32);
    const std::string spring = "spring " + std::to_string(s);
    if (a >= header.nodes || b >= header.nodes) {
      Fail(path, spring + " joins node " + std::to_string(a) + " to node " + std::to_string(b) +
                     " but the model has " + std::to_string(header.nodes) + " nodes");
    }
    if (a == b) Fail(path, spring + " joins node " + std::to_string(a) + " to itself");
    if (!Positive(stiffness) || !Positive(rest_length) || !Positive(weight_a) ||
        !Positive(weight_b)) {
      Fail(path, spring + " has stiffness " + Str(stiffness) + ", rest length " + Str(rest_length) +
                     ", dispersion weights " + Str(weight_a) + " and " + Str(weight_b) +
                     " (all must be finite and > 0)");
    }
    try {
      builder.AddSpring(static_cast<NodeIndex>(a), static_cast<NodeIndex>(b), stiffness);
    } catch (const std::exception& e) {
      Fail(path, spring + ": " + e.what());
    }
    // a != b, so each call sets the weight at the intended end.
    builder.SetDispersionWeight(static_cast<SpringIndex>(s), static_cast<NodeIndex>(a), weight_a);
    builder.SetDispersionWeight(static_cast<SpringIndex>(s), static_cast<NodeIndex>(b), weight_b);
    stored_rest_length[s] = rest_length;
  }

  for (std::uint32_t e = 0; e < header.corrections; ++e) {
    file.Read(bytes, kCorrectionBytes);
    std::array<SpringIndex, 12> edges;
    for (int j = 0; j < 12; ++j) {
      const std::uint32_t spring = GetU32(bytes + 4 * j);
      if (spring >= header.springs) {
        Fail(path, "correction element " + std::to_string(e) + " refers to spring " +
                       std::to_string(spring) + " but the model has " +
                       std::to_string(header.springs) + " springs");
      }
      edges[j] = static_cast<SpringIndex>(spring);
    }
    const double coefficient = GetF64(bytes + 48);
    if (!std::isfinite(coefficient)) {
      Fail(path, "correction element " + std::to_string(e) + " has a non-finite coefficient");
    }
    builder.AddCorrectionElement(edges, coefficient);
  }

  // A file that changed between the checksum pass and this one is caught here.
  const std::uint64_t parsed_hash = file.hash();
  unsigned char stored[8];
  file.Read(stored, sizeof stored, /*hashed=*/false);
  if (GetU64(stored) != parsed_hash) Fail(path, "changed while being read");

  Model model = [&] {
    try {
      return builder.Build(volume, characteristic_length);
    } catch (const std::exception& e) {
      Fail(path, e.what());
    }
  }();
  // The builder derives rest lengths from the positions; a different result than at save time
  // (another platform's sqrt or FMA contraction) would silently change every spring's force.
  for (std::uint32_t s = 0; s < header.springs; ++s) {
    const double derived = model.spring_rest_length()[s];
    if (std::abs(derived - stored_rest_length[s]) > 1e-12 * stored_rest_length[s]) {
      Fail(path, "spring " + std::to_string(s) + " has stored rest length " +
                     Str(stored_rest_length[s]) + " but its nodes are " + Str(derived) + " apart");
    }
  }
  return model;
}

}  // namespace msm_sim::core
