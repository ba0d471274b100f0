// The implicit substep (docs/physics.md §7.1): static equilibrium, energy, friction and rollback
// at steps far beyond the explicit stability limit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/experiments/indentation_experiment.h"
#include "msm_sim/experiments/slide_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/dof_constraints.h"
#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model_builder.h"
#include "sliding_checks.h"

namespace msm_sim::core {
namespace {

// The material (E 200 kPa, rho 1100) in a box from the origin.
std::shared_ptr<const Model> Block(const Eigen::Vector3d& size, double spacing, double poisson,
                                   SpringLaw law = SpringLaw::kLinear) {
  CubicLatticeOptions options;
  options.size = size;
  options.lattice.spacing = spacing;
  options.lattice.spring_law = law;
  return std::make_shared<Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), options));
}

// Explicit (Verlet), no gravity.
WorldOptions ExplicitOptions() {
  WorldOptions options;
  options.gravity = Eigen::Vector3d::Zero();
  return options;
}

WorldOptions ImplicitOptions(double max_substep, double gravity = 0.0) {
  WorldOptions options;
  options.integrator = Integrator::kImplicit;
  options.implicit_max_substep = max_substep;
  options.gravity = Eigen::Vector3d(0.0, 0.0, -gravity);
  return options;
}

// The explicit World's substep for the model (s).
double ExplicitStableStep(std::shared_ptr<const Model> model, double damping_beta) {
  World world;
  BodyOptions options;
  options.damping_beta = damping_beta;
  world.AddBody("probe", std::move(model), options);
  return world.stable_time_step();
}

std::vector<NodeIndex> BottomLayer(const Model& model) {
  const Eigen::Matrix3Xd& x = model.rest_positions();
  const double bottom = x.row(2).minCoeff();
  std::vector<NodeIndex> nodes;
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    if (x(2, i) < bottom + 1e-9) nodes.push_back(i);
  }
  return nodes;
}

// The nodes within `radius` of `point` at rest, as World::ApplyForce picks them.
std::vector<NodeIndex> NodesNear(const Model& model, const Eigen::Vector3d& point, double radius) {
  std::vector<NodeIndex> nodes;
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    if ((model.rest_positions().col(i) - point).norm() <= radius) nodes.push_back(i);
  }
  return nodes;
}

double MeanDisplacementZ(const Model& model, const Eigen::Matrix3Xd& x,
                         const std::vector<NodeIndex>& nodes) {
  double sum = 0.0;
  for (const NodeIndex i : nodes) sum += x(2, i) - model.rest_positions()(2, i);
  return sum / nodes.size();
}

// A block held at `clamp`, pushed down on top with `force` (N) over `radius` (m) for 0.5 s of
// 1 ms steps, against the static solver's deflection under the same push and clamp.
struct SettledPush {
  double deflection = 0.0;  // m, mean over the pushed nodes, settled
  double expected = 0.0;    // m, the static solver's
  double reaction = 0.0;    // N, on the clamp along z
  double iterations_per_step = 0.0;
};

SettledPush PushAndSettle(const std::shared_ptr<const Model>& model,
                          const std::vector<NodeIndex>& clamp, const WorldOptions& options) {
  const Eigen::Vector3d point(0.02, 0.02, model->rest_positions().row(2).maxCoeff());
  const double radius = 0.006, force = 1.0;
  const std::vector<NodeIndex> pushed = NodesNear(*model, point, radius);
  EXPECT_GE(pushed.size(), 4u);

  DofConstraints constraints(model->num_nodes());
  for (const NodeIndex i : clamp) constraints.FixNode(i);
  Eigen::Matrix3Xd external = Eigen::Matrix3Xd::Zero(3, model->num_nodes());
  double pushed_mass = 0.0;
  for (const NodeIndex i : pushed) pushed_mass += model->masses()[i];
  for (const NodeIndex i : pushed) external(2, i) = -force * model->masses()[i] / pushed_mass;
  Eigen::Matrix3Xd statics = model->rest_positions();
  EXPECT_TRUE(SolveStaticEquilibrium(*model, constraints, external, StaticSolverOptions{}, &statics)
                  .converged);
  SettledPush result;
  result.expected = MeanDisplacementZ(*model, statics, pushed);

  World world(options);
  BodyOptions body_options;
  body_options.damping_beta = 1e-4;
  const int body = world.AddBody("block", model, body_options);
  world.AddKinematicGroup(body, KinematicGroup{"clamp", clamp, {}});
  world.ApplyForce(body, point, Eigen::Vector3d(0.0, 0.0, -force), radius, 10.0);
  int iterations = 0, steps = 0;
  for (; world.time() < 0.5 - 1e-9; ++steps) {
    const StepReport report = world.Step(1e-3);
    EXPECT_TRUE(report.accepted) << report.reason;
    if (options.integrator == Integrator::kImplicit) {
      EXPECT_EQ(report.substeps, 1);
    }
    iterations += report.solver_iterations;
  }
  result.deflection = MeanDisplacementZ(*model, world.state(body).positions, pushed);
  result.reaction = world.wrenches(body)[0].force.z();
  result.iterations_per_step = double(iterations) / steps;
  return result;
}

