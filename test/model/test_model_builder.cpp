#include <stdexcept>

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

}  // namespace
}  // namespace msm_sim::core
