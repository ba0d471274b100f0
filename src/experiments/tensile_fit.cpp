#include "msm_sim/experiments/tensile_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "msm_sim/mechanics/lattice_uniaxial_tension.h"

namespace msm_sim::core {
namespace {

constexpr double kAlphaMin = -12.0, kAlphaMax = 1.0;
constexpr double kBetaMin = 0.0, kBetaMax = 2.0;

// One law's best fit: E by least squares, and its RMS error (infinite where the lattice has no
// lateral equilibrium).
struct Trial {
  PowerSpringLaw law;
  double youngs = 0.0;
  double rms = std::numeric_limits<double>::infinity();
};

Trial Evaluate(const std::vector<TensilePoint>& points, double poisson, PowerSpringLaw law) {
  Trial trial;
  trial.law = law;
  std::vector<double> unit;
  try {
    unit = ModelTensileStress(points, 1.0, poisson, law);
  } catch (const std::runtime_error&) {
    return trial;
  }
  double cross = 0.0, square = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    cross += points[i].stress * unit[i];
    square += unit[i] * unit[i];
  }
  if (!(square > 0.0) || !(cross > 0.0)) return trial;
  trial.youngs = cross / square;
  for (double& stress : unit) stress *= trial.youngs;
  trial.rms = TensileRmsError(points, unit);
  return trial;
}

// The coarse grid's best law.
Trial GridSearch(const std::vector<TensilePoint>& points, double poisson, int* evaluations) {
  Trial best;
  for (double alpha = kAlphaMin; alpha <= kAlphaMax + 1e-9; alpha += 1.0) {
    for (double beta = kBetaMin; beta <= kBetaMax + 1e-9; beta += 0.1) {
      const Trial trial = Evaluate(points, poisson, PowerSpringLaw{alpha, beta});
      ++*evaluations;
      if (trial.rms < best.rms) best = trial;
    }
  }
  return best;
}

// Compass search from `start`: try ± step along alpha and beta, move to any improvement, halve
// the steps when none improves.
Trial PatternSearch(const std::vector<TensilePoint>& points, double poisson, Trial best,
                    int* evaluations) {
  double step_alpha = 0.5, step_beta = 0.05;
  while (step_alpha > 1e-4) {
    bool moved = false;
    const double moves[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& move : moves) {
      PowerSpringLaw law = best.law;
      law.alpha = std::clamp(law.alpha + move[0] * step_alpha, kAlphaMin, kAlphaMax);
      law.beta = std::clamp(law.beta + move[1] * step_beta, kBetaMin, kBetaMax);
      const Trial trial = Evaluate(points, poisson, law);
      ++*evaluations;
      if (trial.rms < best.rms - 1e-12) {
        best = trial;
        moved = true;
      }
    }
    if (!moved) {
      step_alpha *= 0.5;
      step_beta *= 0.5;
    }
  }
  return best;
}

}  // namespace

std::vector<TensilePoint> TensileFitRange(const std::vector<TensilePoint>& curve,
                                          double max_strain) {
  std::vector<TensilePoint> range;
  double largest = 0.0;
  for (const TensilePoint& point : curve) {
    if (point.strain > 0.0 && point.strain <= max_strain) {
      range.push_back(point);
      largest = std::max(largest, point.stress);
    }
  }
  if (range.size() < 5) {
    throw std::invalid_argument("the curve has " + std::to_string(range.size()) +
                                " points with strain in (0, " + std::to_string(max_strain) +
                                "]; the fit needs at least 5");
  }
  if (!(largest > 0.0)) throw std::invalid_argument("the curve's stresses are not positive");
  return range;
}

std::vector<double> ModelTensileStress(const std::vector<TensilePoint>& points, double youngs,
                                       double poisson, const PowerSpringLaw& law) {
  std::vector<double> stress;
  stress.reserve(points.size());
  for (const TensilePoint& point : points) {
    stress.push_back(LatticeUniaxialTension(point.strain, youngs, poisson, law).nominal_stress);
  }
  return stress;
}

double TensileRmsError(const std::vector<TensilePoint>& points,
                       const std::vector<double>& model_stress) {
  double sum = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double difference = model_stress[i] - points[i].stress;
    sum += difference * difference;
    largest = std::max(largest, points[i].stress);
  }
  return std::sqrt(sum / static_cast<double>(points.size())) / largest;
}

TensileFitResult FitTensileCurve(const std::vector<TensilePoint>& curve,
                                 const TensileFitOptions& options) {
  if (!(options.max_strain > 0.0) || !std::isfinite(options.max_strain)) {
    throw std::invalid_argument("--max-strain must be finite and > 0");
  }
  if (!(options.poisson > -1.0 && options.poisson < 0.5)) {
    throw std::invalid_argument("Poisson's ratio must lie in (-1, 0.5)");
  }
  TensileFitResult result;
  result.fitted = TensileFitRange(curve, options.max_strain);
  const Trial coarse = GridSearch(result.fitted, options.poisson, &result.evaluations);
  if (!std::isfinite(coarse.rms)) {
    throw std::invalid_argument("no spring law of the family follows the curve");
  }
  const Trial best = PatternSearch(result.fitted, options.poisson, coarse, &result.evaluations);
  result.youngs = best.youngs;
  result.law = best.law;
  result.rms_error = best.rms;
  result.model_stress = ModelTensileStress(result.fitted, best.youngs, options.poisson, best.law);
  for (const TensilePoint& point : result.fitted) {
    result.max_stress = std::max(result.max_stress, point.stress);
  }
  return result;
}

}  // namespace msm_sim::core
