// The orientation barrier's skip test (docs/physics.md §4 "Orientation barrier"): through a
// BarrierReference it must add the same forces, bit for bit, as the full evaluation, on seeded
// walks that bring corners close to the threshold and past it, in both precisions and on the
// trajectories of both integrators.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/force_evaluator.h"
#include "msm_sim/mechanics/orientation_barrier.h"

namespace msm_sim::core {
namespace {

constexpr double kSpacing = 0.01;  // m

std::shared_ptr<const Model> Block(const Eigen::Vector3d& cells) {
  CubicLatticeOptions options;
  options.size = cells * kSpacing;
  options.lattice.spacing = kSpacing;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1000.0), options));
}

// A seeded walk of the block's shape, `steps` long: carried along and turned whole, every node
// drifting by a random walk, and the top layer's nodes near a seeded one pressed down by up to
// 1.6 spacings and let back twice (their corners fall below the threshold, invert, come back).
std::vector<Eigen::Matrix3Xd> Walk(const Model& model, int steps, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const double top = rest.row(2).maxCoeff();
  std::vector<Eigen::Index> layer;
  for (Eigen::Index i = 0; i < rest.cols(); ++i) {
    if (rest(2, i) > top - 0.5 * kSpacing) layer.push_back(i);
  }
  const Eigen::Vector3d centre = rest.col(layer[rng() % layer.size()]);
  const Eigen::Vector3d axis = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)).normalized();
  const Eigen::Vector3d carry = Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  Eigen::Matrix3Xd drift = Eigen::Matrix3Xd::Zero(3, rest.cols());
  std::vector<Eigen::Matrix3Xd> walk;
  for (int k = 0; k < steps; ++k) {
    for (Eigen::Index i = 0; i < drift.size(); ++i) drift.data()[i] += 4e-4 * kSpacing * noise(rng);
    const double depth = 1.6 * kSpacing * std::pow(std::sin(2.0 * M_PI * k / steps), 2);
    Eigen::Matrix3Xd x = rest + drift;
    for (const Eigen::Index i : layer) {
      const double r2 = (rest.col(i) - centre).squaredNorm() / std::pow(2.5 * kSpacing, 2);
      if (r2 < 1.0) x(2, i) -= depth * (1.0 - r2);
    }
    const Eigen::AngleAxisd turn(2e-3 * k, axis);
    walk.push_back((turn.toRotationMatrix() * x).colwise() + 0.05 * kSpacing * k * carry);
  }
  return walk;
}

bool Same(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return a.cols() == b.cols() && (a.array() == b.array()).all();
}

TEST(OrientationBarrierTracking, SameForcesAsTheFullEvaluationOnSeededWalks) {
  const auto model = Block(Eigen::Vector3d(6, 5, 4));
  const OrientationBarrier barrier(*model, 1e5, 0.3);
  for (unsigned seed = 1; seed <= 4; ++seed) {
    BarrierReference reference;
    int full_checks = 0, active_steps = 0, inverted_steps = 0;
    const std::vector<Eigen::Matrix3Xd> walk = Walk(*model, 400, seed);
    for (std::size_t k = 0; k < walk.size(); ++k) {
      const Eigen::Matrix3Xd& x = walk[k];
      const Eigen::Matrix3Xd start = Eigen::Matrix3Xd::Constant(3, x.cols(), 0.1 * k);
      Eigen::Matrix3Xd tracked = start, full = start;
      barrier.AccumulateForces(x, &tracked, &reference);
      barrier.AccumulateForces(x, &full);
      ASSERT_TRUE(Same(tracked, full)) << "seed " << seed << " step " << k;
      full_checks += Same(reference.positions, x);
      ASSERT_EQ(barrier.ActiveCorners(x, &reference), barrier.ActiveCorners(x));
      active_steps += !barrier.ActiveCorners(x).empty();
      inverted_steps += barrier.VolumeRatios(x).minCoeff() < 0.0;
    }
    EXPECT_GT(active_steps, 50);
    EXPECT_GT(inverted_steps, 10);
    EXPECT_LT(full_checks, 40) << "seed " << seed;  // the test skips most evaluations' corners
  }
}

