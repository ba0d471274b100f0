// Acceptance tests of the dynamics (docs/physics.md §7, thesis ch. 6; issue "Dynamics"): sliding
// with dry friction, energy conservation, non-penetration, resting and pressing contacts, rejected
// steps.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/experiments/slide_experiment.h"
#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/lattice/mesh_lattice_builder.h"
#include "msm_sim/model/model_builder.h"
#include "rejected_step_checks.h"
#include "sliding_checks.h"

namespace msm_sim::core {
namespace {

// Thesis 6.4: boxes of 3 x 2 x 2, 5 x 3 x 3 and 9 x 5 x 5 nodes of equal mass, and a body of
// another mass and shape (a squat anti-aliased cylinder of 3 kg standing on its base; a ball
// would roll), stop after v0^2 / (2 mu g).
TEST(Sliding, StoppingDistanceIsIndependentOfResolutionShapeAndMass) {
  const SolidMesh cylinder_mesh(MakeCylinderMesh(0.4, 0.4, 64));
  MeshCubicLatticeOptions cylinder_lattice;
  cylinder_lattice.lattice.spacing = 0.1;
  const auto cylinder = std::make_shared<Model>(
      BuildCubicLatticeInSolid(Material::FromYoungsPoisson(1e5, 0.3, 3.0 / cylinder_mesh.volume()),
                               cylinder_mesh, cylinder_lattice));
  const std::vector<std::shared_ptr<const Model>> bodies = {SlidingBox(2, 1.0), SlidingBox(3, 1.0),
                                                            SlidingBox(5, 1.0), cylinder};
  ExpectCoulombStoppingDistances(bodies, SlideExperimentOptions{}, 3);  // the three boxes
}

std::shared_ptr<const Model> Ball(double radius, double spacing, const Material& material) {
  const SolidMesh mesh(MakeIcosphereMesh(radius, 4));
  MeshCubicLatticeOptions options;
  options.lattice.spacing = spacing;
  return std::make_shared<Model>(BuildCubicLatticeInSolid(material, mesh, options));
}

Collider Ground(double height = 0.0, double friction = 0.5) {
  Collider ground;
  ground.name = "ground";
  ground.friction = friction;
  ground.pose.translation() = Eigen::Vector3d(0.0, 0.0, height);
  return ground;
}

// What a bouncing ball's total energy E(t) did (fractions of its start E0).
struct BounceRecord {
  int flights = 0;
  /// The lowest node's highest point in each flight, as a fraction of its height at the drop.
  std::vector<double> apexes;
  double worst_deviation = 0.0;  ///< max |E / E0 - 1|
  double largest_gain = 0.0;     ///< max (E_k - E_{k-1}) / E0 over single steps
  double loss_per_second = 0.0;  ///< -slope of the least-squares line through E / E0 (1/s)
};

// Thesis 6.2: a frictionless, undamped elastic ball of 360 nodes (E = 100 kPa) dropped from 0.2 m
// + `higher` bounces on the ground in steps of `step` (s) for 10 s, or `flights` flights (if > 0).
BounceRecord BounceBall(const WorldOptions& world_options, double step, double higher = 0.0,
                        int flights = 0) {
  const auto ball = Ball(0.1, 0.025, Material::FromYoungsPoisson(1e5, 0.3, 1000.0));
  World world(world_options);
  BodyOptions options;
  options.friction = 0.0;
  const int body = world.AddBody("ball", ball, options);
  world.AddCollider(Ground(0.0, 0.0));
  State state = world.state(body);
  state.positions.row(2).array() += 0.3 + higher;
  world.SetState(body, state);
  const double initial = world.ComputeEnergies(body).total();
  const double drop_height = state.positions.row(2).minCoeff();
  BounceRecord record;
  bool airborne = false;  // the drop itself counts as the first flight
  double previous = 1.0, n = 0.0, sum_t = 0.0, sum_e = 0.0, sum_tt = 0.0, sum_te = 0.0;
  const int steps = static_cast<int>(std::lround(10.0 / step));
  for (int k = 1; k <= steps; ++k) {
    const StepReport report = world.Step(step);
    EXPECT_TRUE(report.accepted) << report.reason;
    if (!report.accepted) break;
    const double lowest = world.state(body).positions.row(2).minCoeff();
    const bool now_airborne = lowest > 0.03;
    record.flights += now_airborne && !airborne;
    if (now_airborne && !airborne) record.apexes.push_back(0.0);
    if (now_airborne) record.apexes.back() = std::max(record.apexes.back(), lowest / drop_height);
    airborne = now_airborne;
    if (flights > 0 && record.flights > flights && !airborne) break;  // its apex is complete
    const double e = world.ComputeEnergies(body).total() / initial, t = k * step;
    record.worst_deviation = std::max(record.worst_deviation, std::abs(e - 1.0));
    record.largest_gain = std::max(record.largest_gain, e - previous);
    previous = e;
    n += 1.0, sum_t += t, sum_e += e, sum_tt += t * t, sum_te += t * e;
  }
  record.loss_per_second = -(n * sum_te - sum_t * sum_e) / (n * sum_tt - sum_t * sum_t);
  if (flights > 0) return record;
  std::printf(
      "  %s, %.1f ms steps: %d flights in 10 s (rebounds to %.3f, %.3f, %.3f of the drop "
      "height), largest energy deviation %.3f %%, loss %.4f %% per second, largest gain in one "
      "step %.4f %%\n",
      IntegratorName(world_options.integrator), 1e3 * step, record.flights - 1,
      record.apexes.size() > 1 ? record.apexes[1] : 0.0,
      record.apexes.size() > 2 ? record.apexes[2] : 0.0,
      record.apexes.size() > 3 ? record.apexes[3] : 0.0, 100 * record.worst_deviation,
      100 * record.loss_per_second, 100 * record.largest_gain);
  return record;
}

// The split elastic response conserves energy. It stops a node for one substep at each contact,
// which costs energy to first order in the step (2.4 % over 10 s at 1 ms, 0.6 % at 0.5 ms); at
// 0.2 ms the total stays within 1 % at every instant. Single steps in contact gain up to 0.5 % of
// it and give it back in the next ones (with e = 1 only; README "Dynamics"), so the per-step gain
// is reported, not bounded; so is the number of flights in 10 s (later impacts turn on rounding).
TEST(Energy, ElasticBallBouncingForTenSecondsKeepsItsEnergy) {
  for (const SpringPrecision precision : {SpringPrecision::kSingle, SpringPrecision::kDouble}) {
    WorldOptions options;
    options.spring_precision = precision;
    const BounceRecord record = BounceBall(options, 2e-4);
    ASSERT_GE(record.apexes.size(), 4u);  // the drop and three rebounds
    EXPECT_LT(record.worst_deviation, 0.01);
  }
}

// That the ball keeps bouncing: its first three rebounds from nine drops 0.18-0.22 m. Each impact
// leaves part of the fall in vibration, how much turning on which cut cells' small collision
// spheres meet the ground first: 5 mm more drop can take the rebounds from about 0.5 to 0.25 of
// the drop (docs/design/mass-scaling.md), so their mean over the drops is what is bounded.
TEST(Energy, ElasticBallReboundsOverARangeOfDropHeights) {
  double sum = 0.0;
  int count = 0;
  for (int drop = -4; drop <= 4; ++drop) {
    const BounceRecord record = BounceBall(WorldOptions{}, 2e-4, 0.005 * drop, 3);
    ASSERT_GE(record.apexes.size(), 4u);  // the drop and three rebounds
    std::printf("  drop %+.3f m: rebounds to %.3f, %.3f, %.3f of the drop height\n", 0.005 * drop,
                record.apexes[1], record.apexes[2], record.apexes[3]);
    for (int rebound = 1; rebound <= 3; ++rebound) sum += record.apexes[rebound], ++count;
  }
  std::printf("  mean rebound %.3f of the drop height\n", sum / count);
  EXPECT_GT(sum / count, 0.3);
}

// The implicit integrator (docs/physics.md §7.1) on the same ball in 1 ms steps, one implicit
// substep each: its kick takes the elastic force at the step's end position and so cannot add
// energy, and the loss per second (measured 2.8 %) is what the scheme's damping costs. No step
// may gain more than 0.1 % of the starting energy (measured: none gains).
TEST(Energy, ImplicitBallBouncingNeverGainsEnergyInAStep) {
  WorldOptions options;
  options.integrator = Integrator::kImplicit;
  const BounceRecord record = BounceBall(options, 1e-3);
  RecordProperty("loss_per_second_percent", std::to_string(100 * record.loss_per_second));
  ASSERT_GE(record.apexes.size(), 2u);  // the drop and at least one rebound
  EXPECT_LT(record.largest_gain, 1e-3);
  EXPECT_GT(record.loss_per_second, 0.0);
}

// A single node (no springs) with a collision sphere of 25 mm.
std::shared_ptr<const Model> Particle() {
  ModelBuilder builder(Material::FromYoungsPoisson(1e5, 0.25, 1000.0));
  builder.AddNode(Eigen::Vector3d::Zero(), 1.0);
  return std::make_shared<Model>(builder.Build(1e-6, 0.05));
}

// A plane through the origin whose free side faces `normal`.
Collider PlaneFacing(const std::string& name, const Eigen::Vector3d& normal) {
  Collider plane;
  plane.name = name;
  plane.friction = 0.0;
  plane.pose.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal).toRotationMatrix();
  return plane;
}

// Thesis 6.2.2: a node between two planes at 30 degrees, touching both at once, never crosses
// either: after the first part of the response it approaches neither.
TEST(Contacts, NodeInAThirtyDegreeWedgeNeverPenetrates) {
  World world;
  BodyOptions options;
  options.friction = 0.0;
  options.restitution = 0.3;  // loses energy, so that it ends wedged against both walls
  const int body = world.AddBody("node", Particle(), options);
  const double half = 15.0 * M_PI / 180.0;
  const Eigen::Vector3d n1(-std::cos(half), 0.0, std::sin(half));  // right wall's free side
  const Eigen::Vector3d n2(std::cos(half), 0.0, std::sin(half));   // left wall's
  world.AddCollider(PlaneFacing("right", n1));
  world.AddCollider(PlaneFacing("left", n2));
  State state = world.state(body);
  state.positions.col(0) = Eigen::Vector3d(0.05, 0.0, 0.5);
  state.velocities.col(0) = Eigen::Vector3d(-1.0, 0.0, 0.0);
  world.SetState(body, state);
  const double radius = world.border(body).radii[0];
  double closest = std::numeric_limits<double>::infinity();
  int touching_both = 0;
  for (int step = 0; step < 5000; ++step) {
    ASSERT_TRUE(world.Step(1e-3).accepted);
    const Eigen::Vector3d x = world.state(body).positions.col(0);
    closest = std::min({closest, n1.dot(x), n2.dot(x)});
    touching_both += n1.dot(x) < radius && n2.dot(x) < radius;
  }
  std::printf(
      "  closest approach of the node's centre to a wall: %.4f m (sphere radius %.4f m); "
      "%d steps touching both walls\n",
      closest, radius, touching_both);
  EXPECT_GT(touching_both, 100);
  // The overlap never exceeds what one substep of travel can add before detection.
  EXPECT_GT(closest, 0.5 * radius);
}

std::shared_ptr<const Model> Block(double size, double spacing, double youngs = 1e5) {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d::Constant(size);
  options.lattice.spacing = spacing;
  return std::make_shared<Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(youngs, 0.3, 1000.0), options));
}

