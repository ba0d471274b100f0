#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/model/model_statistics.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(3e4, 0.25, 1050.0);

RandomLatticeOptions SmallBlock() {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(1.0, 0.6, 0.5);
  options.lattice.spacing = 0.1;
  return options;
}

double CalibratedYoungs(const Model& model) {
  double sum = 0.0;
  for (int s = 0; s < model.num_springs(); ++s) {
    sum += model.spring_stiffness()[s] * std::pow(model.spring_rest_length()[s], 2);
  }
  return sum / (6.0 * model.volume());
}

TEST(RandomLatticeBuilder, PlacesTheRequestedNodesAtLeastMinLApart) {
  const RandomLatticeOptions options = SmallBlock();
  const Model model = BuildRandomLattice(kMaterial, options);
  EXPECT_EQ(model.num_nodes(), 300);  // V / l^3
  EXPECT_NEAR(model.masses().sum(), 1050.0 * 0.3, 1e-9);
  const auto& p = model.rest_positions();
  double closest = 1e9;
  for (int i = 0; i < model.num_nodes(); ++i) {
    for (int j = i + 1; j < model.num_nodes(); ++j) {
      closest = std::min(closest, (p.col(i) - p.col(j)).norm());
    }
  }
  EXPECT_GE(closest, options.min_distance * options.lattice.spacing);
  for (double length : model.spring_rest_length()) {
    EXPECT_LT(length, options.max_distance * options.lattice.spacing);
  }
}

TEST(RandomLatticeBuilder, ConnectsEveryPairCloserThanMaxL) {
  const RandomLatticeOptions options = SmallBlock();
  const Model model = BuildRandomLattice(kMaterial, options);
  const auto& p = model.rest_positions();
  int pairs = 0;
  for (int i = 0; i < model.num_nodes(); ++i) {
    for (int j = i + 1; j < model.num_nodes(); ++j) {
      if ((p.col(i) - p.col(j)).norm() < options.max_distance * options.lattice.spacing) ++pairs;
    }
  }
  EXPECT_EQ(model.num_springs(), pairs);
}

TEST(RandomLatticeBuilder, CalibratesBothStiffnessLawsToE) {
  RandomLatticeOptions options = SmallBlock();
  for (const auto law : {RandomStiffnessLaw::kUniform, RandomStiffnessLaw::kInverseSquare}) {
    options.stiffness_law = law;
    const Model model = BuildRandomLattice(kMaterial, options);
    EXPECT_NEAR(CalibratedYoungs(model) / 3e4, 1.0, 1e-12);
    const auto& k = model.spring_stiffness();
    const auto& l = model.spring_rest_length();
    if (law == RandomStiffnessLaw::kUniform) {
      EXPECT_DOUBLE_EQ(k.front(), k.back());
    } else {
      EXPECT_NEAR(k.front() * l.front() * l.front(), k.back() * l.back() * l.back(), 1e-9);
    }
  }
}

TEST(RandomLatticeBuilder, IsDeterministicPerSeed) {
  RandomLatticeOptions options = SmallBlock();
  const Model a = BuildRandomLattice(kMaterial, options);
  const Model b = BuildRandomLattice(kMaterial, options);
  EXPECT_EQ(a.rest_positions(), b.rest_positions());
  EXPECT_EQ(a.spring_stiffness(), b.spring_stiffness());
  options.seed = 2;
  const Model c = BuildRandomLattice(kMaterial, options);
  EXPECT_NE(a.rest_positions(), c.rest_positions());
}

TEST(RandomLatticeBuilder, ReportsImpossibleSetUps) {
  RandomLatticeOptions options = SmallBlock();
  options.min_distance = 1.3;  // far beyond the random-packing limit for N = V / l^3
  options.max_distance = 2.0;
  options.max_draws_per_node = 50;
  EXPECT_THROW(BuildRandomLattice(kMaterial, options), std::runtime_error);
  options = SmallBlock();
  options.max_distance = 0.5;  // below min distance
  EXPECT_THROW(BuildRandomLattice(kMaterial, options), std::invalid_argument);
  options = SmallBlock();
  options.lattice.spacing = 2.0;
  EXPECT_THROW(BuildRandomLattice(kMaterial, options), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
