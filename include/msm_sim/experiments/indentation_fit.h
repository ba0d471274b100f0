#pragma once

#include <functional>
#include <vector>

#include "msm_sim/experiments/indentation_curve.h"
#include "msm_sim/experiments/indentation_experiment.h"

namespace msm_sim::core {

/// The simulated indentation profile (RunIndentationExperiment's) of the sample's geometry made of
/// a material of Young's modulus `youngs` (Pa), to at least the measured curve's deepest depth.
using IndentationSimulator = std::function<std::vector<IndentationSample>(double youngs)>;

struct IndentationFitOptions {
  double poisson = 0.49;        ///< nu of the sample, in (-1, 0.5): Hertz's starting estimate
  double sphere_radius = 0.01;  ///< m, > 0: Hertz's starting estimate
  /// Stop when the simulated curve, scaled by least squares onto the measured one, needs a scale
  /// within this relative distance of 1.
  double tolerance = 1e-3;
  int max_simulations = 12;  ///< >= 2
};

struct IndentationFitResult {
  double youngs = 0.0;        ///< Pa: the simulated modulus whose curve fits best
  double hertz_youngs = 0.0;  ///< Pa: the start, Hertz's least-squares modulus of the curve
  /// RMS over the measured points of (simulated − measured force) at `youngs`, divided by the
  /// largest measured force.
  double residual = 0.0;
  int simulations = 0;
  bool converged = false;     ///< false: max_simulations ran out; `youngs` is the best one seen
  std::vector<double> tried;  ///< Pa, every simulated modulus in order
};

/// The modulus E for which Hertz's force 4/3 E/(1 − ν²) √R δ^{3/2} fits the curve best in least
/// squares (docs/physics.md §6.1). Throws std::invalid_argument if no point has depth > 0 or the
/// forces do not add up to a positive fit.
double HertzYoungsModulus(const std::vector<IndentationPoint>& curve, double poisson,
                          double sphere_radius);

/// The least-squares scale s minimising Σ (F_measured − s F_simulated)² over the curve's points,
/// F_simulated read from the profile by ProfileForceAt; 0 when the profile has no force there.
double LeastSquaresScale(const std::vector<IndentationPoint>& curve,
                         const std::vector<IndentationSample>& profile);

/// Finds the Young's modulus whose simulated indentation reproduces the measured curve
/// (docs/physics.md §6.1): a 1-D search on g(log E) = log s(E), s the least-squares scale above,
/// which is 0 at the fit and falls with slope about −1 (force is nearly proportional to E at fixed
/// geometry and ν). It starts at Hertz's estimate, takes one fixed-point step E ← s E, then secant
/// steps (a step whose secant slope is not negative falls back to the fixed-point step; steps are
/// limited to a factor of 4 in E). Preconditions: `curve` from ReadIndentationCurve; `simulate`
/// returns a non-empty profile for every E > 0. Throws std::invalid_argument for bad options and
/// std::runtime_error if a simulation gives no positive force at the measured depths.
IndentationFitResult FitYoungsModulus(const std::vector<IndentationPoint>& curve,
                                      const IndentationSimulator& simulate,
                                      const IndentationFitOptions& options);

}  // namespace msm_sim::core