double LowestSphere(const World& world, int body) {
  return LowestSphereBottom(world.state(body).positions, world.border(body));
}

// Two blocks stacked on the ground (the top one dropped from 5 mm, shifted by a quarter of a
// node spacing) settle; no pair of their collision spheres ever overlaps by more than 10 %.
TEST(Contacts, TwoStackedBlocksSettleWithoutInterpenetration) {
  World world;
  BodyOptions options;
  options.damping_beta = 0.01;
  options.restitution = 0.2;
  const int bottom = world.AddBody("bottom", Block(0.2, 0.04), options);
  const int top = world.AddBody("top", Block(0.2, 0.04), options);
  Collider ground = Ground(LowestSphere(world, bottom));
  ground.restitution = 0.2;
  world.AddCollider(ground);
  State state = world.state(top);
  state.positions.row(2).array() += 0.2 + 2.0 * world.border(top).radii[0] + 0.005;
  state.positions.row(0).array() += 0.01;
  world.SetState(top, state);
  const BorderNodes& a = world.border(top);
  const BorderNodes& b = world.border(bottom);
  double closest = std::numeric_limits<double>::infinity();  // relative to the sum of radii
  for (int step = 0; step < 2000; ++step) {
    ASSERT_TRUE(world.Step(1e-3).accepted);
    for (std::size_t p = 0; p < a.nodes.size(); ++p) {
      for (std::size_t q = 0; q < b.nodes.size(); ++q) {
        const double distance = (world.state(top).positions.col(a.nodes[p]) -
                                 world.state(bottom).positions.col(b.nodes[q]))
                                    .norm();
        closest = std::min(closest, distance / (a.radii[p] + b.radii[q]));
      }
    }
  }
  const double top_height = world.state(top).positions.row(2).mean();
  const double bottom_height = world.state(bottom).positions.row(2).mean();
  std::printf(
      "  closest pair of collision spheres: %.3f of the touching distance; block centres "
      "%.4f m apart vertically\n",
      closest, top_height - bottom_height);
  EXPECT_GT(closest, 0.9);
  EXPECT_NEAR(top_height - bottom_height, 0.2 + 2.0 * a.radii[0] - 0.04, 0.01);
  for (const int body : {bottom, top}) {
    EXPECT_LT(world.state(body).velocities.colwise().norm().maxCoeff(), 1e-3);
  }
}

