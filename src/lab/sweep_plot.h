#pragma once

#include <string>

namespace msm_sim::lab {

/// Writes a PNG plot of a poisson-sweep (its JSON text) with Debian's python3 and matplotlib.
/// Returns an empty string on success, otherwise a one-line reason.
std::string PlotPoissonSweep(const std::string& sweep_json, const std::string& png_path);

/// The same for `msm_lab indent --json`'s object (or a list of them): force and Hertz's force
/// against depth, and their ratio.
std::string PlotIndentation(const std::string& indent_json, const std::string& png_path);

/// The same for `msm_lab fit --tensile`'s object with its "curve" rows: the measured and the
/// model's stress against strain, and their difference.
std::string PlotTensileFit(const std::string& fit_json, const std::string& png_path);

}  // namespace msm_sim::lab
