#include "lab_dynamics_commands.h"

#include <chrono>
#include <iomanip>
#include <memory>
#include <stdexcept>

#include "lab_model.h"
#include "lab_report.h"
#include "msm_sim/experiments/grip_experiment.h"
#include "msm_sim/experiments/indentation_experiment.h"
#include "msm_sim/experiments/realtime_experiment.h"
#include "msm_sim/model/model_statistics.h"
#include "sweep_plot.h"

namespace msm_sim::lab {
namespace {

core::SpringPrecision PrecisionNamed(const std::string& name) {
  return name == "single" ? core::SpringPrecision::kSingle : core::SpringPrecision::kDouble;
}

std::shared_ptr<const core::Model> LabBlock(const ModelArguments& model) {
  return std::make_shared<const core::Model>(BuildLabModel(model, LoadLabBody(model, true)));
}

// The table's first line: the block and the sphere.
void PrintScene(const LabArguments& arguments, const char* what, std::ostream& out) {
  const Eigen::Vector3d& size = arguments.model.size;
  out << what << ": block " << size.x() << " x " << size.y() << " x " << size.z()
      << " m, sphere radius " << arguments.contact.sphere_radius << " m, dampers beta "
      << arguments.contact.damping << " s\n";
}

}  // namespace

int RunRealtime(const LabArguments& arguments, std::ostream& out) {
  const ContactArguments& contact = arguments.contact;
  core::RealtimeExperimentOptions options;
  options.sphere_radius = contact.sphere_radius;
  options.seconds = contact.seconds;
  options.damping_beta = contact.damping;
  options.integrator = IntegratorNamed(contact.integrator);
  options.threads = contact.threads;
  options.spring_precision = PrecisionNamed(contact.precision);
  options.time_step_safety = contact.time_step_safety;
  const auto model = LabBlock(arguments.model);
  const core::RealtimeExperimentResult result = core::RunRealtimeExperiment(model, options);
  if (arguments.json) {
    const Json json{{"nodes", result.nodes},
                    {"added_mass", model->added_mass()},
                    {"springs", result.springs},
                    {"integrator", result.integrator},
                    {"step", result.step},
                    {"substeps", result.substeps},
                    {"wall_per_simulated_second", result.wall_per_simulated_second},
                    {"real_time_factor", result.real_time_factor},
                    {"peak_force", result.peak_force}};
    out << json.dump() << "\n";
    return 0;
  }
  PrintScene(arguments, "real-time run, block on the ground", out);
  PrintModelTable(arguments.model, core::ComputeModelStatistics(*model), out);
  out << std::setprecision(4) << "sphere speed     " << options.speed << " m/s, down\n"
      << "integrator       " << result.integrator << ", step " << 1e3 * result.step << " ms in "
      << result.substeps << " substeps of " << 1e3 * result.substep << " ms";
  if (options.integrator == core::Integrator::kImplicit) {
    out << ", " << result.solver_iterations_per_step << " CG iterations per step";
  }
  out << "\n"
      << "simulated        " << result.seconds_simulated << " s in " << result.wall_seconds
      << " s\n"
      << "wall / simulated " << result.wall_per_simulated_second << "\n"
      << "real-time factor " << result.real_time_factor << "\n"
      << "peak force       " << result.peak_force << " N\n";
  if (result.substep_refinement > 1) {
    out << "substeps refined " << result.substep_refinement
        << "x finer after a step diverged at the stable step (docs/physics.md section 7)\n";
  }
  return 0;
}

namespace {

// The sphere started start_depth inside the block and held (penetration recovery), against
// the slow press's force at that depth; empty if no start depth was given.
Json RunHeldIndent(const core::IndentationExperimentOptions& pressed,
                   const core::IndentationExperimentResult& press, double start_depth,
                   std::shared_ptr<const core::Model> model) {
  if (!(start_depth > 0.0)) return Json();
  core::IndentationExperimentOptions options = pressed;
  options.start_depth = start_depth;
  const core::IndentationExperimentResult held = core::RunIndentationExperiment(model, options);
  return Json{{"start_depth", start_depth},
              {"overlap_before", held.overlap_before},
              {"overlap_after", held.overlap_after},
              {"force_after", held.force_after},
              {"slow_force", core::ProfileForceAt(press.profile, start_depth)},
              {"peak_kinetic", held.peak_kinetic},
              {"final_kinetic", held.final_kinetic},
              {"final_elastic", held.final_elastic}};
}

void PrintHeld(const Json& held, std::ostream& out) {
  if (held.is_null()) return;
  out << std::defaultfloat << std::setprecision(4) << "\nheld at "
      << 1e3 * held["start_depth"].get<double>() << " mm from the start, 0.2 s:\n"
      << "overlap          " << 1e3 * held["overlap_before"].get<double>() << " mm before, "
      << 1e3 * held["overlap_after"].get<double>() << " mm after\n"
      << "force after      " << held["force_after"].get<double>() << " N (slow press "
      << held["slow_force"].get<double>() << " N)\n"
      << "kinetic energy   " << held["peak_kinetic"].get<double>() << " J peak, "
      << held["final_kinetic"].get<double>() << " J after; elastic "
      << held["final_elastic"].get<double>() << " J\n";
}

}  // namespace

int RunIndent(const LabArguments& arguments, std::ostream& out) {
  const auto start = std::chrono::steady_clock::now();
  const ContactArguments& contact = arguments.contact;
  core::IndentationExperimentOptions options;
  options.sphere_radius = contact.sphere_radius;
  options.depth = contact.depth;
  options.speed = contact.speed;
  options.damping_beta = contact.damping;
  options.friction = contact.friction;
  options.integrator = IntegratorNamed(contact.integrator);
  options.spring_precision = PrecisionNamed(contact.precision);
  const auto model = LabBlock(arguments.model);
  const core::IndentationExperimentResult result = core::RunIndentationExperiment(model, options);
  const Json held = RunHeldIndent(options, result, contact.start_depth, model);
  Json profile = Json::array();
  for (const core::IndentationSample& row : result.profile) {
    profile.push_back({row.depth, row.force, row.hertz_force});
  }
  Json json{{"profile", profile},
            {"touch_depth", result.touch_depth},
            {"nodes", model->num_nodes()},
            {"added_mass", model->added_mass()},
            {"seconds", result.seconds_simulated},
            {"integrator", contact.integrator}};
  if (!held.is_null()) json.update(held);
  if (!arguments.plot.empty()) {
    const std::string failure = PlotIndentation(json.dump(), arguments.plot);
    if (!failure.empty()) throw std::runtime_error(failure);
  }
  if (arguments.json) {
    out << json.dump() << "\n";
    return 0;
  }
  PrintScene(arguments, "indentation, base clamped", out);
  PrintModelTable(arguments.model, core::ComputeModelStatistics(*model), out);
  out << "integrator       " << contact.integrator << ", step " << 1e3 * options.step << " ms\n"
      << "speed            " << contact.speed << " m/s, depth " << contact.depth
      << " m past first contact (at " << result.contact_time << " s), friction " << contact.friction
      << "\n\n"
      << "  depth [mm]   force [N]   Hertz [N]\n"
      << std::fixed;
  for (const core::IndentationSample& row : result.profile) {
    out << std::setprecision(4) << std::setw(12) << 1e3 * row.depth << std::setw(12) << row.force
        << std::setw(12) << row.hertz_force << "\n";
  }
  PrintHeld(held, out);
  if (!arguments.plot.empty()) out << "\nplot: " << arguments.plot << "\n";
  out << std::defaultfloat << std::setprecision(4) << "\nsimulated        "
      << result.seconds_simulated << " s\n"
      << "time: " << Seconds(start) << " s\n";
  return 0;
}

int RunGrip(const LabArguments& arguments, std::ostream& out) {
  const GripArguments& grip = arguments.grip;
  core::GripExperimentOptions options;
  options.hold_ratio = grip.ratio;
  options.squeeze = grip.squeeze;
  options.damping_beta = grip.damping;
  options.lift_time = grip.lift_time;
  options.integrator = IntegratorNamed(grip.integrator);
  const auto model = LabBlock(arguments.model);
  const core::GripExperimentResult r = core::RunGripExperiment(model, options);
  if (arguments.json) {
    const Json json{{"ratio", grip.ratio},
                    {"integrator", grip.integrator},
                    {"nodes", model->num_nodes()},
                    {"added_mass", model->added_mass()},
                    {"weight", r.weight},
                    {"normal_force", r.normal_force},
                    {"lift_normal_force", r.lift_normal_force_mean},
                    {"mu", r.friction},
                    {"slip", r.slip},
                    {"max_slip", r.max_slip},
                    {"seconds_lifted", r.seconds_lifted},
                    {"held", r.held}};
    out << json.dump() << "\n";
    return 0;
  }
  const Eigen::Vector3d& size = arguments.model.size;
  out << "grip: block " << size.x() << " x " << size.y() << " x " << size.z()
      << " m between two rigid jaws, squeezed " << 1e3 * grip.squeeze << " mm each, dampers beta "
      << grip.damping << " s\n";
  PrintModelTable(arguments.model, core::ComputeModelStatistics(*model), out);
  out << std::setprecision(4) << "integrator       " << grip.integrator << ", step "
      << 1e3 * options.step << " ms\n"
      << "weight m g       " << r.weight << " N\n"
      << "F_n per jaw      " << r.normal_force << " N before the lift, " << r.lift_normal_force_mean
      << " N during it (least " << r.lift_normal_force_min << " N)\n"
      << "mu               " << r.friction << " (2 mu F_n = " << grip.ratio << " m g)\n"
      << "slip             " << 1e3 * r.slip << " mm after " << r.seconds_lifted
      << " s of lift (largest " << 1e3 * r.max_slip << " mm)\n"
      << "verdict          "
      << (r.held        ? "held"
          : r.left_jaws ? "slid out of the jaws"
                        : "slipping")
      << "\n";
  return 0;
}

}  // namespace msm_sim::lab