TEST(Contacts, RestingBlockLoadsTheGroundWithItsWeightThroughItsCentreOfMass) {
  World world;
  BodyOptions options;
  options.damping_beta = 0.004;
  const auto block = Block(0.2, 0.025);
  const int body = world.AddBody("block", block, options);
  // Off the ground frame's origin, so that the torque about it is not zero.
  State state = world.state(body);
  state.positions.row(0).array() += 0.3;
  state.positions.row(1).array() -= 0.2;
  world.SetState(body, state);
  world.AddCollider(Ground(LowestSphere(world, body)));
  for (int step = 0; step < 1000; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  const int steps = 1000;
  for (int step = 0; step < steps; ++step) {
    ASSERT_TRUE(world.Step(1e-3).accepted);
    force += world.wrenches(body)[0].force / steps;
    torque += world.wrenches(body)[0].torque / steps;
  }
  const double weight = block->masses().sum() * 9.81;
  const Eigen::Vector3d com = world.state(body).positions * block->masses() / block->masses().sum();
  std::printf(
      "  ground force (%.3f, %.3f, %.3f) N against weight %.3f N; torque (%.4f, %.4f) N m, "
      "expected (%.4f, %.4f)\n",
      force.x(), force.y(), force.z(), weight, torque.x(), torque.y(), com.cross(force).x(),
      com.cross(force).y());
  EXPECT_NEAR(-force.z() / weight, 1.0, 0.01);
  EXPECT_LT(force.head<2>().norm(), 0.01 * weight);
  // The ground's reaction acts under the centre of mass: tau = com x F about the ground origin.
  EXPECT_LT((torque - com.cross(force)).norm(), 0.01 * com.norm() * weight);
}

// The nodes of `model` below `height` at rest, as a kinematic group.
KinematicGroup ClampBelow(const Model& model, double height) {
  KinematicGroup clamp{"clamp", {}, {}};
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    if (model.rest_positions()(2, i) < height) clamp.nodes.push_back(i);
  }
  return clamp;
}

