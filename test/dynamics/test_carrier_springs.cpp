// Issue "Fidelity against FEM", must-show 5 (carrier springs, restated; docs/physics.md §4): a
// block compressed to 30 % of its height between a rigid support its base is glued to and a
// rigid plate, held, released.
//
// What holds: with the carrier law t = k L0 (L - L0) / L no spring gets shorter than 40 % of its
// rest length at nu = 0.45 (37 % at 0.25; the must-show's bound is 10 %); linear springs reach
// 15.5 % (13 %).
// What does not, on springs alone: the lattice does not come back. Under the plate the node
// layers fold like an accordion, with either law (a layer passes its neighbour by slipping
// sideways, which no spring resists once the block is this compressed, and a folded lattice has
// the same spring lengths as an unfolded one). 1 s after the release the farthest node is
// 48-49 % of the block's size from its rest position (the bound is 1 %) and 25-29 % of the
// vertical springs point down.
// What brings it back: the orientation barrier (BodyOptions::orientation_threshold,
// docs/physics.md §4), which knows which way each cell corner faced at rest.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/mechanics/orientation_barrier.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

constexpr double kSide = 0.02;       // m, a cube
constexpr double kSpacing = 0.0025;  // m: 8 x 8 x 8 nodes

struct Squeeze {
  double shortest = std::numeric_limits<double>::infinity();  // min L / L0, pressing and holding
  double height_held = 0.0;     // m, top node centres above the clamped ones at the hold's end
  double farthest_after = 0.0;  // m, max |x - X| over the nodes 1 s after the release
  double inverted_after = 0.0;  // fraction of the vertical A springs pointing down then
  double smallest_ratio = std::numeric_limits<double>::infinity();  // min corner J, held
  int rejected_steps = 0;
  bool finite = true;
};

double ShortestSpring(const Model& model, const Eigen::Matrix3Xd& x) {
  double shortest = std::numeric_limits<double>::infinity();
  for (int s = 0; s < model.num_springs(); ++s) {
    const Eigen::Vector3d r = x.col(model.spring_node_b()[s]) - x.col(model.spring_node_a()[s]);
    shortest = std::min(shortest, r.norm() / model.spring_rest_length()[s]);
  }
  return shortest;
}

// Vertical edge springs (along z at rest) whose current vector points the other way.
double InvertedVerticalSprings(const Model& model, const Eigen::Matrix3Xd& x) {
  int vertical = 0, inverted = 0;
  for (int s = 0; s < model.num_springs(); ++s) {
    const int a = model.spring_node_a()[s], b = model.spring_node_b()[s];
    const Eigen::Vector3d rest = model.rest_positions().col(b) - model.rest_positions().col(a);
    if (std::abs(rest.z()) < 0.99 * rest.norm()) continue;
    ++vertical;
    if ((x(2, b) - x(2, a)) * rest.z() < 0.0) ++inverted;
  }
  return static_cast<double>(inverted) / vertical;
}

// The cube of kSide at kSpacing (E = 100 kPa, rho = 1100) with springs of `law`.
std::shared_ptr<const Model> Cube(double poisson, SpringLaw law) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d::Constant(kSide);
  lattice_options.lattice.spacing = kSpacing;
  lattice_options.lattice.spring_law = law;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1100.0), lattice_options));
}

// No gravity, a third of the usual step safety, `integrator`.
WorldOptions SqueezeWorldOptions(Integrator integrator) {
  WorldOptions options;
  options.gravity.setZero();
  // The step is stable for carrier springs down to 70 % of their length; at 30 % the tangent
  // stiffness is (0.7 / 0.3)^2 = 5.4 times that: a third of the usual safety keeps it stable.
  options.time_step_safety = 0.25;
  options.integrator = integrator;
  return options;
}

