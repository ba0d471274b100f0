#include "msm_sim/experiments/indentation_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace msm_sim::core {
namespace {

// A secant step larger than this factor in E is cut back (a noisy or flat secant).
const double kLargestLogStep = std::log(4.0);

double RelativeResidual(const std::vector<IndentationPoint>& curve,
                        const std::vector<IndentationSample>& profile) {
  double squares = 0.0, largest = 0.0;
  for (const IndentationPoint& point : curve) {
    const double difference = ProfileForceAt(profile, point.depth) - point.force;
    squares += difference * difference;
    largest = std::max(largest, std::abs(point.force));
  }
  return largest > 0.0 ? std::sqrt(squares / static_cast<double>(curve.size())) / largest : 0.0;
}

void CheckOptions(const std::vector<IndentationPoint>& curve,
                  const IndentationFitOptions& options) {
  if (curve.empty()) throw std::invalid_argument("the indentation curve is empty");
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    throw std::invalid_argument("fit tolerance must be finite and > 0");
  }
  if (options.max_simulations < 2) throw std::invalid_argument("max_simulations must be >= 2");
}

// One simulation at exp(log_youngs): records it and returns g = log(scale).
struct FitSearch {
  const std::vector<IndentationPoint>& curve;
  const IndentationSimulator& simulate;
  IndentationFitResult* result;
  double best_g = INFINITY;

  double Evaluate(double log_youngs) {
    const double youngs = std::exp(log_youngs);
    const std::vector<IndentationSample> profile = simulate(youngs);
    ++result->simulations;
    result->tried.push_back(youngs);
    const double scale = LeastSquaresScale(curve, profile);
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      throw std::runtime_error("the simulation at E = " + std::to_string(youngs) +
                               " Pa gives no positive force at the measured depths");
    }
    const double g = std::log(scale);
    if (std::abs(g) < std::abs(best_g)) {
      best_g = g;
      result->youngs = youngs;
      result->residual = RelativeResidual(curve, profile);
    }
    return g;
  }
};

}  // namespace

double HertzYoungsModulus(const std::vector<IndentationPoint>& curve, double poisson,
                          double sphere_radius) {
  double fitted = 0.0, squares = 0.0;
  for (const IndentationPoint& point : curve) {
    const double unit = HertzForce(1.0, poisson, sphere_radius, point.depth);  // F at E = 1 Pa
    fitted += point.force * unit;
    squares += unit * unit;
  }
  if (!(squares > 0.0)) throw std::invalid_argument("the curve has no point deeper than 0");
  if (!(fitted > 0.0)) throw std::invalid_argument("the curve's forces are not positive");
  return fitted / squares;
}

double LeastSquaresScale(const std::vector<IndentationPoint>& curve,
                         const std::vector<IndentationSample>& profile) {
  double cross = 0.0, squares = 0.0;
  for (const IndentationPoint& point : curve) {
    const double simulated = ProfileForceAt(profile, point.depth);
    cross += point.force * simulated;
    squares += simulated * simulated;
  }
  return squares > 0.0 ? cross / squares : 0.0;
}

ContactResolution ResolutionOf(const std::vector<IndentationPoint>& curve, double sphere_radius,
                               double spacing) {
  if (curve.empty()) throw std::invalid_argument("the indentation curve is empty");
  if (!(sphere_radius > 0.0) || !(spacing > 0.0) || !std::isfinite(sphere_radius + spacing)) {
    throw std::invalid_argument("the sphere radius and the spacing must be finite and > 0");
  }
  ContactResolution resolution;
  resolution.contact_radius = std::sqrt(sphere_radius * curve.back().depth);
  resolution.spacing = spacing;
  resolution.nodes_across = resolution.contact_radius / spacing;
  return resolution;
}

ContactResolution ResolvingResolution(const std::vector<IndentationPoint>& curve,
                                      double sphere_radius) {
  if (curve.empty() || !(curve.back().depth > 0.0)) {
    throw std::invalid_argument("the indentation curve has no depth > 0");
  }
  const double contact_radius = std::sqrt(sphere_radius * curve.back().depth);
  return ResolutionOf(curve, sphere_radius, contact_radius / kNodesAcrossContactRadius);
}

IndentationFitResult FitYoungsModulus(const std::vector<IndentationPoint>& curve,
                                      const IndentationSimulator& simulate,
                                      const IndentationFitOptions& options) {
  CheckOptions(curve, options);
  IndentationFitResult result;
  result.hertz_youngs = HertzYoungsModulus(curve, options.poisson, options.sphere_radius);
  FitSearch search{curve, simulate, &result};
  const double tolerance = std::log1p(options.tolerance);
  double x0 = std::log(result.hertz_youngs);
  double g0 = search.Evaluate(x0);
  if (std::abs(g0) <= tolerance) {
    result.converged = true;
    return result;
  }
  double x1 = x0 + std::clamp(g0, -kLargestLogStep, kLargestLogStep);  // E <- s E
  while (result.simulations < options.max_simulations) {
    const double g1 = search.Evaluate(x1);
    if (std::abs(g1) <= tolerance) {
      result.converged = true;
      break;
    }
    const double slope = (g1 - g0) / (x1 - x0);
    const double step = slope < 0.0 ? -g1 / slope : g1;
    x0 = x1;
    g0 = g1;
    x1 += std::clamp(step, -kLargestLogStep, kLargestLogStep);
  }
  return result;
}

