#include "sweep_plot.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "plot_script.h"

namespace msm_sim::lab {
namespace {

std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// A fresh temporary file path with the given suffix; empty on failure.
std::string TemporaryFile(const char* suffix, const std::string& contents) {
  const char* directory = std::getenv("TMPDIR");
  std::string pattern = std::string(directory ? directory : "/tmp") + "/msm_lab_XXXXXX" + suffix;
  const int fd = mkstemps(pattern.data(), static_cast<int>(std::string(suffix).size()));
  if (fd < 0) return "";
  close(fd);
  std::ofstream(pattern) << contents;
  return pattern;
}

// Runs one of the embedded plotting scripts on the JSON text; "" or a one-line reason.
std::string RunPlotScript(const char* script, const std::string& json,
                          const std::string& png_path) {
  const std::string json_file = TemporaryFile(".json", json);
  const std::string script_file = TemporaryFile(".py", script);
  const std::string error_file = TemporaryFile(".txt", "");
  if (json_file.empty() || script_file.empty() || error_file.empty()) {
    return "cannot create temporary files for the plot";
  }
  // Debian's python3, not a pyenv one that may lack matplotlib.
  const std::string command = "/usr/bin/python3 " + ShellQuote(script_file) + " " +
                              ShellQuote(json_file) + " " + ShellQuote(png_path) + " 2>" +
                              ShellQuote(error_file);
  const int status = std::system(command.c_str());
  std::string reason;
  if (status != 0) {
    std::ifstream errors(error_file);
    std::string line, last;
    while (std::getline(errors, line)) {
      if (!line.empty()) last = line;
    }
    reason = "plotting failed: " + (last.empty() ? "python3 exited with an error" : last);
  }
  std::remove(json_file.c_str());
  std::remove(script_file.c_str());
  std::remove(error_file.c_str());
  return reason;
}

}  // namespace

std::string PlotPoissonSweep(const std::string& sweep_json, const std::string& png_path) {
  return RunPlotScript(kPoissonSweepPlotScript, sweep_json, png_path);
}

std::string PlotIndentation(const std::string& indent_json, const std::string& png_path) {
  return RunPlotScript(kIndentationPlotScript, indent_json, png_path);
}

std::string PlotTensileFit(const std::string& fit_json, const std::string& png_path) {
  return RunPlotScript(kTensilePlotScript, fit_json, png_path);
}

}  // namespace msm_sim::lab
