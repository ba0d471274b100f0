#include "lab_fit_command.h"

#include <cctype>
#include <fstream>
#include <iomanip>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "lab_model.h"
#include "lab_report.h"
#include "msm_sim/experiments/indentation_curve.h"
#include "msm_sim/experiments/indentation_fit.h"

namespace msm_sim::lab {
namespace {

std::vector<core::IndentationPoint> ReadCurve(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::invalid_argument("cannot read " + path);
  return core::ReadIndentationCurve(file);
}

// A parameter-server name: a letter, then letters, digits and underscores.
void CheckMaterialName(const std::string& name) {
  bool valid = !name.empty() && std::isalpha(static_cast<unsigned char>(name[0]));
  for (const char c : name)
    valid = valid && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  if (!valid) {
    throw std::invalid_argument("--name '" + name +
                                "' is not a parameter name (a letter, then letters, digits, _)");
  }
}

void WriteYaml(const LabArguments& arguments, const core::IndentationFitResult& fit, int nodes) {
  std::ofstream file(arguments.fit.yaml);
  const ModelArguments& model = arguments.model;
  file << std::setprecision(6) << "# msm_lab fit of " << arguments.fit.curve << ": sphere radius "
       << arguments.contact.sphere_radius << " m, block " << model.size.x() << " x "
       << model.size.y() << " x " << model.size.z() << " m clamped at its base, " << nodes
       << " nodes;\n# RMS residual " << fit.residual << " of the largest force, " << fit.simulations
       << " simulations. Load it like config/materials.yaml.\n"
       << "materials:\n  " << arguments.fit.name << ":\n    youngs: " << fit.youngs
       << "\n    poisson: " << model.poisson << "\n    density: " << model.density << "\n";
  if (!file.good()) throw std::runtime_error("cannot write " + arguments.fit.yaml);
}

void PrintFit(const LabArguments& arguments, const core::IndentationFitResult& fit, int nodes,
              double deepest, std::ostream& out) {
  if (arguments.json) {
    Json json{{"youngs", fit.youngs},
              {"poisson", arguments.model.poisson},
              {"hertz_youngs", fit.hertz_youngs},
              {"residual", fit.residual},
              {"simulations", fit.simulations},
              {"converged", fit.converged},
              {"tried", fit.tried},
              {"nodes", nodes},
              {"deepest_depth", deepest}};
    if (!arguments.fit.yaml.empty()) json["yaml"] = arguments.fit.yaml;
    out << json.dump() << "\n";
    return;
  }
  out << std::setprecision(5) << "fit of " << arguments.fit.curve << " to " << 1e3 * deepest
      << " mm, sphere radius " << arguments.contact.sphere_radius << " m, " << nodes
      << " nodes, nu " << arguments.model.poisson << "\n"
      << "Young's modulus  " << fit.youngs << " Pa" << (fit.converged ? "" : " (not converged)")
      << "\nHertz estimate   " << fit.hertz_youngs << " Pa (the search's start)\n"
      << "residual         " << fit.residual << " (RMS of the largest force)\n"
      << "simulations      " << fit.simulations << "\n";
  if (!arguments.fit.yaml.empty()) out << "material         " << arguments.fit.yaml << "\n";
}

}  // namespace

int RunFit(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  CheckMaterialName(arguments.fit.name);
  const std::vector<core::IndentationPoint> curve = ReadCurve(arguments.fit.curve);
  const ContactArguments& contact = arguments.contact;
  core::IndentationExperimentOptions options;
  options.sphere_radius = contact.sphere_radius;
  options.depth = curve.back().depth;
  options.speed = contact.speed;
  options.damping_beta = contact.damping;
  options.dispersion = arguments.model.dispersion == "one-pass" ? core::DispersionPasses::kOnePass
                                                                : core::DispersionPasses::kTwoPass;
  core::ParseIntegrator(contact.integrator, &options.integrator);
  const LabBody body = LoadLabBody(arguments.model, true);
  int nodes = 0;
  const core::IndentationSimulator simulate = [&](double youngs) {
    ModelArguments model = arguments.model;
    model.youngs = youngs;
    auto built = std::make_shared<const core::Model>(BuildLabModel(model, body));
    nodes = built->num_nodes();
    return core::RunIndentationExperiment(built, options).profile;
  };
  core::IndentationFitOptions fit_options;
  fit_options.poisson = arguments.model.poisson;
  fit_options.sphere_radius = contact.sphere_radius;
  const core::IndentationFitResult fit = core::FitYoungsModulus(curve, simulate, fit_options);
  if (!arguments.fit.yaml.empty()) WriteYaml(arguments, fit, nodes);
  PrintFit(arguments, fit, nodes, options.depth, out);
  if (fit.converged) return 0;
  err << "msm_lab: error: the fit did not converge in " << fit.simulations
      << " simulations (best E " << fit.youngs << " Pa, residual " << fit.residual << ")\n";
  return 1;
}

}  // namespace msm_sim::lab
