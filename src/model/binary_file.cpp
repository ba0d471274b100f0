#include "model/binary_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <stdexcept>
#include <system_error>

namespace msm_sim::core::binary_file {
namespace {

std::string ErrnoMessage(int error) { return std::generic_category().message(error); }

}  // namespace

void Fail(const std::string& kind, const std::string& path, const std::string& problem) {
  throw std::runtime_error(kind + " '" + path + "': " + problem);
}

AtomicFileWriter::AtomicFileWriter(const std::string& kind, const std::string& path)
    : kind_(kind), path_(path) {
  // Process id plus a counter make the name unique among concurrent saves; O_EXCL guarantees
  // we never write into somebody else's file. Mode 0666 lets the umask decide, like fopen.
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    temp_path_ = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
    fd_ = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0 && errno != EEXIST) {
      Fail("cannot create temporary file '" + temp_path_ + "': " + ErrnoMessage(errno));
    }
  }
  if (fd_ < 0) Fail("cannot create a temporary file next to it (all names taken)");
  buffer_.reserve(kBufferBytes);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(temp_path_.c_str());
}

void AtomicFileWriter::Commit() {
  Flush();
  unsigned char checksum[kChecksumBytes];
  PutU64(hash_, checksum);
  WriteAll(checksum, sizeof checksum);
  // Without fsync a power cut after the rename could leave an empty file under the real name.
  if (::fsync(fd_) != 0) Fail("cannot flush to disk: " + ErrnoMessage(errno));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) Fail("cannot close: " + ErrnoMessage(errno));
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    Fail("cannot rename '" + temp_path_ + "' to it: " + ErrnoMessage(errno));
  }
  committed_ = true;
}

void AtomicFileWriter::Flush() {
  hash_ = Fnv1a(hash_, buffer_.data(), buffer_.size());
  WriteAll(buffer_.data(), buffer_.size());
  buffer_.clear();
}

void AtomicFileWriter::WriteAll(const unsigned char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t written = ::write(fd_, data, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      Fail("cannot write: " + ErrnoMessage(errno));
    }
    data += written;
    size -= static_cast<std::size_t>(written);
  }
}

void AtomicFileWriter::Fail(const std::string& problem) const {
  binary_file::Fail(kind_, path_, problem);
}

HashingFileReader::HashingFileReader(const std::string& kind, const std::string& path)
    : kind_(kind), path_(path) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever.
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd_ < 0) Fail("cannot open: " + ErrnoMessage(errno));
  struct stat info;
  if (::fstat(fd_, &info) != 0) {
    const int error = errno;
    ::close(fd_);
    Fail("cannot stat: " + ErrnoMessage(error));
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd_);
    Fail(S_ISDIR(info.st_mode) ? "is a directory" : "not a regular file");
  }
  size_ = static_cast<std::uint64_t>(info.st_size);
  // No larger than the file: a small (or foreign) file should not cost a megabyte to reject.
  buffer_.resize(static_cast<std::size_t>(std::clamp<std::uint64_t>(size_, 1, kBufferBytes)));
}

HashingFileReader::~HashingFileReader() { ::close(fd_); }

void HashingFileReader::Rewind() {
  if (::lseek(fd_, 0, SEEK_SET) != 0) Fail("cannot seek: " + ErrnoMessage(errno));
  begin_ = end_ = 0;
  hash_ = kFnvOffsetBasis;
}

void HashingFileReader::Skip(std::uint64_t size) {
  unsigned char scratch[4096];
  while (size > 0) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(size, sizeof scratch));
    Read(scratch, n);
    size -= n;
  }
}

void HashingFileReader::Fill() {
  for (;;) {
    const ssize_t n = ::read(fd_, buffer_.data(), buffer_.size());
    if (n > 0) {
      begin_ = 0;
      end_ = static_cast<std::size_t>(n);
      return;
    }
    if (n == 0) Fail("truncated while being read (did the file change?)");
    if (errno != EINTR) Fail("cannot read: " + ErrnoMessage(errno));
  }
}

void HashingFileReader::Fail(const std::string& problem) const {
  binary_file::Fail(kind_, path_, problem);
}

}  // namespace msm_sim::core::binary_file
