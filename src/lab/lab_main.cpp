#include "lab_main.h"

#include <exception>
#include <stdexcept>

#include "lab_arguments.h"
#include "lab_commands.h"

namespace msm_sim::lab {
namespace {

// First line of a possibly multi-line message, so that every error is one line on stderr.
std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

int RunLabMain(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  // roslaunch appends remapping-style arguments (__name:=..., __log:=...); they are not ours.
  std::vector<std::string> ours;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (i > 0 && args[i].find(":=") != std::string::npos) continue;
    ours.push_back(args[i]);
  }
  const ParseOutcome parsed = ParseLabArguments(ours);
  if (!parsed.arguments) {
    if (parsed.exit_code == kLabSuccess) {
      out << parsed.message;
    } else {
      err << "msm_lab: error: " << FirstLine(parsed.message)
          << " (run 'msm_lab --help' for usage)\n";
    }
    return parsed.exit_code;
  }
  try {
    return RunLabCommand(*parsed.arguments, out, err);
  } catch (const std::invalid_argument& error) {
    err << "msm_lab: error: " << FirstLine(error.what()) << "\n";
    return kLabBadArguments;
  } catch (const std::exception& error) {
    err << "msm_lab: error: " << FirstLine(error.what()) << "\n";
    return kLabFailure;
  }
}

}  // namespace msm_sim::lab