// Clamps body `id`'s bottom layer, adds the support under it and the plate; returns the plate.
Collider& AddSupportAndPlate(World& world, int id, const Model& model, double bottom, double top) {
  world.AddKinematicGroup(
      id,
      KinematicGroup{"base",
                     NodesInHalfSpace(model, Eigen::Vector3d(0.0, 0.0, bottom + 0.25 * kSpacing),
                                      Eigen::Vector3d::UnitZ()),
                     {}});
  Collider support;  // the half-space z <= 0, the block's bottom face
  support.name = "support";
  support.pose = Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, bottom - 0.5 * kSpacing));
  world.AddCollider(support);
  Collider plate;  // the same half-space turned over: solid above its frame
  plate.name = "plate";
  plate.pose = Eigen::Translation3d(0.5 * kSide, 0.5 * kSide, top + 0.001) *
               Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX());
  return world.collider(world.AddCollider(plate));
}

// Prints what a squeeze of the cube of rest height `height` did.
void PrintSqueeze(double poisson, SpringLaw law, double orientation_threshold, double height,
                  const Squeeze& result) {
  std::printf(
      "  nu %.2f, %s springs, orientation threshold %.1f: held at %.1f %% of the height; shortest "
      "spring %.1f %% of its rest "
      "length, smallest corner volume ratio %.2f; 1 s after the release the farthest node is %.2f "
      "%% of the block's size (%.2g m) from rest "
      "and %.0f %% of the vertical springs point down; %d rejected steps\n",
      poisson, law == SpringLaw::kNonlinear ? "carrier" : "linear", orientation_threshold,
      100.0 * result.height_held / height, 100.0 * result.shortest, result.smallest_ratio,
      100.0 * result.farthest_after / kSide, result.farthest_after, 100.0 * result.inverted_after,
      result.rejected_steps);
}

// The cube (E = 100 kPa, rho = 1100, no gravity) on a rigid support, its bottom layer clamped,
// under a rigid plate (friction 0.5): the plate comes down at 0.1 m/s until the top node
// centres are at 30 % of their rest height above the clamped layer's, stays 0.2 s, then lifts
// at 1 m/s out of reach; the block then has 1 s.
Squeeze SqueezeAndRelease(double poisson, SpringLaw law, double orientation_threshold = 0.0,
                          Integrator integrator = Integrator::kExplicit) {
  const auto model = Cube(poisson, law);
  World world(SqueezeWorldOptions(integrator));
  BodyOptions body;
  body.damping_beta = 1e-3;  // s: rings down well within the second after the release
  body.orientation_threshold = orientation_threshold;
  const OrientationBarrier corners(*model, 0.0, 0.5);  // to measure J only
  const int id = world.AddBody("block", model, body);
  const double bottom = model->rest_positions().row(2).minCoeff();
  const double top = model->rest_positions().row(2).maxCoeff();
  Collider& moving = AddSupportAndPlate(world, id, *model, bottom, top);
  const double radius = world.border(id).radii.front();  // the plate meets collision spheres
  const double pressed = bottom + 0.3 * (top - bottom) + radius;
  const double dt = 1e-3;
  Squeeze result;
  const auto step = [&](bool track) {
    if (!world.Step(dt).accepted) ++result.rejected_steps;
    result.finite = result.finite && world.state(id).positions.allFinite();
    if (track) {
      result.shortest =
          std::min(result.shortest, ShortestSpring(*model, world.state(id).positions));
      result.smallest_ratio = std::min(result.smallest_ratio,
                                       corners.VolumeRatios(world.state(id).positions).minCoeff());
    }
  };
  moving.linear_velocity = Eigen::Vector3d(0.0, 0.0, -0.1);
  while (moving.pose.translation().z() > pressed) {
    moving.pose.translation().z() = std::max(pressed, moving.pose.translation().z() - 0.1 * dt);
    step(true);
  }
  moving.linear_velocity.setZero();
  for (int k = 0; k < 200; ++k) step(true);
  result.height_held = world.state(id).positions.row(2).maxCoeff() - bottom;
  moving.linear_velocity = Eigen::Vector3d(0.0, 0.0, 1.0);
  while (moving.pose.translation().z() < top + 0.02) {
    moving.pose.translation().z() += 1.0 * dt;
    step(false);
  }
  moving.linear_velocity.setZero();
  for (int k = 0; k < 1000; ++k) step(false);
  const Eigen::Matrix3Xd& x = world.state(id).positions;
  result.farthest_after = (x - model->rest_positions()).colwise().norm().maxCoeff();
  result.inverted_after = InvertedVerticalSprings(*model, x);
  PrintSqueeze(poisson, law, orientation_threshold, top - bottom, result);
  return result;
}