// (a) A block clamped at its bottom layer, pushed down on top with 1 N, settles with 1 ms
// implicit steps onto the static solver's deflection, with either preconditioner.
TEST(ImplicitIntegrator, ClampedBlockUnderPushSettlesToTheStaticDeflection) {
  for (const double poisson : {0.25, 0.49}) {
    const auto model = Block(Eigen::Vector3d(0.04, 0.04, 0.02), 0.005, poisson);
    double jacobi_iterations = 0.0;
    for (const ImplicitPreconditioner preconditioner :
         {ImplicitPreconditioner::kJacobi, ImplicitPreconditioner::kMultigrid}) {
      WorldOptions options = ImplicitOptions(1e-3);
      options.implicit_preconditioner = preconditioner;
      const SettledPush push = PushAndSettle(model, BottomLayer(*model), options);
      std::printf(
          "  nu %.2f, %d nodes, %s: deflection %.5f mm, static %.5f mm (%+.3f %%), clamp "
          "reaction %.4f N, %.1f CG iterations per 1 ms step (explicit substep %.1f us)\n",
          poisson, model->num_nodes(), ImplicitPreconditionerName(preconditioner),
          1e3 * push.deflection, 1e3 * push.expected, 100 * (push.deflection / push.expected - 1),
          push.reaction, push.iterations_per_step, 1e6 * ExplicitStableStep(model, 1e-4));
      EXPECT_NEAR(push.deflection / push.expected, 1.0, 0.01);
      EXPECT_NEAR(push.reaction, -1.0, 0.01);  // the clamp holds the push
      // The V-cycle pays off in iterations (docs/design/implicit-solver.md); falling back to
      // Jacobi would not.
      if (preconditioner == ImplicitPreconditioner::kJacobi) {
        jacobi_iterations = push.iterations_per_step;
      } else {
        EXPECT_LT(push.iterations_per_step, 0.6 * jacobi_iterations);
      }
    }
  }
}

// The same block clamped at its base face instead (face anchors, docs/physics.md §2.1), with
// both integrators: the anchors, held by the clamp, neither limit the explicit step nor upset
// the implicit solve, and both settle onto the static deflection of the anchored model.
TEST(ImplicitIntegrator, FaceClampedBlockSettlesToTheStaticDeflectionWithBothIntegrators) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.04, 0.04, 0.02);
  lattice_options.lattice.spacing = 0.005;
  lattice_options.surface.anchored_planes = {
      AnchoredPlane{Eigen::Vector3d::Zero(), -Eigen::Vector3d::UnitZ()}};
  for (const double poisson : {0.25, 0.49}) {
    const auto model = std::make_shared<const Model>(
        BuildCubicLattice(Material::FromYoungsPoisson(2e5, poisson, 1100.0), lattice_options));
    const std::vector<NodeIndex> anchors =
        AnchorNodes(*model, lattice_options.surface.anchored_planes[0]);
    for (const bool implicit : {false, true}) {
      const SettledPush push =
          PushAndSettle(model, anchors, implicit ? ImplicitOptions(1e-3) : ExplicitOptions());
      std::printf("  nu %.2f, %s, face-clamped: deflection %.5f mm, static %.5f mm (%+.3f %%)\n",
                  poisson, implicit ? "implicit" : "explicit", 1e3 * push.deflection,
                  1e3 * push.expected, 100 * (push.deflection / push.expected - 1));
      EXPECT_NEAR(push.deflection / push.expected, 1.0, 0.01) << implicit;
      EXPECT_NEAR(push.reaction, -1.0, 0.01) << implicit;
    }
  }
}

