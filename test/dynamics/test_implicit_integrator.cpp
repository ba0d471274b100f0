// The implicit substep (docs/physics.md §7.1): static equilibrium, energy and sliding at steps
// far beyond the explicit stability limit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "implicit_test_blocks.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/experiments/slide_experiment.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/dof_constraints.h"
#include "msm_sim/mechanics/static_solver.h"
#include "msm_sim/model/model_builder.h"
#include "sliding_checks.h"

namespace msm_sim::core {
namespace {

// Explicit (Verlet), no gravity.
WorldOptions ExplicitOptions() {
  WorldOptions options;
  options.gravity = Eigen::Vector3d::Zero();
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
// implicit steps onto the static solver's deflection.
TEST(ImplicitIntegrator, ClampedBlockUnderPushSettlesToTheStaticDeflection) {
  for (const double poisson : {0.25, 0.49}) {
    const auto model = Block(Eigen::Vector3d(0.04, 0.04, 0.02), 0.005, poisson);
    const SettledPush push = PushAndSettle(model, BottomLayer(*model), ImplicitOptions(1e-3));
    std::printf(
        "  nu %.2f, %d nodes: deflection %.5f mm, static %.5f mm (%+.3f %%), clamp "
        "reaction %.4f N, %.1f CG iterations per 1 ms step (explicit substep %.1f us)\n",
        poisson, model->num_nodes(), 1e3 * push.deflection, 1e3 * push.expected,
        100 * (push.deflection / push.expected - 1), push.reaction, push.iterations_per_step,
        1e6 * ExplicitStableStep(model, 1e-4));
    EXPECT_NEAR(push.deflection / push.expected, 1.0, 0.01);
    EXPECT_NEAR(push.reaction, -1.0, 0.01);  // the clamp holds the push
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

}  // namespace
}  // namespace msm_sim::core