TEST(CarrierSprings, NoSpringShorterThanATenthWhenSqueezedToThirtyPercent) {
  const Squeeze carrier = SqueezeAndRelease(0.45, SpringLaw::kNonlinear);
  const Squeeze linear = SqueezeAndRelease(0.45, SpringLaw::kLinear);
  for (const Squeeze* run : {&carrier, &linear}) {
    EXPECT_TRUE(run->finite);
    EXPECT_EQ(run->rejected_steps, 0);
    EXPECT_LT(run->height_held, 0.32 * (kSide - kSpacing));  // it was squeezed that far
  }
  EXPECT_GT(carrier.shortest, 0.10);  // measured 0.40 (linear: 0.155)
  EXPECT_GT(carrier.shortest, linear.shortest);
  // Without the orientation barrier neither comes back (measured: the farthest node 48-49 % of
  // the block's size from rest, 25-29 % of the vertical springs pointing down).
  EXPECT_GT(carrier.farthest_after, 0.1 * kSide);
  EXPECT_GT(linear.farthest_after, 0.1 * kSide);
}

// The must-show itself: with the orientation barrier (corners below 20 % of their rest volume
// pushed back, modulus E) the squeezed block comes back. Corners still invert under the plate
// (J down to -0.5 .. -1.2), but the barrier remembers which way they faced and unfolds them once
// the plate lifts (measured: farthest node 0.0 % of the size, no vertical spring pointing
// down; at threshold 0.1 the carrier block at nu = 0.25 stayed folded, 44 %).
TEST(CarrierSprings, ComeBackAfterTheSqueezeWithTheOrientationBarrier) {
  const double threshold = 0.2;
  const Squeeze carrier_45 = SqueezeAndRelease(0.45, SpringLaw::kNonlinear, threshold);
  const Squeeze carrier_25 = SqueezeAndRelease(0.25, SpringLaw::kNonlinear, threshold);
  const Squeeze linear_45 = SqueezeAndRelease(0.45, SpringLaw::kLinear, threshold);
  for (const Squeeze* run : {&carrier_45, &carrier_25, &linear_45}) {
    EXPECT_TRUE(run->finite);
    EXPECT_EQ(run->rejected_steps, 0);
    EXPECT_LT(run->height_held, 0.32 * (kSide - kSpacing));
    EXPECT_LT(run->farthest_after, 0.01 * kSide);
    EXPECT_EQ(run->inverted_after, 0.0);
  }
  EXPECT_GT(carrier_45.shortest, 0.10);
  EXPECT_GT(carrier_25.shortest, 0.10);
}

// The same with the implicit integrator (its stiffness includes the barrier's): linear springs
// (the implicit integrator refuses carrier springs with dispersion, which have no symmetric
// stiffness). Measured: without the barrier 48 % and 28 % of the vertical springs pointing down,
// shortest spring 8.8 %; with it back to 1.5e-9 m, shortest spring 15.9 %.
TEST(CarrierSprings, ComeBackWithTheImplicitIntegratorToo) {
  const Squeeze guarded = SqueezeAndRelease(0.45, SpringLaw::kLinear, 0.2, Integrator::kImplicit);
  const Squeeze bare = SqueezeAndRelease(0.45, SpringLaw::kLinear, 0.0, Integrator::kImplicit);
  for (const Squeeze* run : {&guarded, &bare}) {
    EXPECT_TRUE(run->finite);
    EXPECT_EQ(run->rejected_steps, 0);
    EXPECT_LT(run->height_held, 0.32 * (kSide - kSpacing));
  }
  EXPECT_LT(guarded.farthest_after, 0.01 * kSide);
  EXPECT_EQ(guarded.inverted_after, 0.0);
  EXPECT_GT(bare.farthest_after, 0.1 * kSide);
}

}  // namespace
}  // namespace msm_sim::core
