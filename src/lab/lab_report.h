#pragma once
// What every lab command reports the same way: the model's statistics, the static solver's
// outcome and the time taken, as JSON fields or table lines.

#include <chrono>
#include <ostream>

#include <nlohmann/json.hpp>

#include "lab_arguments.h"
#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::lab {

/// Keys keep the order they are inserted in, so that the JSON reads like the table.
using Json = nlohmann::ordered_json;

/// nodes, springs, mean_springs_per_node, mean_spring_length, spring_length_stddev, total_mass,
/// added_mass.
Json ModelJson(const core::ModelStatistics& stats);

/// converged, newton_iterations, cg_iterations, max_residual_force.
Json SolverJson(const core::StaticSolverReport& report);

/// The table's model lines: which lattice and springs, then its statistics.
void PrintModelTable(const ModelArguments& arguments, const core::ModelStatistics& stats,
                     std::ostream& out);

/// Wall-clock seconds since `start`.
double Seconds(std::chrono::steady_clock::time_point start);

/// Writes the one error line of a static solve that did not converge; returns exit code 1.
int ReportSolverFailure(const core::StaticSolverReport& report, std::ostream& err);

}  // namespace msm_sim::lab
