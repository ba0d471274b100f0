#include "lab_deflection_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <optional>

#include "lab_model.h"
#include "lab_reference.h"
#include "lab_report.h"
#include "msm_sim/experiments/cantilever_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::lab {
namespace {

// True if the cantilever is clamped and loaded at its faces: asked for, or by default wherever
// face anchors can be built (an unrotated node-centred cubic lattice in the box).
bool DeflectionAtFaces(const LabArguments& arguments) {
  if (!arguments.ends.empty()) return arguments.ends == "faces";
  const ModelArguments& model = arguments.model;
  return model.model == "cubic" && model.construction == "node" && !model.rotate;
}

// For an unrotated node-centred cubic lattice: whether its free faces' bending stiffness was
// restored, and if not, how much EI the lattice misses at its cells through the height
// (docs/physics.md §2.1).
void PrintFreeFaces(const LabArguments& arguments, std::ostream& out) {
  const ModelArguments& model = arguments.model;
  if (model.model != "cubic" || model.construction != "node" || model.rotate) return;
  const int across = std::max(1, static_cast<int>(std::lround(model.size.z() / model.spacing)));
  if (model.free_face_bending && across >= 4) {
    out << "free faces       bending stiffness restored (--free-face-bending)\n";
    return;
  }
  out << std::setprecision(3) << "free faces       not corrected"
      << (model.free_face_bending ? " (fewer than 4 cells through the height)" : "")
      << ": EI low by " << 100.0 * core::FreeFaceBendingDeficit(across) << " % at " << across
      << " cells through the height"
      << (model.free_face_bending ? "" : " (--free-face-bending restores it)") << "\n"
      << std::setprecision(5);
}

// The text report of RunDeflection.
void PrintDeflection(const LabArguments& arguments, const core::ModelStatistics& stats, bool faces,
                     const core::CantileverExperimentResult& result,
                     const std::optional<LabReference>& reference, double seconds,
                     std::ostream& out) {
  out << "cantilever, clamped at x = 0, force " << arguments.force << " N in -z at the end ("
      << (faces ? "faces" : "node layers") << ")\n";
  PrintModelTable(arguments.model, stats, out);
  out << std::setprecision(5) << "beam length      " << result.beam_length
      << (faces ? " m (the body's length)\n\n" : " m (frozen layer to loaded layer)\n\n")
      << "       x [m]   deflection [m]   Euler-Bernoulli [m]\n";
  for (const core::DeflectionSample& sample : result.profile) {
    out << std::setw(12) << sample.x << "  " << std::setw(15) << sample.deflection << "  "
        << std::setw(18) << sample.theory << "\n";
  }
  out << "\ntip deflection   " << result.tip_deflection << " m, theory "
      << result.theory_tip_deflection << " m ("
      << 100.0 * (result.tip_deflection / result.theory_tip_deflection - 1.0) << " %)\n"
      << "end face         " << result.end_face_deflection << " m (x = L, extrapolated; "
      << 100.0 * (result.end_face_deflection / result.theory_tip_deflection - 1.0)
      << " % from the theory at L)\n";
  PrintFreeFaces(arguments, out);
  if (reference) PrintReference(*reference, result.end_face_deflection, out);
  out << "solver: " << result.solver.message << "\n"
      << "time: " << seconds << " s\n";
}

}  // namespace

int RunDeflection(const LabArguments& arguments, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  const bool faces = DeflectionAtFaces(arguments);
  core::BodyRecipe recipe = LabRecipe(arguments.model, LoadLabBody(arguments.model, true));
  if (faces) recipe.surface.anchored_planes.push_back(core::AnchoredPlane{});  // the face x = 0
  const core::Model model = core::BuildModel(recipe);
  const core::ModelStatistics stats = core::ComputeModelStatistics(model);
  const double build_seconds = Seconds(start);
  // Before the lattice's solve, so that a missing ccx or a refused mesh fails fast; its time is
  // reported apart (reference_seconds), not in `seconds`.
  const std::optional<LabReference> reference = RunLabReference(arguments);
  const auto solve_start = std::chrono::steady_clock::now();
  core::CantileverExperimentOptions options;
  options.body_size = arguments.model.size;
  options.total_force = arguments.force;
  options.ends = faces ? core::CantileverEnds::kFaces : core::CantileverEnds::kNodeLayers;
  const core::CantileverExperimentResult result = core::RunCantileverExperiment(model, options);
  if (!result.solver.converged) return ReportSolverFailure(result.solver, err);
  const double seconds = build_seconds + Seconds(solve_start);

  if (arguments.json) {
    Json profile = Json::array();
    for (const core::DeflectionSample& sample : result.profile) {
      profile.push_back({sample.x, sample.deflection, sample.theory});
    }
    Json json{{"command", "deflection"},
              {"model", arguments.model.model},
              {"youngs_target", arguments.model.youngs},
              {"poisson_target", arguments.model.poisson},
              {"force", arguments.force},
              {"ends", faces ? "faces" : "layers"},
              {"free_face_bending", arguments.model.free_face_bending},
              {"tip_deflection", result.tip_deflection},
              {"end_face_deflection", result.end_face_deflection},
              {"theory_tip_deflection", result.theory_tip_deflection},
              {"beam_length", result.beam_length},
              {"profile", profile}};
    if (reference) AddReferenceJson(*reference, &json);
    json.update(ModelJson(stats));
    json["solver"] = SolverJson(result.solver);
    json["seconds"] = seconds;
    out << json.dump() << "\n";
    return 0;
  }
  PrintDeflection(arguments, stats, faces, result, reference, seconds, out);
  return 0;
}

}  // namespace msm_sim::lab