namespace {

// One trial ν of FitYoungsAndPoisson: E fitted to the first curve, g of the second.
struct PoissonTrial {
  double poisson = 0.0, youngs = 0.0, g = 0.0, residual = 0.0, second_residual = 0.0;
};

void CheckMaterialFitOptions(const MaterialFitOptions& options) {
  const double lo = options.lowest_poisson, hi = options.highest_poisson;
  if (!(lo > -1.0) || !(hi < 0.5) || !(lo < hi)) {
    throw std::invalid_argument(
        "the Poisson's ratio bracket must satisfy -1 < lowest < highest < 0.5");
  }
  if (!(options.poisson_tolerance > 0.0) || options.max_poisson_trials < 2) {
    throw std::invalid_argument("poisson_tolerance must be > 0 and max_poisson_trials >= 2");
  }
}

// Regula falsi with the Illinois modification on g(nu) between two trials of opposite sign.
// Returns the first interior trial with |g| within the tolerance, else the end of the final
// bracket with the smaller |g|; *converged when either happened. A bracket end is never taken
// for small |g| alone: near nu = 1/2 an unresolved lattice's g need not be monotonic, and noise
// can bring an end within the tolerance far from the sign change the bracket closes on.
PoissonTrial BracketedPoissonRoot(PoissonTrial low, PoissonTrial high,
                                  const std::function<PoissonTrial(double)>& trial,
                                  const MaterialFitOptions& options, bool* converged) {
  double g_low = low.g, g_high = high.g;  // Illinois: the stuck end's g is halved
  int last_moved = 0;                     // -1 low, +1 high
  const double g_tolerance = std::log1p(options.youngs.tolerance);
  for (int trials = 2; trials < options.max_poisson_trials &&
                       high.poisson - low.poisson > options.poisson_tolerance;
       ++trials) {
    double poisson = (low.poisson * g_high - high.poisson * g_low) / (g_high - g_low);
    if (!(poisson > low.poisson && poisson < high.poisson)) {
      poisson = 0.5 * (low.poisson + high.poisson);
    }
    const PoissonTrial t = trial(poisson);
    if (std::abs(t.g) <= g_tolerance) {
      *converged = true;
      return t;
    }
    if ((t.g > 0.0) == (low.g > 0.0)) {
      low = t;
      g_low = t.g;
      if (last_moved == -1) g_high *= 0.5;
      last_moved = -1;
    } else {
      high = t;
      g_high = t.g;
      if (last_moved == 1) g_low *= 0.5;
      last_moved = 1;
    }
  }
  *converged = high.poisson - low.poisson <= options.poisson_tolerance;
  return std::abs(low.g) < std::abs(high.g) ? low : high;
}

}  // namespace

MaterialFitResult FitYoungsAndPoisson(const std::vector<IndentationPoint>& first,
                                      const std::vector<IndentationPoint>& second,
                                      const MaterialSimulator& simulate_first,
                                      const MaterialSimulator& simulate_second,
                                      const MaterialFitOptions& options) {
  CheckMaterialFitOptions(options);
  if (second.empty()) throw std::invalid_argument("the second indentation curve is empty");
  MaterialFitResult result;
  const std::function<PoissonTrial(double)> trial = [&](double poisson) {
    IndentationFitOptions inner = options.youngs;
    inner.poisson = poisson;
    const IndentationFitResult fit = FitYoungsModulus(
        first, [&](double youngs) { return simulate_first(youngs, poisson); }, inner);
    const std::vector<IndentationSample> profile = simulate_second(fit.youngs, poisson);
    result.simulations += fit.simulations + 1;
    const double scale = LeastSquaresScale(second, profile);
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      throw std::runtime_error(
          "the second sample's simulation gives no positive force at its "
          "measured depths");
    }
    const PoissonTrial t{poisson, fit.youngs, std::log(scale), fit.residual,
                         RelativeResidual(second, profile)};
    result.trials.push_back({t.poisson, t.youngs, t.g});
    return t;
  };
  PoissonTrial low = trial(options.lowest_poisson), high = trial(options.highest_poisson);
  // Samples that respond alike to nu (g the same at both ends) cannot determine it.
  const bool alike = std::abs(low.g - high.g) <= 2.0 * std::log1p(options.youngs.tolerance);
  if (alike || (low.g > 0.0) == (high.g > 0.0)) {
    throw std::runtime_error(
        "no Poisson's ratio in [" + std::to_string(options.lowest_poisson) + ", " +
        std::to_string(options.highest_poisson) +
        "] reproduces both curves: the two samples must respond differently to nu (e.g. a block "
        "much thicker than the contact and a thin layer clamped at its base)");
  }
  bool converged = false;
  const PoissonTrial best = BracketedPoissonRoot(low, high, trial, options, &converged);
  result.converged = converged;
  result.youngs = best.youngs;
  result.poisson = best.poisson;
  result.residual = best.residual;
  result.second_residual = best.second_residual;
  return result;
}

}  // namespace msm_sim::core
