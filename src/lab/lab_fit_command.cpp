#include "lab_fit_command.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "lab_fit_tensile.h"
#include "lab_model.h"
#include "lab_report.h"
#include "msm_sim/experiments/indentation_curve.h"
#include "msm_sim/experiments/indentation_fit.h"
#include "msm_sim/io/regular_file.h"

namespace msm_sim::lab {
namespace {

std::vector<core::IndentationPoint> ReadCurve(const std::string& path) {
  const std::string problem = core::RegularFileProblem(path);
  if (!problem.empty()) throw std::invalid_argument("cannot read " + path + ": " + problem);
  std::ifstream file(path);
  if (!file) throw std::invalid_argument("cannot read " + path);
  return core::ReadIndentationCurve(file);
}

// The lattice spacing a fit simulates at, against the contact it must resolve.
struct FitResolution {
  core::ContactResolution contact;  // of the first curve at the spacing used
  bool chosen = false;              // by the rule (no --spacing or --target-nodes given)
};

// The spacing --spacing or --target-nodes gives on this block.
double GivenSpacing(const ModelArguments& model, const Eigen::Vector3d& size) {
  if (model.target_nodes > 0) return std::cbrt(size.prod() / model.target_nodes);
  return model.spacing;
}

// Refuses a block the resolving spacing would fill with more than the fit's node budget.
void CheckNodeBudget(const Eigen::Vector3d& size, const core::ContactResolution& resolution) {
  const double nodes = size.prod() / std::pow(resolution.spacing, 3);
  if (nodes <= core::kIndentationFitNodeBudget) return;
  std::ostringstream message;
  message << std::setprecision(3) << "resolving the contact (" << core::kNodesAcrossContactRadius
          << " nodes across its radius " << 1e3 * resolution.contact_radius << " mm: spacing "
          << 1e3 * resolution.spacing << " mm) needs about " << static_cast<long long>(nodes)
          << " nodes on the " << 1e3 * size.x() << " x " << 1e3 * size.y() << " x "
          << 1e3 * size.z() << " mm block, more than the fit's budget of "
          << static_cast<long long>(core::kIndentationFitNodeBudget)
          << "; give a block about 10 contact radii (" << std::setprecision(3)
          << 1e4 * resolution.contact_radius
          << " mm) wide and deep, or --spacing to fit at a coarser resolution";
  throw std::invalid_argument(message.str());
}

// The fit's spacing (docs/lab.md "fit"): given, or chosen with kNodesAcrossContactRadius nodes
// across the smallest of the curves' largest contact radii, within the node budget. Sets it on
// *arguments; warns on `err` when a given spacing does not resolve the contact.
FitResolution ResolveSpacing(LabArguments* arguments,
                             const std::vector<core::IndentationPoint>& curve,
                             const std::vector<core::IndentationPoint>& second, std::ostream& err) {
  ModelArguments& model = arguments->model;
  const double radius = arguments->contact.sphere_radius;
  FitResolution resolution;
  resolution.chosen = model.spacing == 0.0 && model.target_nodes == 0;
  if (!resolution.chosen) {
    resolution.contact = core::ResolutionOf(curve, radius, GivenSpacing(model, model.size));
  } else {
    core::ContactResolution rule = core::ResolvingResolution(curve, radius);
    if (!second.empty()) {
      const core::ContactResolution other = core::ResolvingResolution(second, radius);
      if (other.spacing < rule.spacing) rule.spacing = other.spacing;
      CheckNodeBudget(arguments->fit.second_size, rule);
    }
    CheckNodeBudget(model.size, rule);
    model.spacing = rule.spacing;
    resolution.contact = core::ResolutionOf(curve, radius, rule.spacing);
  }
  if (resolution.contact.nodes_across < core::kNodesAcrossContactRadius * (1.0 - 1e-9)) {
    err << std::setprecision(3) << "msm_lab: warning: the spacing "
        << 1e3 * resolution.contact.spacing << " mm puts " << resolution.contact.nodes_across
        << " nodes across the contact radius " << 1e3 * resolution.contact.contact_radius
        << " mm (fewer than " << core::kNodesAcrossContactRadius
        << "): E is this lattice's, not the material's (omit --spacing to resolve the contact)\n";
  }
  return resolution;
}

// What either fit found, for the report and the YAML entry.
struct FitOutcome {
  double youngs = 0.0, poisson = 0.0, residual = 0.0;
  int simulations = 0;
  bool converged = false;
  Json details;  // the fit's own JSON keys
  int nodes = 0;
  double deepest = 0.0;
  FitResolution resolution;
};

// One measured sample: `indent` on its block, to its curve's deepest depth, for any material.
struct Sample {
  Sample(const LabArguments& arguments, const Eigen::Vector3d& size,
         const std::vector<core::IndentationPoint>& curve)
      : model(arguments.model) {
    model.size = size;
    body = LoadLabBody(model, true);
    const ContactArguments& contact = arguments.contact;
    options.sphere_radius = contact.sphere_radius;
    options.depth = curve.back().depth;
    options.speed = contact.speed;
    options.damping_beta = contact.damping;
    core::ParseIntegrator(contact.integrator, &options.integrator);
    options.spring_precision = contact.precision == "single" ? core::SpringPrecision::kSingle
                                                             : core::SpringPrecision::kDouble;
  }

