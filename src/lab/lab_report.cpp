#include "lab_report.h"

namespace msm_sim::lab {

Json ModelJson(const core::ModelStatistics& stats) {
  return Json{{"nodes", stats.nodes},
              {"springs", stats.springs},
              {"mean_springs_per_node", stats.mean_springs_per_node},
              {"mean_spring_length", stats.mean_spring_length},
              {"spring_length_stddev", stats.spring_length_stddev},
              {"total_mass", stats.total_mass},
              {"added_mass", stats.added_mass}};
}

Json SolverJson(const core::StaticSolverReport& report) {
  return Json{{"converged", report.converged},
              {"newton_iterations", report.newton_iterations},
              {"cg_iterations", report.linear_iterations},
              {"max_residual_force", report.max_residual_force}};
}

void PrintModelTable(const ModelArguments& arguments, const core::ModelStatistics& stats,
                     std::ostream& out) {
  out << "model            " << arguments.model
      << (arguments.model != "cubic"           ? ""
          : arguments.construction == "corner" ? " (element-corner)"
                                               : " (node-centred)")
      << (arguments.poisson != 0.25 && arguments.model != "baudet" ? ", extended MSM" : "") << ", "
      << arguments.spring << " springs";
  if (arguments.surface_dispersion != 1.0) {
    out << ", outer layer keeping " << arguments.surface_dispersion
        << " of its bulk (--surface-dispersion)";
  }
  out << "\n"
      << "nodes            " << stats.nodes << "\n"
      << "springs          " << stats.springs << "\n"
      << "<S>              " << stats.mean_springs_per_node << "\n"
      << "<L>, dL          " << stats.mean_spring_length << " m, " << stats.spring_length_stddev
      << " m\n"
      << "total mass       " << stats.total_mass << " kg\n";
  if (stats.added_mass > 0.0) {
    out << "added mass       " << stats.added_mass << " kg (mass scaling of cut cells)\n";
  }
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int ReportSolverFailure(const core::StaticSolverReport& report, std::ostream& err) {
  err << "msm_lab: error: static equilibrium " << report.message << "\n";
  return 1;
}

}  // namespace msm_sim::lab
