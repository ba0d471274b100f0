#pragma once
// Thesis 6.4's sliding test, shared by the explicit (test_dynamics.cpp) and implicit
// (test_implicit_integrator.cpp) integrators' tests.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/experiments/slide_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {

// Element-corner box 2 x 1 x 1 m of (2n - 1) x n x n nodes and total mass `mass`.
inline std::shared_ptr<const Model> SlidingBox(int n, double mass) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(2.0, 1.0, 1.0);
  options.lattice.spacing = 1.0 / (n - 1);
  options.construction = CubicConstruction::kElementCorner;
  return std::make_shared<Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.25, mass / 2.0), options));
}

// For (v0, mu) = (1 m/s, 0.5) and (2 m/s, 0.3), each body slid with `options` (its integrator
// and step) stops within 5 % of v0^2 / (2 mu g), and the first `spread_count` bodies (the
// resolutions of one box) within 3 % of each other.
inline void ExpectCoulombStoppingDistances(const std::vector<std::shared_ptr<const Model>>& bodies,
                                           SlideExperimentOptions options,
                                           std::size_t spread_count) {
  struct Case {
    double v0, mu;
  };
  for (const Case c : {Case{1.0, 0.5}, Case{2.0, 0.3}}) {
    options.initial_speed = c.v0;
    options.friction = c.mu;
    std::vector<double> distances;
    for (const auto& body : bodies) {
      const SlideExperimentResult r = RunSlideExperiment(body, options);
      std::printf(
          "  v0 %.1f m/s, mu %.1f: %5d nodes, %6.3f kg, step %.3g ms: distance %.4f m, theory "
          "%.4f m (%+.2f %%)\n",
          c.v0, c.mu, body->num_nodes(), body->masses().sum(), 1e3 * options.step, r.distance,
          r.theory_distance, 100 * (r.distance / r.theory_distance - 1));
      EXPECT_TRUE(r.stopped);
      EXPECT_NEAR(r.distance / r.theory_distance, 1.0, 0.05);
      distances.push_back(r.distance);
    }
    const auto [lo, hi] = std::minmax_element(distances.begin(), distances.begin() + spread_count);
    EXPECT_LE(*hi / *lo - 1.0, 0.03);
  }
}

}  // namespace msm_sim::core