  std::vector<core::IndentationSample> Simulate(double youngs, double poisson) {
    ModelArguments material = model;
    material.youngs = youngs;
    material.poisson = poisson;
    const auto built = std::make_shared<const core::Model>(BuildLabModel(material, body));
    nodes = built->num_nodes();
    return core::RunIndentationExperiment(built, options).profile;
  }

  ModelArguments model;
  LabBody body;
  core::IndentationExperimentOptions options;
  int nodes = 0;
};

FitOutcome FitYoungs(const LabArguments& arguments,
                     const std::vector<core::IndentationPoint>& curve) {
  Sample sample(arguments, arguments.model.size, curve);
  core::IndentationFitOptions options;
  options.poisson = arguments.model.poisson;
  options.sphere_radius = arguments.contact.sphere_radius;
  const core::IndentationFitResult fit = core::FitYoungsModulus(
      curve, [&](double youngs) { return sample.Simulate(youngs, options.poisson); }, options);
  FitOutcome outcome;
  outcome.youngs = fit.youngs;
  outcome.poisson = options.poisson;
  outcome.residual = fit.residual;
  outcome.simulations = fit.simulations;
  outcome.converged = fit.converged;
  outcome.details = Json{{"hertz_youngs", fit.hertz_youngs}, {"tried", fit.tried}};
  outcome.nodes = sample.nodes;
  outcome.deepest = curve.back().depth;
  return outcome;
}

FitOutcome FitYoungsAndPoisson(const LabArguments& arguments,
                               const std::vector<core::IndentationPoint>& curve,
                               const std::vector<core::IndentationPoint>& second) {
  Sample first_sample(arguments, arguments.model.size, curve);
  Sample second_sample(arguments, arguments.fit.second_size, second);
  core::MaterialFitOptions options;
  options.youngs.sphere_radius = arguments.contact.sphere_radius;
  const core::MaterialFitResult fit = core::FitYoungsAndPoisson(
      curve, second, [&](double e, double nu) { return first_sample.Simulate(e, nu); },
      [&](double e, double nu) { return second_sample.Simulate(e, nu); }, options);
  FitOutcome outcome;
  outcome.youngs = fit.youngs;
  outcome.poisson = fit.poisson;
  outcome.residual = fit.residual;
  outcome.simulations = fit.simulations;
  outcome.converged = fit.converged;
  outcome.details = Json{{"second_residual", fit.second_residual}, {"trials", fit.trials}};
  outcome.nodes = first_sample.nodes;
  outcome.deepest = curve.back().depth;
  return outcome;
}

// True when the fit's lattice resolves the contact, so that its E is the material's.
bool Resolved(const FitResolution& resolution) {
  return resolution.contact.nodes_across >= core::kNodesAcrossContactRadius * (1.0 - 1e-9);
}

void WriteYaml(const LabArguments& arguments, const FitOutcome& fit) {
  std::ofstream file(arguments.fit.yaml);
  const ModelArguments& model = arguments.model;
  const core::ContactResolution& contact = fit.resolution.contact;
  file << std::setprecision(6) << "# msm_lab fit of " << arguments.fit.curve
       << (arguments.fit.fit_poisson ? " and " + arguments.fit.second_curve : "")
       << ": sphere radius " << arguments.contact.sphere_radius << " m, block " << model.size.x()
       << " x " << model.size.y() << " x " << model.size.z() << " m clamped at its base, "
       << fit.nodes << " nodes, spacing " << contact.spacing << " m (" << std::setprecision(3)
       << contact.nodes_across << " across the contact radius)" << std::setprecision(6)
       << ";\n# RMS residual " << fit.residual << " of the largest force, " << fit.simulations
       << " simulations. Load it like config/materials.yaml.\n"
       << "materials:\n  " << arguments.fit.name << ":\n    youngs: " << fit.youngs
       << "\n    poisson: " << fit.poisson << "\n    density: " << model.density << "\n";
  if (!file.good()) throw std::runtime_error("cannot write " + arguments.fit.yaml);
}

void PrintFitJson(const LabArguments& arguments, const FitOutcome& fit, std::ostream& out) {
  const core::ContactResolution& contact = fit.resolution.contact;
  Json json{{"youngs", fit.youngs},
            {"poisson", fit.poisson},
            {"residual", fit.residual},
            {"simulations", fit.simulations},
            {"converged", fit.converged},
            {"nodes", fit.nodes},
            {"deepest_depth", fit.deepest},
            {"spacing", contact.spacing},
            {"contact_radius", contact.contact_radius},
            {"nodes_across_contact", contact.nodes_across},
            {"resolution", fit.resolution.chosen ? "chosen" : "given"},
            {"contact_resolved", Resolved(fit.resolution)}};
  json.update(fit.details);
  if (!arguments.fit.yaml.empty()) json["yaml"] = arguments.fit.yaml;
  out << json.dump() << "\n";
}

void PrintFit(const LabArguments& arguments, const FitOutcome& fit, std::ostream& out) {
  if (arguments.json) return PrintFitJson(arguments, fit, out);
  const core::ContactResolution& contact = fit.resolution.contact;
  out << std::setprecision(5) << "fit of " << arguments.fit.curve << " to " << 1e3 * fit.deepest
      << " mm, sphere radius " << arguments.contact.sphere_radius << " m, " << fit.nodes
      << " nodes\n"
      << std::setprecision(3) << "resolution       spacing " << 1e3 * contact.spacing << " mm, "
      << contact.nodes_across << " nodes across the contact radius " << 1e3 * contact.contact_radius
      << " mm (" << (fit.resolution.chosen ? "chosen" : "given") << "; at least "
      << core::kNodesAcrossContactRadius << " resolve it)\n"
      << std::setprecision(5) << "Young's modulus  " << fit.youngs << " Pa"
      << (Resolved(fit.resolution) ? " (the material's)" : " (this lattice's: contact unresolved)")
      << (fit.converged ? "" : " (not converged)") << "\nPoisson's ratio  " << fit.poisson
      << (arguments.fit.fit_poisson ? " (fitted to both curves)" : " (given)") << "\n";
  if (fit.details.contains("hertz_youngs")) {
    out << "Hertz estimate   " << fit.details["hertz_youngs"].get<double>()
        << " Pa (the search's start)\n";
  }
  out << "residual         " << fit.residual << " (RMS of the largest force)\n";
  if (fit.details.contains("second_residual")) {
    out << "second residual  " << fit.details["second_residual"].get<double>() << "\n";
  }
  out << "simulations      " << fit.simulations << "\n";
  if (!arguments.fit.yaml.empty()) out << "material         " << arguments.fit.yaml << "\n";
}

}  // namespace

void CheckMaterialName(const std::string& name) {
  bool valid = !name.empty() && std::isalpha(static_cast<unsigned char>(name[0]));
  for (const char c : name) {
    valid = valid && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  }
  if (!valid) {
    throw std::invalid_argument("--name '" + name +
                                "' is not a parameter name (a letter, then letters, digits, _)");
  }
}

int RunFit(const LabArguments& given, std::ostream& out, std::ostream& err) {
  if (!given.fit.tensile.empty()) return RunTensileFit(given, out, err);
  CheckMaterialName(given.fit.name);
  const std::vector<core::IndentationPoint> curve = ReadCurve(given.fit.curve);
  const std::vector<core::IndentationPoint> second = given.fit.fit_poisson
                                                         ? ReadCurve(given.fit.second_curve)
                                                         : std::vector<core::IndentationPoint>{};
  LabArguments arguments = given;
  const FitResolution resolution = ResolveSpacing(&arguments, curve, second, err);
  FitOutcome fit = arguments.fit.fit_poisson ? FitYoungsAndPoisson(arguments, curve, second)
                                             : FitYoungs(arguments, curve);
  fit.resolution = resolution;
  if (!arguments.fit.yaml.empty()) WriteYaml(arguments, fit);
  PrintFit(arguments, fit, out);
  if (fit.converged) return 0;
  err << "msm_lab: error: the fit did not converge in " << fit.simulations
      << " simulations (best E " << fit.youngs << " Pa, nu " << fit.poisson << ", residual "
      << fit.residual << ")\n";
  return 1;
}

}  // namespace msm_sim::lab
