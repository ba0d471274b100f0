// msm_lab: command-line virtual materials lab (see docs/lab.md).
// Exit codes: 0 success, 1 the experiment failed (or a hardness outside its conversion's range),
// 2 bad arguments.
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "lab_arguments.h"
#include "lab_commands.h"

namespace {

// First line of a possibly multi-line message, so that every error is one line on stderr.
std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

int main(int argc, char** argv) {
  // roslaunch appends remapping-style arguments (__name:=..., __log:=...); they are not ours.
  std::vector<std::string> args;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i > 0 && arg.find(":=") != std::string::npos) continue;
    args.push_back(arg);
  }
  const msm_sim::lab::ParseOutcome parsed = msm_sim::lab::ParseLabArguments(args);
  if (!parsed.arguments) {
    if (parsed.exit_code == 0) {
      std::cout << parsed.message;
    } else {
      std::cerr << "msm_lab: error: " << FirstLine(parsed.message)
                << " (run 'msm_lab --help' for usage)\n";
    }
    return parsed.exit_code;
  }
  try {
    return msm_sim::lab::RunLabCommand(*parsed.arguments, std::cout, std::cerr);
  } catch (const std::invalid_argument& error) {
    std::cerr << "msm_lab: error: " << FirstLine(error.what()) << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "msm_lab: error: " << FirstLine(error.what()) << "\n";
    return 1;
  }
}