// A 4 cm finger touching the top nodes' spheres of `body` at rest, moving down at 2 cm/s.
Collider FingerAbove(const World& world, int body, const Model& model) {
  Collider sphere;
  sphere.name = "finger";
  sphere.shape = ColliderShape::Sphere(0.04);
  sphere.friction = 0.3;
  double top = 0.0;
  for (std::size_t k = 0; k < world.border(body).nodes.size(); ++k) {
    top = std::max(
        top, model.rest_positions()(2, world.border(body).nodes[k]) + world.border(body).radii[k]);
  }
  sphere.pose.translation() = Eigen::Vector3d(0.1, 0.1, top + 0.04);
  sphere.linear_velocity = Eigen::Vector3d(0.0, 0.0, -0.02);
  return sphere;
}

// Prints the pressing forces (N), one a window.
void PrintPressing(const std::vector<double>& pressing) {
  std::printf("  pressing force per mm of indentation:");
  for (const double f : pressing) std::printf(" %.2f", f);
  std::printf(" N\n");
}

// A kinematic sphere pressed at constant speed into a block clamped at its base, then dragged.
TEST(Contacts, PressedSphereForceGrowsWithIndentationAndFrictionIsBounded) {
  World world;
  BodyOptions options;
  options.damping_beta = 0.004;
  options.friction = 0.3;
  const auto block = Block(0.2, 0.02);
  const int body = world.AddBody("block", block, options);
  world.AddKinematicGroup(body, ClampBelow(*block, 0.02));
  const int finger = world.AddCollider(FingerAbove(world, body, *block));
  const double dt = 1e-3;
  // Pressing for 0.6 s (12 mm), force averaged over 50 ms windows (1 mm of indentation).
  std::vector<double> pressing;
  for (int window = 0; window < 12; ++window) {
    double fz = 0.0;
    for (int step = 0; step < 50; ++step) {
      ASSERT_TRUE(world.Step(dt).accepted);
      fz += world.wrenches(body)[finger].force.z() / 50;
    }
    pressing.push_back(fz);  // > 0: the block pushes the finger up
  }
  PrintPressing(pressing);
  // The block first sags under its weight away from the finger; from first contact on, every
  // millimetre of indentation pushes back harder.
  std::size_t first_contact = 0;
  while (first_contact < pressing.size() && pressing[first_contact] <= 0.1) ++first_contact;
  ASSERT_LT(first_contact + 5, pressing.size());
  for (std::size_t w = first_contact + 1; w < pressing.size(); ++w) {
    EXPECT_GT(pressing[w], pressing[w - 1]) << "window " << w;
  }
  EXPECT_GT(pressing.back(), 10.0);
  // Dragging along +x at 2 cm/s at constant depth.
  world.collider(finger).linear_velocity = Eigen::Vector3d(0.02, 0.0, 0.0);
  for (int step = 0; step < 100; ++step) ASSERT_TRUE(world.Step(dt).accepted);
  for (int window = 0; window < 8; ++window) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (int step = 0; step < 50; ++step) {
      ASSERT_TRUE(world.Step(dt).accepted);
      f += world.wrenches(body)[finger].force / 50;
    }
    const double tangential = f.head<2>().norm();
    std::printf("  dragging: F_t %.3f N, F_n %.3f N, ratio %.3f (mu 0.3)\n", tangential, f.z(),
                tangential / f.z());
    // Coulomb's bound per microcollision holds for the sum up to the spread of contact normals
    // over the curved finger: 5 %.
    EXPECT_LE(tangential, 0.3 * f.z() * 1.05);
    EXPECT_LT(f.x(), 0.0);  // the block holds the finger back
  }
}

TEST(Steps, AbsurdForceIsRejectedAndTheStateKept) {
  World world;
  const int body = world.AddBody("block", Block(0.2, 0.05));
  world.AddCollider(Ground(LowestSphere(world, body)));
  for (int step = 0; step < 10; ++step) ASSERT_TRUE(world.Step(1e-3).accepted);
  ExpectAbsurdForceRejectedAndStateKept(&world, body, Eigen::Vector3d(0.1, 0.1, 0.2), 0.05);
  EXPECT_THROW(world.ApplyForce(body, Eigen::Vector3d::Zero(),
                                Eigen::Vector3d(std::nan(""), 0.0, 0.0), 0.05, 0.0),
               std::invalid_argument);
  EXPECT_THROW(world.Step(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
