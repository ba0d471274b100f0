#pragma once
// msm_lab's whole command line as a function: what the executable runs, and what the Python
// module msm_sim.lab runs, so that both give the same output and the same error lines.

#include <ostream>
#include <string>
#include <vector>

namespace msm_sim::lab {

/// Exit codes of RunLabMain, as the msm_lab executable returns them.
inline constexpr int kLabSuccess = 0;
inline constexpr int kLabFailure = 1;       ///< the experiment failed (e.g. no convergence)
inline constexpr int kLabBadArguments = 2;  ///< bad options or values

/// Parses `args` (args[0] the program name; roslaunch's name:=value arguments are skipped) and
/// runs the command: its table or JSON goes to `out`, --help to `out` with code 0, and every
/// error as one line "msm_lab: error: ..." to `err`. Never throws; returns the exit code.
int RunLabMain(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace msm_sim::lab
