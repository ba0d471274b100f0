#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "msm_sim/model/model_builder.h"
#include "msm_sim/model/model_statistics.h"
#include "msm_sim/model/state.h"

namespace msm_sim::core {
namespace {

const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.25, 1000.0);

TEST(ModelBuilder, BuildsSpringsAndAdjacency) {
  ModelBuilder builder(kMaterial);
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({1, 0, 0}, 2.0);
  builder.AddNode({0, 2, 0}, 3.0);
  builder.AddSpring(0, 1, 10.0);
  builder.AddSpring(0, 2, 20.0);
  const Model model = builder.Build(1.0, 1.0);
  ASSERT_EQ(model.num_nodes(), 3);
  ASSERT_EQ(model.num_springs(), 2);
  EXPECT_DOUBLE_EQ(model.spring_rest_length()[1], 2.0);
  EXPECT_EQ(model.num_incident_springs(0), 2);
  EXPECT_EQ(model.num_incident_springs(1), 1);
  EXPECT_EQ(model.num_incident_springs(2), 1);
  const int offset = model.incidence_offsets()[2];
  EXPECT_EQ(model.incident_springs()[offset], 1);

  const ModelStatistics stats = ComputeModelStatistics(model);
  EXPECT_DOUBLE_EQ(stats.total_mass, 6.0);
  EXPECT_DOUBLE_EQ(stats.mean_springs_per_node, 4.0 / 3.0);
  EXPECT_DOUBLE_EQ(stats.mean_spring_length, 1.5);
  EXPECT_DOUBLE_EQ(stats.spring_length_stddev, 0.5);

  const State state = State::AtRest(model);
  EXPECT_TRUE(state.Displacements(model).isZero());
  EXPECT_TRUE(state.velocities.isZero());
}

TEST(ModelBuilder, RejectsInvalidNodesAndSprings) {
  ModelBuilder builder(kMaterial);
  EXPECT_THROW(builder.AddNode({0, 0, 0}, 0.0), std::invalid_argument);
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({0, 0, 0}, 1.0);
  EXPECT_THROW(builder.AddSpring(0, 0, 1.0), std::invalid_argument);
  EXPECT_THROW(builder.AddSpring(0, 5, 1.0), std::invalid_argument);
  EXPECT_THROW(builder.AddSpring(0, 1, 1.0), std::invalid_argument);             // coincident
  EXPECT_THROW(ModelBuilder(kMaterial).Build(1.0, 1.0), std::invalid_argument);  // no nodes
}

TEST(ModelBuilder, CarriesThePowerLawAndRejectsBadParameters) {
  ModelBuilder builder(kMaterial);
  builder.AddNode({0, 0, 0}, 1.0);
  builder.AddNode({1, 0, 0}, 1.0);
  builder.AddSpring(0, 1, 1.0);
  builder.SetSpringLaw(SpringLaw::kPower, PowerSpringLaw{-4.5, 0.1});
  const Model power = builder.Build(1.0, 1.0);
  EXPECT_EQ(power.spring_law(), SpringLaw::kPower);
  EXPECT_EQ(power.power_spring_law().alpha, -4.5);
  EXPECT_EQ(power.power_spring_law().beta, 0.1);
  // The other laws report their own members of the family (docs/physics.md §4.1).
  builder.SetSpringLaw(SpringLaw::kNonlinear, PowerSpringLaw{-4.5, 0.1});
  EXPECT_EQ(builder.Build(1.0, 1.0).power_spring_law().alpha, -1.0);
  EXPECT_EQ(builder.Build(1.0, 1.0).power_spring_law().beta, 0.0);
  builder.SetSpringLaw(SpringLaw::kLinear);
  EXPECT_EQ(builder.Build(1.0, 1.0).power_spring_law().alpha, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const PowerSpringLaw bad :
       {PowerSpringLaw{nan, 0.0}, PowerSpringLaw{inf, 0.0}, PowerSpringLaw{-1.0, -0.1},
        PowerSpringLaw{-1.0, nan}, PowerSpringLaw{-1.0, inf}}) {
    try {
      builder.SetSpringLaw(SpringLaw::kPower, bad);
      ADD_FAILURE() << "accepted alpha " << bad.alpha << ", beta " << bad.beta;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("power spring law"), std::string::npos) << e.what();
    }
  }
  // A refused law leaves the builder's law as it was.
  EXPECT_EQ(builder.Build(1.0, 1.0).spring_law(), SpringLaw::kLinear);
}

}  // namespace
}  // namespace msm_sim::core
