#include "lab_commands.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "lab_deflection_command.h"
#include "lab_dynamics_commands.h"
#include "lab_fit_command.h"
#include "lab_grasp_command.h"
#include "lab_material_command.h"
#include "lab_model.h"
#include "lab_report.h"
#include "lab_squeeze_command.h"
#include "msm_sim/experiments/compression_experiment.h"
#include "msm_sim/experiments/slide_experiment.h"
#include "msm_sim/geometry/vtk_export.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/material/extended_msm.h"
#include "msm_sim/model/model_file.h"
#include "msm_sim/model/model_statistics.h"
#include "msm_sim/model/state.h"
#include "sweep_plot.h"

namespace msm_sim::lab {
namespace {

struct CompressionRun {
  core::ModelStatistics stats;
  core::CompressionExperimentResult result;
};

CompressionRun Compress(const ModelArguments& model_arguments, double strain) {
  const LabBody body = LoadLabBody(model_arguments, true);
  const core::Model model = BuildLabModel(model_arguments, body);
  core::CompressionExperimentOptions options;
  options.body_size = body.max - body.min;
  if (body.solid) {
    // E is the axial stress over the strain: the force through the middle plane over the area
    // of the body's section there (the box's Ly Lz for a block).
    options.cross_section_area = core::CrossSectionArea(
        body.solid->surface(), 0.5 * (body.min + body.max), Eigen::Vector3d::UnitX());
  }
  options.strain = strain;
  return {core::ComputeModelStatistics(model), core::RunCompressionExperiment(model, options)};
}

int RunCompression(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  const CompressionRun run = Compress(arguments.model, arguments.strain);
  const core::CompressionExperimentResult& result = run.result;
  if (!result.solver.converged) return ReportSolverFailure(result.solver, err);
  const double seconds = Seconds(start);
  const double youngs = arguments.model.youngs;
  const double youngs_error = result.youngs_measured / youngs - 1.0;

  if (arguments.json) {
    Json json{{"command", "compression"},
              {"model", arguments.model.model},
              {"spring", arguments.model.spring},
              {"dispersion_ratio", core::DispersionRatio(arguments.model.poisson)},
              {"youngs_target", youngs},
              {"poisson_target", arguments.model.poisson},
              {"youngs_measured", result.youngs_measured},
              {"poisson_measured", result.poisson_measured},
              {"youngs_relative_error", youngs_error},
              {"youngs_stress_corrected", result.youngs_stress_corrected},
              {"poisson_stress_corrected", result.poisson_stress_corrected},
              {"axial_force", result.axial_force},
              {"strain", arguments.strain}};
    if (arguments.model.alpha && arguments.model.beta) {
      json["alpha"] = *arguments.model.alpha;  // the power law's, docs/physics.md §4.1
      json["beta"] = *arguments.model.beta;
    }
    json.update(ModelJson(run.stats));
    json["solver"] = SolverJson(result.solver);
    json["seconds"] = seconds;
    out << json.dump() << "\n";
    return 0;
  }
  out << "uniaxial compression along x, strain " << arguments.strain << "\n";
  PrintModelTable(arguments.model, run.stats, out);
  out << std::setprecision(5);
  out << "\n                  target        measured      stress-corrected\n"
      << "E [Pa]            " << std::setw(12) << youngs << "  " << std::setw(12)
      << result.youngs_measured << "  " << std::setw(12) << result.youngs_stress_corrected << "\n"
      << "nu                " << std::setw(12) << arguments.model.poisson << "  " << std::setw(12)
      << result.poisson_measured << "  " << std::setw(12) << result.poisson_stress_corrected << "\n"
      << "E error           " << std::setw(11) << 100.0 * youngs_error << " %\n"
      << "\nsolver: " << result.solver.message << "\n"
      << "time: " << seconds << " s\n";
  return 0;
}

int RunPoissonSweep(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  if (arguments.targets.empty()) throw std::invalid_argument("--targets needs at least one value");
  Json rows = Json::array();
  for (const double target : arguments.targets) {
    ModelArguments model = arguments.model;
    model.poisson = target;
    const CompressionRun run = Compress(model, arguments.strain);
    if (!run.result.solver.converged) return ReportSolverFailure(run.result.solver, err);
    rows.push_back(
        {{"poisson_target", target},
         {"dispersion_ratio", core::DispersionRatio(target)},
         {"poisson_theory", core::PoissonFromDispersionRatio(core::DispersionRatio(target))},
         {"poisson_measured", run.result.poisson_measured},
         {"poisson_stress_corrected", run.result.poisson_stress_corrected},
         {"youngs_measured", run.result.youngs_measured},
         {"youngs_relative_error", run.result.youngs_measured / model.youngs - 1.0},
         {"nodes", run.stats.nodes},
         {"springs", run.stats.springs},
         {"mean_springs_per_node", run.stats.mean_springs_per_node}});
  }
  Json sweep{{"command", "poisson-sweep"},
             {"model", arguments.model.model},
             {"spring", arguments.model.spring},
             {"youngs_target", arguments.model.youngs},
             {"results", rows},
             {"seconds", Seconds(start)}};
  if (!arguments.plot.empty()) {
    const std::string failure = PlotPoissonSweep(sweep.dump(), arguments.plot);
    if (!failure.empty()) {
      err << "msm_lab: error: " << failure << "\n";
      return 1;
    }
  }
  if (arguments.json) {
    out << sweep.dump() << "\n";
    return 0;
  }
  out << "Poisson sweep, " << arguments.model.model << " eMSM, E = " << arguments.model.youngs
      << " Pa, " << rows[0]["nodes"].get<int>() << " nodes\n\n"
      << "  nu target        Q   nu measured   nu - target   E error [%]\n"
      << std::fixed;
  for (const Json& row : rows) {
    const double target = row["poisson_target"].get<double>();
    const double measured = row["poisson_measured"].get<double>();
    out << std::setprecision(3) << std::setw(11) << target << std::setw(9)
        << row["dispersion_ratio"].get<double>() << std::setprecision(4) << std::setw(14)
        << measured << std::setw(14) << measured - target << std::setprecision(2) << std::setw(14)
        << 100.0 * row["youngs_relative_error"].get<double>() << "\n";
  }
  if (!arguments.plot.empty()) out << "\nplot: " << arguments.plot << "\n";
  out << "time: " << std::setprecision(2) << Seconds(start) << " s\n";
  return 0;
}

int RunBuild(const LabArguments& arguments, std::ostream& out) {
  const auto start = std::chrono::steady_clock::now();
  const LabBody body = LoadLabBody(arguments.model, false);
  const core::Model model = BuildLabModel(arguments.model, body);
  const core::ModelStatistics stats = core::ComputeModelStatistics(model);
  const double build_seconds = Seconds(start);
  if (!arguments.out.empty()) core::SaveModel(model, arguments.out);
  if (!arguments.vtk.empty()) core::WriteVtu(model, core::State::AtRest(model), arguments.vtk);
  const Eigen::Vector3d& lo = body.min;
  const Eigen::Vector3d& hi = body.max;
  if (arguments.json) {
    Json json{{"command", "build"},
              {"model", arguments.model.model},
              {"mesh", arguments.model.mesh},
              {"antialias", arguments.model.antialias},
              {"spacing", model.characteristic_length()},
              {"nodes", stats.nodes},
              {"springs", stats.springs},
              {"mass", stats.total_mass},
              {"mesh_volume", body.volume},
              {"bbox_min", {lo.x(), lo.y(), lo.z()}},
              {"bbox_max", {hi.x(), hi.y(), hi.z()}},
              {"mean_springs_per_node", stats.mean_springs_per_node},
              {"build_seconds", build_seconds}};
    if (!arguments.out.empty()) json["out"] = arguments.out;
    if (!arguments.vtk.empty()) json["vtk"] = arguments.vtk;
    out << json.dump() << "\n";
    return 0;
  }
  out << "mesh             " << arguments.model.mesh << " (scale " << arguments.model.scale << ")\n"
      << "mesh volume      " << body.volume << " m^3\n"
      << "bounding box     [" << lo.transpose() << "] .. [" << hi.transpose() << "] m\n"
      << "spacing          " << model.characteristic_length() << " m"
      << (arguments.model.model == "cubic"
              ? (arguments.model.antialias ? ", anti-aliased" : ", not anti-aliased")
              : "")
      << "\n";
  PrintModelTable(arguments.model, stats, out);
  out << "mass / (rho V)   " << stats.total_mass / (arguments.model.density * body.volume) << "\n";
  if (!arguments.out.empty()) out << "saved            " << arguments.out << "\n";
  if (!arguments.vtk.empty()) out << "vtk              " << arguments.vtk << "\n";
  out << "time: " << build_seconds << " s\n";
  return 0;
}

// The box of the slide experiment: an element-corner lattice (nodes on the box's corners and
// faces) whose node counts and size must agree on one spacing.
core::Model SlideBox(const SlideArguments& slide) {
  if (!slide.size.allFinite() || (slide.size.array() <= 0.0).any()) {
    throw std::invalid_argument("slide box size must be finite and > 0");
  }
  if (!(slide.mass > 0.0) || !std::isfinite(slide.mass)) {
    throw std::invalid_argument("slide mass must be finite and > 0");
  }
  const Eigen::Vector3d spacing = slide.size.array() / (slide.nodes.cast<double>().array() - 1.0);
  if ((spacing.array() - spacing.x()).abs().maxCoeff() > 1e-6 * spacing.x()) {
    std::ostringstream message;
    message << "--nodes and --size give spacings " << spacing.x() << ", " << spacing.y() << ", "
            << spacing.z() << " m; the lattice is cubic, so size / (nodes - 1) must agree";
    throw std::invalid_argument(message.str());
  }
  core::CubicLatticeOptions options;
  options.size = slide.size;
  options.lattice.spacing = spacing.x();
  options.construction = core::CubicConstruction::kElementCorner;
  return core::BuildCubicLattice(core::Material::FromYoungsPoisson(slide.youngs, slide.poisson,
                                                                   slide.mass / slide.size.prod()),
                                 options);
}

int RunSlide(const LabArguments& arguments, std::ostream& out) {
  const auto start = std::chrono::steady_clock::now();
  const SlideArguments& slide = arguments.slide;
  const auto model = std::make_shared<const core::Model>(SlideBox(slide));
  core::SlideExperimentOptions options;
  options.initial_speed = slide.v0;
  options.friction = slide.mu;
  if (!(slide.v0 > 0.0) || !(slide.mu > 0.0) || !std::isfinite(slide.v0 + slide.mu)) {
    throw std::invalid_argument("--v0 and --mu must be finite and > 0");
  }
  const core::SlideExperimentResult result = core::RunSlideExperiment(model, options);
  const double seconds = Seconds(start);
  if (arguments.json) {
    Json json{{"command", "slide"},
              {"nodes", model->num_nodes()},
              {"mass", model->masses().sum()},
              {"v0", slide.v0},
              {"mu", slide.mu},
              {"distance", result.distance},
              {"theory_distance", result.theory_distance},
              {"relative_error", result.distance / result.theory_distance - 1.0},
              {"seconds_simulated", result.seconds_simulated},
              {"stopped", result.stopped},
              {"steps", result.steps},
              {"seconds", seconds}};
    out << json.dump() << "\n";
    return 0;
  }
  out << "slide: " << slide.nodes.x() << " x " << slide.nodes.y() << " x " << slide.nodes.z()
      << " nodes, " << model->masses().sum() << " kg, v0 " << slide.v0 << " m/s, mu " << slide.mu
      << "\n"
      << std::setprecision(5) << "distance          " << result.distance << " m\n"
      << "theory v0^2/2mug  " << result.theory_distance << " m ("
      << 100.0 * (result.distance / result.theory_distance - 1.0) << " %)\n"
      << "simulated         " << result.seconds_simulated << " s"
      << (result.stopped ? "" : " (did not stop)") << "\n"
      << "time: " << seconds << " s\n";
  return 0;
}

}  // namespace

int RunLabCommand(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  switch (arguments.command) {
    case LabCommand::kCompression:
      return RunCompression(arguments, out, err);
    case LabCommand::kDeflection:
      return RunDeflection(arguments, out, err);
    case LabCommand::kPoissonSweep:
      return RunPoissonSweep(arguments, out, err);
    case LabCommand::kBuild:
      return RunBuild(arguments, out);
    case LabCommand::kSlide:
      return RunSlide(arguments, out);
    case LabCommand::kRealtime:
      return RunRealtime(arguments, out);
    case LabCommand::kIndent:
      return RunIndent(arguments, out);
    case LabCommand::kFit:
      return RunFit(arguments, out, err);
    case LabCommand::kGrip:
      return RunGrip(arguments, out);
    case LabCommand::kGrasp:
      return RunGrasp(arguments, out);
    case LabCommand::kMaterial:
      return RunMaterial(arguments, out);
    case LabCommand::kSqueeze:
      return RunSqueeze(arguments, out, err);
  }
  return 1;
}

}  // namespace msm_sim::lab
