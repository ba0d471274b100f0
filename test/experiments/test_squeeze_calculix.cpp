// The squeeze against CalculiX (issue 61): a sphere of 5 cm diameter, E 259 kPa, between rigid
// frictionless plates closed to 30 % of its diameter, on a 3 mm cubic lattice, against the stored
// axisymmetric neo-Hookean reference (test/data/calculix_squeeze_nu0*.csv, made by
// scripts/calculix_squeeze.py; test/data/README.md). The power law is fitted here, as a user
// would, to the same neo-Hookean material's uniaxial curve (test/data/neo_hookean_*_tensile.csv,
// scripts/hyperelastic_tensile.py). Needs no ccx.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <future>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lab_grasp_command.h"
#include "lab_model.h"
#include "msm_sim/experiments/indentation_experiment.h"
#include "msm_sim/experiments/squeeze_experiment.h"
#include "msm_sim/experiments/tensile_fit.h"

namespace msm_sim::core {
namespace {

constexpr double kRadius = 0.025;
constexpr double kYoungs = 259e3;
constexpr double kSpacing = 0.003;

struct ReferenceRow {
  double approach, force, radius;
};

std::vector<ReferenceRow> ReadReference(const std::string& name) {
  std::ifstream in(std::string(MSM_SIM_TEST_DATA_DIR) + "/" + name);
  std::vector<ReferenceRow> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'a') continue;
    std::istringstream fields(line);
    ReferenceRow row{};
    char comma = 0;
    fields >> row.approach >> comma >> row.force >> comma >> row.radius;
    rows.push_back(row);
  }
  return rows;
}

// The reference at this approach: the force interpolated as a local power of the approach (the
// curve is close to one, Hertz's 3/2 at small approach), the radius linearly.
ReferenceRow ReferenceAt(const std::vector<ReferenceRow>& rows, double approach) {
  std::size_t k = 1;
  while (k + 1 < rows.size() && rows[k].approach < approach) ++k;
  const ReferenceRow& a = rows[k - 1];
  const ReferenceRow& b = rows[k];
  const double t = (approach - a.approach) / (b.approach - a.approach);
  const double p = std::log(b.force / a.force) / std::log(b.approach / a.approach);
  return {approach, a.force * std::pow(approach / a.approach, p),
          a.radius + t * (b.radius - a.radius)};
}

TensileFitResult FitNeoHookean(double poisson, const std::string& curve_name) {
  std::ifstream csv(std::string(MSM_SIM_TEST_DATA_DIR) + "/" + curve_name);
  const TensileCurve curve = ReadTensileCurve(csv, TensileColumns{});
  TensileFitOptions options;
  options.poisson = poisson;
  return FitTensileCurve(curve.points, options);
}

SqueezeExperimentResult SqueezeSphere(double youngs, double poisson, const PowerSpringLaw* law,
                                      double fraction) {
  lab::LabArguments arguments;
  arguments.grasp.shape = "sphere";
  arguments.grasp.radius = kRadius;
  lab::ModelArguments& model = arguments.model;
  model.spacing = kSpacing;
  model.youngs = youngs;
  model.poisson = poisson;
  model.density = 1100.0;
  if (law != nullptr) {
    model.spring = "power";
    model.alpha = law->alpha;
    model.beta = law->beta;
  }
  const auto built =
      std::make_shared<const Model>(lab::BuildLabModel(model, lab::GraspBody(arguments)));
  SqueezeExperimentOptions options;
  options.approach = fraction * 2.0 * kRadius;
  return RunSqueezeExperiment(built, options);
}

// Over the rows with approach in [1 %, max_fraction] of the diameter: the extremes of
// F / F_CalculiX - 1 and the largest |r - r_CalculiX|.
struct Errors {
  double force_min = 0.0, force_max = 0.0, radius = 0.0;
};

Errors Compare(const SqueezeExperimentResult& result, const std::vector<ReferenceRow>& reference,
               double max_fraction) {
  Errors errors;
  for (const SqueezeSample& row : result.profile) {
    const double fraction = row.approach / (2.0 * kRadius);
    if (fraction < 0.01 || fraction > max_fraction + 1e-9) continue;
    const ReferenceRow expected = ReferenceAt(reference, row.approach);
    const double error = row.force / expected.force - 1.0;
    errors.force_min = std::min(errors.force_min, error);
    errors.force_max = std::max(errors.force_max, error);
    errors.radius = std::max(errors.radius, std::abs(row.contact_radius - expected.radius));
    std::printf("  %5.1f %%  F %8.3f N  CalculiX %8.3f N  (%+6.1f %%)  r %5.2f mm  (%5.2f mm)\n",
                100.0 * fraction, row.force, expected.force, 100.0 * error,
                1e3 * row.contact_radius, 1e3 * expected.radius);
  }
  return errors;
}

