#pragma once

#include <vector>

#include "msm_sim/experiments/tensile_curve.h"
#include "msm_sim/material/power_spring_law.h"

namespace msm_sim::core {

struct TensileFitOptions {
  double max_strain = 1.0;  ///< fit the points with 0 < strain <= this, > 0
  double poisson = 0.49;    ///< nu of the model, in (-1, 0.5)
};

struct TensileFitResult {
  double youngs = 0.0;  ///< Pa, the model's small-strain modulus
  PowerSpringLaw law;   ///< docs/physics.md §4.1
  /// RMS over the fitted points of (model − measured stress), divided by the largest measured
  /// stress among them.
  double rms_error = 0.0;
  double max_stress = 0.0;           ///< Pa, the largest measured stress fitted
  std::vector<TensilePoint> fitted;  ///< the measured points fitted
  std::vector<double> model_stress;  ///< Pa, the model's stress at each of them
  int evaluations = 0;               ///< laws tried
};

/// The measured points with 0 < strain <= max_strain. Throws std::invalid_argument if fewer than
/// 5 remain or their largest stress is not positive.
std::vector<TensilePoint> TensileFitRange(const std::vector<TensilePoint>& curve,
                                          double max_strain);

/// The model's engineering stress (Pa) at each point's strain: LatticeUniaxialTension
/// (docs/physics.md §4.1) for the material (youngs, poisson) with springs following `law`.
std::vector<double> ModelTensileStress(const std::vector<TensilePoint>& points, double youngs,
                                       double poisson, const PowerSpringLaw& law);

/// RMS of (model − measured) over `points` as a fraction of their largest measured stress.
double TensileRmsError(const std::vector<TensilePoint>& points,
                       const std::vector<double>& model_stress);

/// Fits E and the law (alpha in [-12, 1], beta in [0, 2]) so that the lattice's uniaxial
/// response follows the curve up to options.max_strain, in least squares (docs/physics.md §4.1):
/// the response is proportional to E at a fixed law, so E is the least-squares scale for each
/// (alpha, beta), and (alpha, beta) minimise the RMS error by a grid search refined by a
/// pattern search. Deterministic. Throws std::invalid_argument for bad options or range.
TensileFitResult FitTensileCurve(const std::vector<TensilePoint>& curve,
                                 const TensileFitOptions& options);

}  // namespace msm_sim::core
