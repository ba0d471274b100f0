#pragma once
// Shared by the msm_lab command-line tests: runs the built msm_lab executable (its path comes
// from the test target's MSM_LAB_EXECUTABLE definition).

#include <string>

#include "../run_command.h"

namespace msm_sim::testing {

using LabRun = CommandRun;

inline LabRun RunLab(const std::string& arguments) {
  return RunCommand(std::string(MSM_LAB_EXECUTABLE) + " " + arguments);
}

inline int CountLines(const std::string& text) {
  int lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

}  // namespace msm_sim::testing
