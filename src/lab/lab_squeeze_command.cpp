#include "lab_squeeze_command.h"

#include <chrono>
#include <iomanip>
#include <memory>

#include "lab_grasp_command.h"
#include "lab_model.h"
#include "lab_report.h"
#include "msm_sim/experiments/squeeze_experiment.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::lab {
namespace {

core::SqueezeExperimentOptions SqueezeOptions(const LabArguments& arguments) {
  const SqueezeArguments& squeeze = arguments.squeeze;
  core::SqueezeExperimentOptions options;
  options.approach = squeeze.approach;
  options.speed = squeeze.speed;
  options.friction = squeeze.friction;
  options.damping_beta = squeeze.damping;
  options.orientation_threshold = squeeze.orientation_threshold;
  options.samples = squeeze.samples;
  options.integrator = IntegratorNamed(squeeze.integrator);
  options.time_step_safety = squeeze.time_step_safety;
  return options;
}

void PrintSqueeze(const LabArguments& arguments, const core::Model& model,
                  const core::SqueezeExperimentResult& r, std::ostream& out) {
  const SqueezeArguments& squeeze = arguments.squeeze;
  out << "squeeze: " << arguments.grasp.shape << " between two rigid flat plates, mu "
      << squeeze.friction << ", approach " << 1e3 * squeeze.approach << " mm at "
      << 1e3 * squeeze.speed << " mm/s a plate\n";
  PrintModelTable(arguments.model, core::ComputeModelStatistics(model), out);
  out << std::fixed << "height           " << std::setprecision(3) << 1e3 * r.height << " mm\n\n"
      << "  approach [mm]   force [N]   patch radius [mm]   patch area [mm^2]\n";
  for (const core::SqueezeSample& row : r.profile) {
    out << std::setprecision(3) << std::setw(15) << 1e3 * row.approach << std::setprecision(4)
        << std::setw(12) << row.force << std::setprecision(2) << std::setw(20)
        << 1e3 * row.contact_radius << std::setprecision(1) << std::setw(20)
        << 1e6 * row.contact_area << "\n";
  }
  out << std::defaultfloat << "simulated        " << r.seconds_simulated << " s\n";
}

}  // namespace

int RunSqueeze(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  const core::SqueezeExperimentOptions options = SqueezeOptions(arguments);
  const auto model =
      std::make_shared<const core::Model>(BuildLabModel(arguments.model, GraspBody(arguments)));
  const core::SqueezeExperimentResult r = core::RunSqueezeExperiment(model, options);
  if (r.folded_corners > 0) {
    // A folded lattice's spring forces are no elastic body's: no force is reported.
    err << "msm_lab: error: squeeze: " << r.folded_corners
        << " lattice cell corners turned inside out at an approach of " << r.folded_at
        << " m; use a finer spacing, a smaller approach or a higher --orientation-threshold\n";
    return 1;
  }
  if (!arguments.json) {
    PrintSqueeze(arguments, *model, r, out);
    return 0;
  }
  Json profile = Json::array(), area = Json::array();
  for (const core::SqueezeSample& row : r.profile) {
    profile.push_back({row.approach, row.force, row.contact_radius});
    area.push_back(row.contact_area);
  }
  const Json json{{"command", "squeeze"},
                  {"shape", arguments.grasp.shape},
                  {"spring", arguments.model.spring},
                  {"friction", arguments.squeeze.friction},
                  {"speed", arguments.squeeze.speed},
                  {"integrator", arguments.squeeze.integrator},
                  {"nodes", r.nodes},
                  {"added_mass", model->added_mass()},
                  {"spacing", model->characteristic_length()},
                  {"height", r.height},
                  {"profile", profile},
                  {"area", area},
                  {"seconds_simulated", r.seconds_simulated},
                  {"seconds", Seconds(start)}};
  out << json.dump() << "\n";
  return 0;
}

}  // namespace msm_sim::lab