// Two unit masses on one 1 kN/m spring along x.
std::shared_ptr<const Model> SingleSpring() {
  ModelBuilder builder(Material::FromYoungsPoisson(1e5, 0.25, 1000.0));
  builder.AddNode(Eigen::Vector3d::Zero(), 1.0);
  builder.AddNode(Eigen::Vector3d(0.1, 0.0, 0.0), 1.0);
  builder.AddSpring(0, 1, 1000.0);
  return std::make_shared<Model>(builder.Build(1e-6, 0.01));
}

// (b) The undamped spring at 100 times the explicit stable step. The kick takes the elastic
// force at the substep's end position x' = x + h (v + v') / 2, so for a linear spring (stiffness
// k, extension e) each step loses exactly E - E' = k (e' - e)^2 / 2 (kinetic change
// F(x') . (x' - x) against the potential's exact second-order expansion): the energy never rises,
// and it falls by the identity's amount, step by step.
TEST(ImplicitIntegrator, UndampedSpringLosesExactlyTheEndPointSchemesEnergyEveryStep) {
  const auto model = SingleSpring();
  const double k = 1000.0;
  const double h = 100.0 * ExplicitStableStep(model, 0.0);
  World world(ImplicitOptions(h));
  const int body = world.AddBody("spring", model);
  State state = world.state(body);
  state.positions(0, 1) += 0.01;
  world.SetState(body, state);
  const auto extension = [&] {
    const Eigen::Matrix3Xd& x = world.state(body).positions;
    return x(0, 1) - x(0, 0) - 0.1;
  };
  const double e0 = world.ComputeEnergies(body).total();
  double previous_energy = e0, previous_extension = extension();
  double worst_identity = 0.0, largest_rise = -1.0;
  for (int step = 0; step < 300; ++step) {
    ASSERT_TRUE(world.Step(h).accepted);
    const double energy = world.ComputeEnergies(body).total();
    const double loss = 0.5 * k * std::pow(extension() - previous_extension, 2);
    worst_identity = std::max(worst_identity, std::abs((previous_energy - energy) - loss) / e0);
    largest_rise = std::max(largest_rise, (energy - previous_energy) / e0);
    previous_energy = energy;
    previous_extension = extension();
  }
  std::printf(
      "  h = %.3g s (h omega = %.1f): each step's loss equals k de^2 / 2 within %.2g of the "
      "start's energy; largest rise in a step %.2g; %.3g of the energy left after 300 steps\n",
      h, h * std::sqrt(2.0 * k), worst_identity, largest_rise, previous_energy / e0);
  EXPECT_LT(worst_identity, 1e-9);
  EXPECT_LE(largest_rise, 1e-12);
  EXPECT_LT(previous_energy, e0);
}

// (b) A free block squeezed by 0.1 % along z and released, at 50 times the explicit stable step:
// with or without dampers no step adds energy beyond the solver's tolerance (1e-6 of the start,
// where the energy has fallen to the conjugate-gradient residual's level), and it decays window
// after window until it reaches that level. At h omega >> 1 the end-point kick damps most of the
// squeeze's modes within a step (docs/physics.md §7.1: the price of large steps).
TEST(ImplicitIntegrator, SqueezedBlockEnergyIsBoundedAndDampersDissipateIt) {
  const auto model = Block(Eigen::Vector3d(0.04, 0.04, 0.02), 0.005, 0.25);
  for (const double beta : {0.0, 1e-4}) {
    const double h = 50.0 * ExplicitStableStep(model, beta);
    WorldOptions world_options = ImplicitOptions(h);
    World world(world_options);
    int iterations = 0;
    BodyOptions body_options;
    body_options.damping_beta = beta;
    const int body = world.AddBody("block", model, body_options);
    State state = world.state(body);
    state.positions.row(2) = 0.01 + 0.999 * (state.positions.row(2).array() - 0.01);
    world.SetState(body, state);
    const double e0 = world.ComputeEnergies(body).total();
    const int steps = 300, window = 30;
    std::vector<double> window_peaks(steps / window, 0.0);
    double after_first = 0.0, largest_rise = 0.0, previous = e0;
    for (int step = 0; step < steps; ++step) {
      const StepReport report = world.Step(h);
      ASSERT_TRUE(report.accepted) << report.reason;
      iterations += report.solver_iterations;
      const double e = world.ComputeEnergies(body).total();
      if (step == 0) after_first = e / e0;
      largest_rise = std::max(largest_rise, (e - previous) / e0);
      previous = e;
      window_peaks[step / window] = std::max(window_peaks[step / window], e / e0);
    }
    const double loss_per_second = (e0 - previous) / (steps * h);
    std::printf(
        "  beta %.0e s, h = %.3g s: %.4g of the energy left after one step, largest rise in "
        "one step %.3g of the start, %.3g left after %.3g s (%.3g J/s lost), %d CG iterations\n",
        beta, h, after_first, largest_rise, previous / e0, steps * h, loss_per_second, iterations);
    RecordProperty(beta > 0.0 ? "damped_loss_per_second" : "undamped_loss_per_second",
                   std::to_string(loss_per_second));
    EXPECT_LT(largest_rise, 1e-6);
    for (std::size_t w = 1; w < window_peaks.size() && window_peaks[w - 1] > 1e-6; ++w) {
      EXPECT_LT(window_peaks[w], window_peaks[w - 1]) << "window " << w;
    }
  }
}

