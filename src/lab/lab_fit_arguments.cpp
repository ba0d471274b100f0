// `msm_lab fit`'s choice between an indentation curve (--indent) and a tensile curve
// (--tensile), the tensile fit's options, and the fit's defaults.
#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

#include "lab_command_line.h"

namespace msm_sim::lab {
namespace {

// The options `fit --tensile` reads; the others describe an indentation's block and probe.
constexpr const char* kTensileOptions[] = {
    "--tensile", "--strain-column", "--stress-column", "--stress-unit", "--max-strain", "--plot",
    "--poisson", "--density",       "--yaml",          "--name",        "--json",       "--help"};

bool Given(const CLI::App* command, const char* name) {
  return command->get_option(name)->count() > 0;
}

}  // namespace

void AddTensileOptions(CLI::App* fit, CommandLine* line) {
  FitArguments& arguments = line->arguments.fit;
  CLI::Option* indent = fit->get_option("--indent");
  CLI::Option* tensile =
      fit->add_option("--tensile", arguments.tensile,
                      "CSV of a uniaxial tensile curve (engineering strain and stress; ',' or ';' "
                      "separated, a header block allowed): fit E and the spring law so that the "
                      "lattice's tension follows it (docs/lab.md)")
          ->check(CLI::ExistingFile);
  tensile->excludes(indent);
  indent->excludes(tensile);
  fit->add_option("--strain-column", arguments.strain_column,
                  "--tensile: the engineering strain's column, by name or 0-based index "
                  "(default: the column named 'Engineering Strain...')")
      ->needs(tensile);
  fit->add_option("--stress-column", arguments.stress_column,
                  "--tensile: the engineering stress's column, by name or 0-based index "
                  "(default: the column named 'Engineering Stress...')")
      ->needs(tensile);
  fit->add_option("--stress-unit", arguments.stress_unit,
                  "--tensile: Pa | kPa | MPa (default: the unit in the column's name, e.g. "
                  "'(MPa)'; required when the name states none)")
      ->check(CLI::IsMember({"Pa", "kPa", "MPa"}))
      ->needs(tensile);
  fit->add_option("--max-strain", arguments.max_strain,
                  "--tensile: fit the curve up to this engineering strain")
      ->capture_default_str()
      ->check(Finite(false))
      ->needs(tensile);
  fit->add_option("--plot", line->arguments.plot,
                  "--tensile: write a plot of the curve and the model to this PNG file")
      ->needs(tensile);
}

std::string FitOptionProblem(const CommandLine& line) {
  const CLI::App* fit = line.fit;
  if (!fit->parsed()) return "";
  if (!Given(fit, "--indent") && !Given(fit, "--tensile")) {
    return "fit needs --indent FILE (an indentation curve) or --tensile FILE (a tensile curve)";
  }
  if (Given(fit, "--indent")) {
    if (line.size.empty()) return "--size is required with --indent";
    if (!Given(fit, "--sphere-radius")) return "--sphere-radius is required with --indent";
    return "";
  }
  for (const CLI::Option* option : fit->get_options()) {
    const std::string name = option->get_name();
    const bool tensile = std::find(std::begin(kTensileOptions), std::end(kTensileOptions), name) !=
                         std::end(kTensileOptions);
    if (!tensile && option->count() > 0) {
      return name + " applies to fit --indent, not to --tensile";
    }
  }
  return "";
}

void ApplyFitDefaults(CommandLine* line) {
  ModelArguments& model = line->arguments.model;
  if (line->fit->get_option("--poisson")->count() == 0) model.poisson = 0.49;
  const std::vector<double>& second = line->second_size;
  if (!second.empty()) {
    line->arguments.fit.second_size = Eigen::Vector3d(second[0], second[1], second[2]);
  }
}

}  // namespace msm_sim::lab
