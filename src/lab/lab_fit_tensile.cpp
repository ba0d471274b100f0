#include "lab_fit_tensile.h"

#include <cctype>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <string>

#include "lab_fit_command.h"
#include "lab_report.h"
#include "msm_sim/experiments/tensile_fit.h"
#include "msm_sim/io/regular_file.h"
#include "sweep_plot.h"

namespace msm_sim::lab {
namespace {

// A column option: a whole number is a 0-based index, anything else a name.
void SetColumn(const std::string& text, std::string* name, int* index) {
  const bool number =
      !text.empty() && text.size() < 9 && text.find_first_not_of("0123456789") == std::string::npos;
  if (number) {
    *index = std::stoi(text);
  } else {
    *name = text;
  }
}

core::TensileCurve ReadCurve(const FitArguments& fit) {
  const std::string problem = core::RegularFileProblem(fit.tensile);
  if (!problem.empty()) throw std::invalid_argument("cannot read " + fit.tensile + ": " + problem);
  std::ifstream file(fit.tensile);
  if (!file) throw std::invalid_argument("cannot read " + fit.tensile);
  core::TensileColumns columns;
  SetColumn(fit.strain_column, &columns.strain_name, &columns.strain_index);
  SetColumn(fit.stress_column, &columns.stress_name, &columns.stress_index);
  columns.stress_unit = fit.stress_unit;
  return core::ReadTensileCurve(file, columns);
}

struct TensileOutcome {
  core::TensileCurve curve;
  core::TensileFitResult fit;
  double poisson = 0.0;
};

// The YAML text's quoting of a file or column name.
std::string Quoted(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text)
    quoted += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return quoted + "\"";
}

void WriteYaml(const LabArguments& arguments, const TensileOutcome& outcome) {
  const core::TensileFitResult& fit = outcome.fit;
  std::ofstream file(arguments.fit.yaml);
  file << std::setprecision(6) << "# msm_lab fit --tensile of " << arguments.fit.tensile
       << ": the node-centred cubic lattice's uniaxial tension (docs/physics.md 4.1)\n# follows "
       << "the curve with RMS error " << fit.rms_error << " of the largest stress "
       << fit.max_stress << " Pa. Load it like config/materials.yaml;\n# the node reads youngs, "
       << "poisson and density (tensile_law and source are the fit's record).\n"
       << "materials:\n  " << arguments.fit.name << ":\n    youngs: " << fit.youngs
       << "\n    poisson: " << outcome.poisson << "\n    density: " << arguments.model.density
       << "\n    tensile_law: {alpha: " << fit.law.alpha << ", beta: " << fit.law.beta
       << ", rms_error: " << fit.rms_error
       << "}\n    source:\n      file: " << Quoted(arguments.fit.tensile)
       << "\n      strain_column: " << Quoted(outcome.curve.strain_column)
       << "\n      stress_column: " << Quoted(outcome.curve.stress_column)
       << "\n      stress_unit: " << outcome.curve.stress_unit << "\n      strain_range: ["
       << fit.fitted.front().strain << ", " << fit.fitted.back().strain
       << "]\n      points: " << fit.fitted.size() << "\n";
  if (!file.good()) throw std::runtime_error("cannot write " + arguments.fit.yaml);
}

Json FitJson(const LabArguments& arguments, const TensileOutcome& outcome) {
  const core::TensileFitResult& fit = outcome.fit;
  Json json{{"command", "fit"},
            {"tensile", arguments.fit.tensile},
            {"youngs", fit.youngs},
            {"poisson", outcome.poisson},
            {"alpha", fit.law.alpha},
            {"beta", fit.law.beta},
            {"rms_error", fit.rms_error},
            {"max_strain", arguments.fit.max_strain},
            {"strain_range", {fit.fitted.front().strain, fit.fitted.back().strain}},
            {"points", fit.fitted.size()},
            {"max_stress", fit.max_stress},
            {"strain_column", outcome.curve.strain_column},
            {"stress_column", outcome.curve.stress_column},
            {"stress_unit", outcome.curve.stress_unit}};
  if (!arguments.fit.yaml.empty()) json["yaml"] = arguments.fit.yaml;
  if (!arguments.plot.empty()) json["plot"] = arguments.plot;
  return json;
}

void PrintFit(const LabArguments& arguments, const TensileOutcome& outcome, std::ostream& out) {
  const core::TensileFitResult& fit = outcome.fit;
  if (arguments.json) {
    out << FitJson(arguments, outcome).dump() << "\n";
    return;
  }
  out << std::setprecision(4) << "tensile fit of " << arguments.fit.tensile
      << "\ncolumns          '" << outcome.curve.strain_column << "', '"
      << outcome.curve.stress_column << "' (" << outcome.curve.stress_unit << ")\nstrain range     "
      << fit.fitted.front().strain << " to " << fit.fitted.back().strain << " ("
      << fit.fitted.size() << " points, --max-strain " << arguments.fit.max_strain << ")\n"
      << std::setprecision(5) << "Young's modulus  " << fit.youngs
      << " Pa (small strain)\nPoisson's ratio  " << outcome.poisson
      << " (given)\nspring law       alpha " << fit.law.alpha << ", beta " << fit.law.beta
      << " (docs/physics.md 4.1)\nRMS error        " << std::setprecision(3)
      << 100.0 * fit.rms_error << " % of the largest stress " << std::setprecision(5)
      << fit.max_stress << " Pa\n";
  if (!arguments.fit.yaml.empty()) out << "material         " << arguments.fit.yaml << "\n";
  if (!arguments.plot.empty()) out << "plot             " << arguments.plot << "\n";
}

// The plot's data: FitJson with the curve's rows [strain, measured, model].
std::string PlotJson(const LabArguments& arguments, const TensileOutcome& outcome) {
  Json json = FitJson(arguments, outcome);
  Json rows = Json::array();
  for (std::size_t i = 0; i < outcome.fit.fitted.size(); ++i) {
    const core::TensilePoint& point = outcome.fit.fitted[i];
    rows.push_back({point.strain, point.stress, outcome.fit.model_stress[i]});
  }
  json["curve"] = rows;
  json["label"] = arguments.fit.name;
  return json.dump();
}

}  // namespace

int RunTensileFit(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  CheckMaterialName(arguments.fit.name);
  TensileOutcome outcome;
  outcome.curve = ReadCurve(arguments.fit);
  outcome.poisson = arguments.model.poisson;
  core::TensileFitOptions options;
  options.max_strain = arguments.fit.max_strain;
  options.poisson = outcome.poisson;
  outcome.fit = core::FitTensileCurve(outcome.curve.points, options);
  if (!arguments.fit.yaml.empty()) WriteYaml(arguments, outcome);
  if (!arguments.plot.empty()) {
    const std::string failure = PlotTensileFit(PlotJson(arguments, outcome), arguments.plot);
    if (!failure.empty()) {
      err << "msm_lab: error: " << failure << "\n";
      return 1;
    }
  }
  PrintFit(arguments, outcome, out);
  return 0;
}

}  // namespace msm_sim::lab
