#include "msm_sim/experiments/indentation_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

}  // namespace msm_sim::core