// An evaluator with the barrier against one without plus the full barrier, as its loops add it:
// onto the springs' sums in double, per share from a zeroed array in single precision.
void ExpectSameForcesAsFull(const std::shared_ptr<const Model>& model,
                            const std::shared_ptr<const OrientationBarrier>& barrier,
                            SpringPrecision precision, const std::vector<Eigen::Matrix3Xd>& walk) {
  ForceEvaluator guarded(*model, SpringKernels::kAuto, 2), plain(*model, SpringKernels::kAuto, 2);
  guarded.set_precision(precision);
  plain.set_precision(precision);
  guarded.set_orientation_barrier(barrier);
  const Eigen::Matrix3Xd v = Eigen::Matrix3Xd::Constant(3, model->num_nodes(), 0.01);
  for (std::size_t k = 0; k < walk.size(); ++k) {
    Eigen::Matrix3Xd with, expected;
    guarded.SetForces(walk[k], v, 1e-3, &with);
    plain.SetForces(walk[k], v, 1e-3, &expected);
    if (precision == SpringPrecision::kDouble) {
      barrier->AccumulateForces(walk[k], &expected);
    } else {
      Eigen::Matrix3Xd added = Eigen::Matrix3Xd::Zero(3, model->num_nodes());
      barrier->AccumulateForces(walk[k], &added);
      expected += added;
    }
    ASSERT_TRUE(Same(with, expected)) << static_cast<int>(precision) << " step " << k;
  }
}

TEST(OrientationBarrierTracking, EvaluatorsAddTheSameForcesInBothPrecisions) {
  const auto model = Block(Eigen::Vector3d(12, 10, 9));  // 1,430 nodes: two node shares
  const auto barrier = std::make_shared<const OrientationBarrier>(*model, 1e5, 0.3);
  const std::vector<Eigen::Matrix3Xd> walk = Walk(*model, 120, 9);
  for (const SpringPrecision precision : {SpringPrecision::kDouble, SpringPrecision::kSingle}) {
    ExpectSameForcesAsFull(model, barrier, precision, walk);
  }
}

// The positions each integrator takes a block through whose top and bottom node layers are
// thrown at each other (its cells squeezed past the threshold and back), one per step.
std::vector<Eigen::Matrix3Xd> Collapse(const std::shared_ptr<const Model>& model,
                                       Integrator integrator) {
  WorldOptions options;
  options.integrator = integrator;
  options.gravity.setZero();
  World world(options);
  BodyOptions body;
  body.orientation_threshold = 0.3;
  const int id = world.AddBody("block", model, body);
  State state = State::AtRest(*model);
  const double bottom = model->rest_positions().row(2).minCoeff();
  const double top = model->rest_positions().row(2).maxCoeff();
  for (Eigen::Index i = 0; i < state.positions.cols(); ++i) {
    const double z = state.positions(2, i);
    if (z > top - 0.5 * kSpacing) state.velocities(2, i) = -15.0;
    if (z < bottom + 0.5 * kSpacing) state.velocities(2, i) = 15.0;
  }
  world.SetState(id, state);
  std::vector<Eigen::Matrix3Xd> walk;
  for (int k = 0; k < 60; ++k) {
    world.Step(2e-4);
    walk.push_back(world.state(id).positions);
  }
  return walk;
}

TEST(OrientationBarrierTracking, SameForcesOnBothIntegratorsTrajectories) {
  const auto model = Block(Eigen::Vector3d(5, 5, 4));
  const auto barrier = std::make_shared<const OrientationBarrier>(*model, 1e5, 0.3);
  for (const Integrator integrator : {Integrator::kExplicit, Integrator::kImplicit}) {
    const std::vector<Eigen::Matrix3Xd> walk = Collapse(model, integrator);
    int active = 0;
    for (const Eigen::Matrix3Xd& x : walk) active += !barrier->ActiveCorners(x).empty();
    EXPECT_GT(active, 5) << static_cast<int>(integrator);
    for (const SpringPrecision precision : {SpringPrecision::kDouble, SpringPrecision::kSingle}) {
      ExpectSameForcesAsFull(model, barrier, precision, walk);
    }
  }
}

}  // namespace
}  // namespace msm_sim::core
