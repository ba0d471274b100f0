#include "msm_sim/io/regular_file.h"

#include <cerrno>
#include <cstring>

#include <sys/stat.h>
#include <unistd.h>

namespace msm_sim::core {

std::string RegularFileProblem(const std::string& path) {
  struct stat info {};
  // stat follows symbolic links and, unlike open, never waits on a FIFO.
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT || errno == ENOTDIR) return "no such file";
    return std::string("cannot be read: ") + std::strerror(errno);
  }
  if (S_ISDIR(info.st_mode)) return "is a directory";
  if (!S_ISREG(info.st_mode)) return "is a FIFO, device or socket, not a regular file";
  if (::access(path.c_str(), R_OK) != 0) {
    return std::string("cannot be read: ") + std::strerror(errno);
  }
  return {};
}

}  // namespace msm_sim::core
