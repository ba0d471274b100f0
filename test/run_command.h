#pragma once
// Shared by the tests that run the package's command-line tools: runs a command and reports
// its exit code, whether a signal ended it, and what it wrote.

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace msm_sim::testing {

struct CommandRun {
  int exit_code = -1;
  bool signalled = false;
  std::string out;
  std::string err;
};

inline CommandRun RunCommand(const std::string& command) {
  // A file of its own: test binaries of two workspaces (or two suites) run at once would
  // otherwise read each other's messages.
  std::string err_file = ::testing::TempDir() + "msm_sim_command_stderr_XXXXXX";
  const int descriptor = mkstemp(err_file.data());
  if (descriptor >= 0) close(descriptor);
  const std::string full = command + " 2>" + err_file;
  CommandRun run;
  FILE* pipe = popen(full.c_str(), "r");
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  run.signalled = WIFSIGNALED(status);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_file);
  std::stringstream text;
  text << err.rdbuf();
  run.err = text.str();
  std::remove(err_file.c_str());
  return run;
}

}  // namespace msm_sim::testing
