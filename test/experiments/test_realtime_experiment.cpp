// The real-time experiment (issue "Real time at real resolution"): what it reports, never how
// fast it runs (the test machine's load decides that).
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <gtest/gtest.h>

#include "msm_sim/experiments/realtime_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

// 4 x 4 x 2 cm at a = 5 mm: 8 x 8 x 4 = 256 nodes, E = 200 kPa, rho = 1100.
std::shared_ptr<const Model> SmallBlock() {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.04, 0.04, 0.02);
  lattice_options.lattice.spacing = 0.005;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.45, 1100.0), lattice_options));
}

TEST(RealtimeExperiment, ReportsTheModelStepsAndContactForce) {
  const auto block = SmallBlock();
  RealtimeExperimentOptions options;
  options.seconds = 0.05;  // the sphere 0.5 mm deep
  const RealtimeExperimentResult result = RunRealtimeExperiment(block, options);
  EXPECT_EQ(result.nodes, block->num_nodes());
  EXPECT_EQ(result.springs, block->num_springs());
  EXPECT_EQ(result.integrator, "explicit");
  EXPECT_EQ(result.step, 1e-3);
  EXPECT_EQ(result.steps, 50);
  EXPECT_NEAR(result.seconds_simulated, 0.05, 1e-12);
  EXPECT_GE(result.substeps, 1);
  EXPECT_NEAR(result.substep * result.substeps, 1e-3, 1e-15);
  EXPECT_TRUE(std::isfinite(result.peak_force));
  EXPECT_GT(result.peak_force, 0.0);
  EXPECT_GT(result.wall_seconds, 0.0);
  EXPECT_NEAR(result.wall_per_simulated_second, result.wall_seconds / 0.05,
              1e-9 * result.wall_per_simulated_second);
  EXPECT_DOUBLE_EQ(result.real_time_factor, 1.0 / result.wall_per_simulated_second);
}

TEST(RealtimeExperiment, SinglePrecisionSpringsPressTheSame) {
  // The spring loops' precision changes the rounding, not the dynamics: the same substeps and
  // the same force on the sphere to the strain resolution of single precision.
  const auto block = SmallBlock();
  RealtimeExperimentOptions options;
  options.seconds = 0.05;
  EXPECT_EQ(options.spring_precision, SpringPrecision::kSingle);  // the World's default
  const RealtimeExperimentResult single = RunRealtimeExperiment(block, options);
  options.spring_precision = SpringPrecision::kDouble;
  const RealtimeExperimentResult exact = RunRealtimeExperiment(block, options);
  EXPECT_EQ(single.substeps, exact.substeps);
  EXPECT_NE(single.peak_force, exact.peak_force);  // the single loops did run
  EXPECT_NEAR(single.peak_force, exact.peak_force, 1e-4 * exact.peak_force);
}

// The realtime block at 4 mm (8,125 nodes), nu = 0.49 with a quarter of the outer layer's bulk
// (surface_dispersion 0.25), pressed 9.5 mm by the 1 cm sphere. About 9 mm deep the compressed
// layers under the sphere buckle and snap (the linearised stiffness there has negative
// eigenvalues, docs/physics.md §7): at the rest shape's stable step that snap overshot past
// max_speed and stopped the body. The World now takes that step again with finer substeps; the
// run completes, and after the snap the force on the sphere matches a run at 0.6 of the stable
// step (which resolves the snap without help) within 5 % of the peak.
TEST(RealtimeExperiment, ADeepPressThatBucklesTheLatticeRunsThrough) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.1, 0.1, 0.05);
  lattice_options.lattice.spacing = 0.004;
  lattice_options.surface.surface_dispersion = 0.25;
  const auto block = std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, 0.49, 1100.0), lattice_options));
  ASSERT_EQ(block->num_nodes(), 8125);
  RealtimeExperimentOptions options;
  options.seconds = 0.95;
  const RealtimeExperimentResult refined = RunRealtimeExperiment(block, options);  // no throw
  options.time_step_safety = 0.6;
  const RealtimeExperimentResult fine = RunRealtimeExperiment(block, options);
  EXPECT_EQ(fine.substep_refinement, 1);
  // Both snapped: the force fell well below its peak.
  EXPECT_LT(refined.final_force, 0.9 * refined.peak_force);
  EXPECT_LT(fine.final_force, 0.9 * fine.peak_force);
  EXPECT_NEAR(refined.peak_force, fine.peak_force, 0.02 * fine.peak_force);
  EXPECT_NEAR(refined.final_force, fine.final_force, 0.05 * fine.peak_force);
  std::printf("refinement %d, peak %.3f / %.3f N, final %.3f / %.3f N\n",
              refined.substep_refinement, refined.peak_force, fine.peak_force, refined.final_force,
              fine.final_force);
}

TEST(RealtimeExperiment, InvalidOptionsThrow) {
  const auto block = SmallBlock();
  for (int field = 0; field < 7; ++field) {
    RealtimeExperimentOptions options;
    double* values[] = {&options.sphere_radius, &options.speed,   &options.seconds,
                        &options.step,          &options.gravity, &options.friction,
                        &options.damping_beta};
    *values[field] = field < 4 ? 0.0 : -1.0;
    EXPECT_THROW(RunRealtimeExperiment(block, options), std::invalid_argument) << field;
    *values[field] = std::nan("");
    EXPECT_THROW(RunRealtimeExperiment(block, options), std::invalid_argument) << field;
  }
  for (const double safety : {0.0, 1.5, std::nan("")}) {
    RealtimeExperimentOptions options;
    options.time_step_safety = safety;
    EXPECT_THROW(RunRealtimeExperiment(block, options), std::invalid_argument) << safety;
  }
}

}  // namespace
}  // namespace msm_sim::core
