#include <vector>

#include <gtest/gtest.h>

#include "mechanics/spring_schedule.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/random_lattice_builder.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

Model CubicBlock() {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.1, 0.06, 0.05);
  options.lattice.spacing = 0.01;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1000.0), options);
}

// Every model spring appears once; each run joins a0 + i and a0 + offset + i, which are the
// model spring's ends (swapped where the schedule says so).
void ExpectSchedulePermutesTheSprings(const Model& model, const SpringSchedule& schedule) {
  ASSERT_EQ(schedule.num_springs(), model.num_springs());
  std::vector<int> seen(model.num_springs(), 0);
  int next = 0;
  for (const SpringRun& run : schedule.runs) {
    ASSERT_EQ(run.first, next);
    ASSERT_GE(run.count, 1);
    ASSERT_LE(run.count, SpringSchedule::kMaxRunLength);
    ASSERT_GT(run.offset, 0);
    for (int i = 0; i < run.count; ++i) {
      const int p = run.first + i;
      const SpringIndex s = schedule.model_index[p];
      ++seen[s];
      const NodeIndex a = schedule.swapped[p] ? model.spring_node_b()[s] : model.spring_node_a()[s];
      const NodeIndex b = schedule.swapped[p] ? model.spring_node_a()[s] : model.spring_node_b()[s];
      EXPECT_EQ(a, run.a0 + i);
      EXPECT_EQ(b, run.a0 + run.offset + i);
    }
    next += run.count;
  }
  EXPECT_EQ(next, model.num_springs());
  for (const int count : seen) EXPECT_EQ(count, 1);
}

TEST(SpringSchedule, CubicLatticeRowsBecomeLongRuns) {
  const Model model = CubicBlock();
  const SpringSchedule schedule = ScheduleSprings(model);
  ExpectSchedulePermutesTheSprings(model, schedule);
  EXPECT_TRUE(schedule.vectorisable());
  // 11 x 7 x 6 nodes: rows are at most 11 long.
  EXPECT_GE(schedule.num_springs(), 6.0 * static_cast<double>(schedule.runs.size()));
}

TEST(SpringSchedule, RandomLatticeIsNotVectorisable) {
  RandomLatticeOptions options;
  options.size = Eigen::Vector3d(0.5, 0.4, 0.3);
  options.lattice.spacing = 0.1;
  const Model model = BuildRandomLattice(Material::FromYoungsPoisson(1e4, 0.3, 1000.0), options);
  const SpringSchedule schedule = ScheduleSprings(model);
  ExpectSchedulePermutesTheSprings(model, schedule);
  EXPECT_FALSE(schedule.vectorisable());
}

TEST(SpringSchedule, SwapsReversedSpringsAndTheirEndData) {
  // A chain whose springs point from the higher index to the lower, with distinct end weights.
  ModelBuilder builder(Material::FromYoungsPoisson(1e4, 0.45, 1000.0));
  for (int i = 0; i < 10; ++i) builder.AddNode(Eigen::Vector3d(0.01 * i, 0.0, 0.0), 0.1);
  for (int i = 0; i < 9; ++i) {
    const SpringIndex s = builder.AddSpring(i + 1, i, 100.0);
    builder.SetDispersionWeight(s, i + 1, 1.5);
    builder.SetDispersionWeight(s, i, 0.5);
  }
  const Model model = builder.Build(1e-6, 0.01);
  const SpringSchedule schedule = ScheduleSprings(model);
  ExpectSchedulePermutesTheSprings(model, schedule);
  ASSERT_EQ(schedule.runs.size(), 1u);
  EXPECT_EQ(schedule.runs[0].count, 9);
  EXPECT_EQ(schedule.runs[0].offset, 1);
  for (const char swapped : schedule.swapped) EXPECT_TRUE(swapped);
  // The scheduled a end (the lower index) takes the model's b-end weight.
  const std::vector<double> weight_a = schedule.ToScheduleEnd(model.dispersion_weight_a().data(),
                                                              model.dispersion_weight_b().data());
  for (const double w : weight_a) EXPECT_EQ(w, 0.5);
}

}  // namespace
}  // namespace msm_sim::core
