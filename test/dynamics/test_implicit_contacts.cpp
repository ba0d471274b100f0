// The implicit substep (docs/physics.md §7.1) in contact: indentation against the explicit
// integrator, Coulomb friction on a slope, rejected steps, and the stiffness it refuses.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "implicit_test_blocks.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/experiments/indentation_experiment.h"
#include "rejected_step_checks.h"

namespace msm_sim::core {
namespace {

// (d) As the explicit Steps test: an absurd push is rejected and the state restored bit for bit.
// The contacts are held in the implicit solve (§7.1): at 1 ms steps a sphere pressed into a
// coarse block meets the explicit integrator's force (before, 43-57 % below it).
TEST(ImplicitIntegrator, IndentationForceMatchesTheExplicitIntegrator) {
  const auto model = Block(Eigen::Vector3d(0.1, 0.1, 0.05), 0.02, 0.25);
  IndentationExperimentOptions options;
  options.depth = 0.005;
  options.samples = 10;
  const IndentationExperimentResult explicit_run = RunIndentationExperiment(model, options);
  options.integrator = Integrator::kImplicit;
  const IndentationExperimentResult implicit_run = RunIndentationExperiment(model, options);
  ASSERT_FALSE(explicit_run.profile.empty());
  ASSERT_FALSE(implicit_run.profile.empty());
  const double expected = explicit_run.profile.back().force;
  std::printf("  %.2f mm deep: implicit %.3f N, explicit %.3f N (%+.2f %%)\n",
              1e3 * implicit_run.profile.back().depth, implicit_run.profile.back().force, expected,
              100 * (implicit_run.profile.back().force / expected - 1));
  ASSERT_GT(expected, 0.0);
  EXPECT_NEAR(implicit_run.profile.back().force, expected, 0.05 * expected);
}

// The block at 1 cm (500 nodes) pressed by a sphere with the default friction 0.5, at
// nu 0.49 and 0.25, and frictionless at nu 0.49: the implicit force within 5 % of the explicit
// one at every depth from 1 mm (measured within 0.9, 2.3 and 1.1 %). The friction is the hard
// part: applied after the solve (until 2026-11-27) the implicit force read 8-10 % low at
// nu 0.49, because the solve let the nodes under the sphere slide with their neighbours and the
// friction then stopped only the nodes (docs/physics.md §7.1). The explicit reference is
// converged in its substep: at half its fraction of the stable step it moves by under 1 %
// (measured 0.45 %).
TEST(ImplicitIntegrator, IndentationMatchesTheExplicitIntegratorWithAndWithoutFriction) {
  struct Case {
    double poisson, friction;
  };
  for (const Case c : {Case{0.49, 0.5}, Case{0.25, 0.5}, Case{0.49, 0.0}}) {
    const auto model = Block(Eigen::Vector3d(0.1, 0.1, 0.05), 0.01, c.poisson);
    IndentationExperimentOptions options;
    options.depth = 0.005;
    options.samples = 10;
    options.friction = c.friction;
    const IndentationExperimentResult explicit_run = RunIndentationExperiment(model, options);
    options.integrator = Integrator::kImplicit;
    const IndentationExperimentResult implicit_run = RunIndentationExperiment(model, options);
    // The rows' depths differ by up to a step's travel (the first step that records a force
    // starts each profile, and the implicit kick's speculative holds record it a step
    // earlier): the explicit profile is read at the implicit rows' depths.
    double worst = 0.0;
    int compared = 0;
    for (const IndentationSample& i : implicit_run.profile) {
      if (i.depth < 1e-3 || i.depth > explicit_run.profile.back().depth) continue;
      const double e = ProfileForceAt(explicit_run.profile, i.depth);
      ASSERT_GT(e, 0.0);
      worst = std::max(worst, std::abs(i.force / e - 1.0));
      ++compared;
    }
    std::printf(
        "  nu %.2f, friction %.1f, %d rows from 1 mm: implicit within %.2f %% of explicit "
        "(%.3f / %.3f N at %.2f mm)\n",
        c.poisson, c.friction, compared, 100 * worst, implicit_run.profile.back().force,
        explicit_run.profile.back().force, 1e3 * explicit_run.profile.back().depth);
    EXPECT_GE(compared, 5);
    EXPECT_LT(worst, 0.05);
    if (c.poisson == 0.49 && c.friction > 0.0) {
      options.integrator = Integrator::kExplicit;
      options.time_step_safety = 0.4;
      const IndentationExperimentResult finer = RunIndentationExperiment(model, options);
      double moved = 0.0;
      for (const IndentationSample& f : finer.profile) {
        if (f.depth < 1e-3 || f.depth > explicit_run.profile.back().depth) continue;
        moved =
            std::max(moved, std::abs(f.force / ProfileForceAt(explicit_run.profile, f.depth) - 1));
      }
      std::printf("  explicit at half the substep: within %.2f %% of the default's\n", 100 * moved);
      EXPECT_LT(moved, 0.01);
    }
  }
}

// Coulomb's law in the solve (docs/physics.md §7.1): a block on a slope (gravity tilted by
// theta from the plane's normal, mu 0.5) stays put where tan theta < mu, its contacts stuck, and
// slides down with acceleration g (sin theta - mu cos theta) where tan theta > mu, its contacts
// sliding with mu times their normal impulse, at 1 ms implicit steps.
TEST(ImplicitIntegrator, BlockOnASlopeSticksBelowTheFrictionAngleAndSlidesAbove) {
  const auto model = Block(Eigen::Vector3d(0.04, 0.04, 0.02), 0.01, 0.3);
  const double g = 9.81, mu = 0.5, seconds = 0.5;
  for (const double slope : {0.4, 0.7}) {  // tan theta
    const double theta = std::atan(slope);
    WorldOptions options = ImplicitOptions(1e-3);
    options.gravity = g * Eigen::Vector3d(std::sin(theta), 0.0, -std::cos(theta));
    World world(options);
    const int body = world.AddBody("block", model);
    world.AddCollider(GroundTouching(world.state(body).positions, world.border(body), mu));
    const Eigen::VectorXd& m = model->masses();
    const auto centre_x = [&](const Eigen::Matrix3Xd& values) {
      return values.row(0).dot(m.transpose()) / m.sum();
    };
    const double start = centre_x(world.state(body).positions);
    for (int step = 0; step < 500; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
    const double moved = centre_x(world.state(body).positions) - start;
    const double speed = centre_x(world.state(body).velocities);
    const double acceleration = g * (std::sin(theta) - mu * std::cos(theta));
    std::printf("  tan theta %.1f (mu %.1f): moved %.4f mm, speed %.4f m/s after %.1f s", slope, mu,
                1e3 * moved, speed, seconds);
    if (slope < mu) {
      std::printf(" (stuck)\n");
      EXPECT_LT(std::abs(moved), 1e-4);  // settling and shearing under its weight: 0.06 mm
      EXPECT_LT(std::abs(speed), 1e-3);
    } else {
      std::printf(", theory %.4f m/s (%+.2f %%)\n", acceleration * seconds,
                  100 * (speed / (acceleration * seconds) - 1));
      EXPECT_NEAR(speed, acceleration * seconds, 0.03 * acceleration * seconds);
    }
  }
}

TEST(ImplicitIntegrator, AbsurdForceIsRejectedAndTheStateKept) {
  World world(ImplicitOptions(1e-3, 9.81));
  const int body = world.AddBody("block", Block(Eigen::Vector3d(0.04, 0.04, 0.02), 0.01, 0.3));
  world.AddCollider(GroundTouching(world.state(body).positions, world.border(body)));
  for (int step = 0; step < 10; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
  ExpectAbsurdForceRejectedAndStateKept(&world, body, Eigen::Vector3d(0.02, 0.02, 0.02), 0.01);
}

// A rejected step leaves no trace: a block sliding down a slope (its contacts carry their
// Coulomb impulses from kick to kick, docs/physics.md §7.1) continues after a rejected push
// exactly as its twin that never saw the push, bit for bit.
TEST(ImplicitIntegrator, ARejectedStepLeavesNoTraceInTheSlidingThatFollows) {
  const auto model = Block(Eigen::Vector3d(0.04, 0.04, 0.02), 0.01, 0.3);
  const double theta = std::atan(0.7);  // above the friction angle of mu 0.5
  WorldOptions options = ImplicitOptions(1e-3);
  options.gravity = 9.81 * Eigen::Vector3d(std::sin(theta), 0.0, -std::cos(theta));
  World pushed(options), twin(options);
  for (World* world : {&pushed, &twin}) {
    const int body = world->AddBody("block", model);
    world->AddCollider(GroundTouching(world->state(body).positions, world->border(body), 0.5));
    for (int step = 0; step < 20; ++step) ASSERT_TRUE(world->Step(1e-3).accepted);
  }
  pushed.ApplyForce(0, Eigen::Vector3d(0.02, 0.02, 0.02), Eigen::Vector3d(1e12, 0.0, 0.0), 0.01,
                    0.0);
  ASSERT_FALSE(pushed.Step(1e-3).accepted);
  for (int step = 0; step < 20; ++step) {
    ASSERT_TRUE(pushed.Step(1e-3).accepted);
    ASSERT_TRUE(twin.Step(1e-3).accepted);
  }
  EXPECT_GT(twin.state(0).velocities.row(0).mean(), 0.05);  // it slides
  EXPECT_EQ(pushed.state(0).positions, twin.state(0).positions);
  EXPECT_EQ(pushed.state(0).velocities, twin.state(0).velocities);
}

// Carrier springs with dispersion have a symmetric K (the dispersion weighted by the tangent,
// docs/physics.md §3), so conjugate gradient takes them: a carrier block hanging from its top
// layer under a gravity that stretches it by a few per cent settles where the explicit
// integrator puts it.
TEST(ImplicitIntegrator, HangsCarrierSpringsWithDispersionAsTheExplicitOneDoes) {
  const auto block = Block(Eigen::Vector3d(0.02, 0.02, 0.04), 0.01, 0.45, SpringLaw::kNonlinear);
  ASSERT_GT(block->dispersion_fraction(), 0.0);
  KinematicGroup top{"top", {}, {}};
  const double z_top = block->rest_positions().row(2).maxCoeff();
  for (int i = 0; i < block->num_nodes(); ++i) {
    if (block->rest_positions()(2, i) > z_top - 1e-9) top.nodes.push_back(i);
  }
  WorldOptions heavy;
  heavy.gravity = Eigen::Vector3d(0.0, 0.0, -3000.0);
  World implicit(ImplicitOptions(1e-3, 3000.0)), explicit_world(heavy);
  BodyOptions damped;
  damped.damping_beta = 1e-3;
  double sags[2];
  int index = 0;
  for (World* world : {&implicit, &explicit_world}) {
    const int body = world->AddBody("carrier", block, damped);
    world->AddKinematicGroup(body, top);
    for (int step = 0; step < 500; ++step) ASSERT_TRUE(world->Step(1e-3).accepted);
    sags[index++] = (world->state(body).positions - block->rest_positions()).row(2).mean();
  }
  std::printf("  mean sag: implicit %.4f mm, explicit %.4f mm\n", 1e3 * sags[0], 1e3 * sags[1]);
  EXPECT_LT(sags[1], -2e-4);
  EXPECT_NEAR(sags[0], sags[1], 0.01 * std::abs(sags[1]));
  WorldOptions bad = ImplicitOptions(0.0);
  EXPECT_THROW(World{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