// (c) Thesis 6.4 with implicit steps: boxes 2 x 1 x 1 m of 3 x 2 x 2, 5 x 3 x 3 and 9 x 5 x 5
// nodes (1 kg) slide from v0 to rest after v0^2 / (2 mu g) within 5 %, the three within 3 % of
// each other, for the two (v0, mu) pairs of the explicit test; every box takes the same step,
// five times the finest box's explicit stable step.
TEST(ImplicitIntegrator, SlidingBoxesStopAfterTheCoulombDistanceAtEveryResolution) {
  const std::vector<std::shared_ptr<const Model>> boxes = {SlidingBox(2, 1.0), SlidingBox(3, 1.0),
                                                           SlidingBox(5, 1.0)};
  SlideExperimentOptions options;
  options.integrator = Integrator::kImplicit;
  options.step = 5.0 * ExplicitStableStep(boxes.back(), 0.0);
  ExpectCoulombStoppingDistances(boxes, options, boxes.size());
}

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
    for (const ImplicitPreconditioner preconditioner :
         {ImplicitPreconditioner::kJacobi, ImplicitPreconditioner::kMultigrid}) {
      options.implicit_preconditioner = preconditioner;
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
          "  nu %.2f, friction %.1f, %d rows from 1 mm: implicit (%s) within %.2f %% of explicit "
          "(%.3f / %.3f N at %.2f mm)\n",
          c.poisson, c.friction, compared, ImplicitPreconditionerName(preconditioner), 100 * worst,
          implicit_run.profile.back().force, explicit_run.profile.back().force,
          1e3 * explicit_run.profile.back().depth);
      EXPECT_GE(compared, 5);
      EXPECT_LT(worst, 0.05);
    }
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
  const State before = world.state(body);
  const double time = world.time();
  world.ApplyForce(body, Eigen::Vector3d(0.02, 0.02, 0.02), Eigen::Vector3d(1e12, 0.0, 0.0), 0.01,
                   0.0);
  const StepReport report = world.Step(1e-3);
  EXPECT_FALSE(report.accepted);
  EXPECT_NE(report.reason.find("m/s"), std::string::npos) << report.reason;
  EXPECT_EQ(world.state(body).positions, before.positions);
  EXPECT_EQ(world.state(body).velocities, before.velocities);
  EXPECT_EQ(world.time(), time);
  EXPECT_TRUE(world.Step(1e-3).accepted);
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

// Conjugate gradient needs a symmetric K: carrier springs with dispersion are refused, by name.
TEST(ImplicitIntegrator, RefusesANonSymmetricStiffness) {
  const auto carrier = Block(Eigen::Vector3d(0.02, 0.02, 0.02), 0.01, 0.45, SpringLaw::kNonlinear);
  ASSERT_GT(carrier->dispersion_fraction(), 0.0);
  World implicit(ImplicitOptions(1e-3));
  try {
    implicit.AddBody("carrier", carrier);
    FAIL() << "accepted a non-symmetric stiffness";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("symmetric"), std::string::npos) << error.what();
  }
  World explicit_world;
  EXPECT_NO_THROW(explicit_world.AddBody("carrier", carrier));
  const int linear =
      implicit.AddBody("linear", Block(Eigen::Vector3d(0.02, 0.02, 0.02), 0.01, 0.45));
  EXPECT_THROW(implicit.ReplaceModel(linear, carrier, BodyOptions{}), std::invalid_argument);
  WorldOptions bad = ImplicitOptions(0.0);
  EXPECT_THROW(World{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
