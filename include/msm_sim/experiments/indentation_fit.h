#pragma once

#include <array>
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

/// How finely a lattice must resolve a spherical contact for its force to follow Hertz's: at
/// least this many lattice spacings across the largest contact radius sqrt(R delta_max)
/// (docs/physics.md §6.1; docs/design/indentation-fit.md measures the force against Hertz's).
inline constexpr double kNodesAcrossContactRadius = 4.0;

/// The most nodes `msm_lab fit` builds to resolve a contact. A block 10 contact radii wide and
/// deep, all that Hertz's contact needs (docs/design/indentation-fit.md), has about 40^3
/// nodes at 4 across the contact radius: the budget leaves three times that
/// volume. Past it a fit's cost, nodes times steps (a finer spacing also shortens the stable
/// step), grows without making E more accurate; docs/lab.md ("fit") explains the choice.
inline constexpr double kIndentationFitNodeBudget = 200'000;

/// The resolution of a fit's lattice relative to the contact it simulates.
struct ContactResolution {
  double contact_radius = 0.0;  ///< m, sqrt(R delta_max): Hertz's at the deepest depth
  double spacing = 0.0;         ///< m, the lattice spacing
  double nodes_across = 0.0;    ///< contact_radius / spacing
};

/// The resolution of `spacing` for a sphere of radius `sphere_radius` pressed to the curve's
/// deepest depth. Throws std::invalid_argument for an empty curve or a non-positive radius or
/// spacing.
ContactResolution ResolutionOf(const std::vector<IndentationPoint>& curve, double sphere_radius,
                               double spacing);

/// The coarsest spacing that resolves the contact: kNodesAcrossContactRadius spacings across
/// the largest contact radius of the curve (same preconditions as ResolutionOf).
ContactResolution ResolvingResolution(const std::vector<IndentationPoint>& curve,
                                      double sphere_radius);

/// The simulated profile of one sample made of a material (E in Pa, ν).
using MaterialSimulator =
    std::function<std::vector<IndentationSample>(double youngs, double poisson)>;

struct MaterialFitOptions {
  double lowest_poisson = 0.0;       ///< the bracket searched for ν, within (-1, 0.5)
  double highest_poisson = 0.495;    ///< > lowest_poisson
  double poisson_tolerance = 0.002;  ///< stop when the bracket is this narrow
  int max_poisson_trials = 14;       ///< >= 2
  /// The inner fits of E to the first curve (their poisson is each trial's).
  IndentationFitOptions youngs;
};

struct MaterialFitResult {
  double youngs = 0.0;           ///< Pa, fitted to the first curve at `poisson`
  double poisson = 0.0;          ///< the root of g (below)
  double residual = 0.0;         ///< the first curve's, as IndentationFitResult::residual
  double second_residual = 0.0;  ///< the second curve's at (youngs, poisson)
  int simulations = 0;           ///< of both samples
  /// The bracket narrowed to the tolerance, or a trial inside it had |g| within the E fit's.
  bool converged = false;
  /// Every trial: ν, the E fitted at it and g = log s2 (the second curve's least-squares scale).
  std::vector<std::array<double, 3>> trials;
};

/// Fits E and ν to two curves on samples whose force depends differently on ν (docs/physics.md
/// §6.1): e.g. a block much thicker than the contact, whose force follows E/(1 − ν²), and a thin
/// layer clamped at its base, which stiffens sharply as ν approaches ½. For each trial ν, E is
/// fitted to the first curve (FitYoungsModulus with `simulate_first`); ν is then the root of
/// g(ν) = log s2, s2 the least-squares scale of the second sample's simulated curve at (E(ν), ν)
/// onto the second measured curve. g falls as ν rises (the second sample stiffens relative to
/// the first); the root is found by bisection with regula-falsi (Illinois) steps. Throws
/// std::invalid_argument for bad options and std::runtime_error if g does not change sign over
/// the bracket or changes by less than twice the E fit's tolerance (the two curves do not
/// determine ν there), or a simulation gives no force.
MaterialFitResult FitYoungsAndPoisson(const std::vector<IndentationPoint>& first,
                                      const std::vector<IndentationPoint>& second,
                                      const MaterialSimulator& simulate_first,
                                      const MaterialSimulator& simulate_second,
                                      const MaterialFitOptions& options);

}  // namespace msm_sim::core
