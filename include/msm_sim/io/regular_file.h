#pragma once
// The one check every reader of a user's path runs before it opens the file: a FIFO opened for
// reading waits for a writer forever, and a device or directory is no input (docs/robustness.md).

#include <string>

namespace msm_sim::core {

/// Empty if `path` names a regular file this process may read; otherwise why not, in a few
/// words ("no such file", "is a directory", "is a FIFO, device or socket, not a regular file",
/// "cannot be read: <errno text>"). Never opens the file, so never blocks.
std::string RegularFileProblem(const std::string& path);

}  // namespace msm_sim::core