// The largest |F / F_CalculiX - 1| over the rows with approach in [from, to] of the diameter.
double LargestErrorBetween(const SqueezeExperimentResult& result,
                           const std::vector<ReferenceRow>& reference, double from, double to) {
  double largest = 0.0;
  for (const SqueezeSample& row : result.profile) {
    const double fraction = row.approach / (2.0 * kRadius);
    if (fraction < from || fraction > to) continue;
    largest =
        std::max(largest, std::abs(row.force / ReferenceAt(reference, row.approach).force - 1.0));
  }
  return largest;
}

struct Case {
  double poisson;
  std::string name;
};
const Case kCases[] = {{0.49, "049"}, {0.45, "045"}};

// What a squeeze to 30 % must meet against the stored reference: nothing folded, the patch
// radius within one spacing, F / F_CalculiX - 1 below `above` and above -`below` from 1 % to
// 30 %, and |F / F_CalculiX - 1| below `band` from `band_from` to `band_to` of the diameter.
struct SqueezeBounds {
  double above, below, band_from, band_to, band;
};

void ExpectSqueezeTo30PercentWithin(const SqueezeExperimentResult& result, const Case& c,
                                    const SqueezeBounds& bounds) {
  const auto reference = ReadReference("calculix_squeeze_nu" + c.name + ".csv");
  ASSERT_EQ(result.folded_corners, 0);
  ASSERT_GT(result.profile.size(), 25u);
  const Errors errors = Compare(result, reference, 0.30);
  EXPECT_LT(errors.radius, kSpacing);
  EXPECT_LT(errors.force_max, bounds.above);
  EXPECT_GT(errors.force_min, -bounds.below);
  EXPECT_LT(LargestErrorBetween(result, reference, bounds.band_from, bounds.band_to), bounds.band);
}

// The stored reference against theory: Hertz for two contacts in series,
// F = 4/3 E / (1 - nu^2) sqrt(R) (delta / 2)^(3/2), lies a few percent below a finite sphere's
// force at 1 % approach, and further below as the patch grows (issue 61).
TEST(SqueezeCalculix, ReferenceSitsAboveHertzByAGapThatGrows) {
  for (const Case& c : kCases) {
    SCOPED_TRACE("nu " + c.name);
    const auto reference = ReadReference("calculix_squeeze_nu" + c.name + ".csv");
    const auto gap = [&](double fraction) {
      const double approach = fraction * 2.0 * kRadius;
      return 1.0 - HertzForce(kYoungs, c.poisson, kRadius, 0.5 * approach) /
                       ReferenceAt(reference, approach).force;
    };
    EXPECT_GT(gap(0.01), 0.02);
    EXPECT_LT(gap(0.01), 0.06);
    EXPECT_GT(gap(0.10), gap(0.01) + 0.05);
    EXPECT_GT(gap(0.30), gap(0.10) + 0.10);
  }
}

// Linear springs, 3 mm, to 30 %. What holds (docs/design/squeeze-vs-fem.md): the patch radius
// within one spacing; the force within 7 % of CalculiX's from 4 % to 12 % of the diameter (the
// collision spheres follow the surface, docs/physics.md §7), above it by less than 30 % below 4 %
// (a patch of one or a few nodes), and below it by less than 35 % up to 30 % (the linear lattice
// softens where the neo-Hookean solid stiffens). The 5 % up to 10 % is not met below 4 %.
TEST(SqueezeCalculix, LinearSpringsAt3mm) {
  for (const Case& c : kCases) {
    SCOPED_TRACE("nu " + c.name);
    ExpectSqueezeTo30PercentWithin(SqueezeSphere(kYoungs, c.poisson, nullptr, 0.30), c,
                                   {0.30, 0.35, 0.04, 0.12, 0.07});
  }
}

// The power law fitted to the neo-Hookean uniaxial curve, 3 mm, to 30 % (docs/design/
// squeeze-vs-fem.md): nothing folds, the patch radius within one spacing, the force within 10 %
// of CalculiX's from 3 % to 20 % of the diameter, above it by less than 20 % below 3 % (a patch of
// one or a few nodes) and below it by less than 20 % up to 30 %. The 5 % is not met
// everywhere: the force dips while the patch grows from one terrace to the next, and falls
// behind the neo-Hookean solid's past 22 %. The two Poisson's ratios run at once.
TEST(SqueezeCalculix, FittedPowerLawAt3mmTo30Percent) {
  std::vector<std::future<SqueezeExperimentResult>> runs;
  for (const Case& c : kCases) {
    runs.push_back(std::async(std::launch::async, [c] {
      const TensileFitResult fit =
          FitNeoHookean(c.poisson, "neo_hookean_259kpa_nu" + c.name + "_tensile.csv");
      return SqueezeSphere(fit.youngs, c.poisson, &fit.law, 0.30);
    }));
  }
  for (std::size_t i = 0; i < runs.size(); ++i) {
    SCOPED_TRACE("nu " + kCases[i].name);
    ExpectSqueezeTo30PercentWithin(runs[i].get(), kCases[i], {0.20, 0.20, 0.03, 0.20, 0.10});
  }
}

}  // namespace
}  // namespace msm_sim::core
