// Penetration recovery (docs/physics.md §7.2): a node found deeper than its collision sphere
// allows is moved back out within WorldOptions::penetration_recovery_time, at no more than
// penetration_max_speed, without an energy burst, for both integrators.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model_transform.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

// 3.6 x 3.6 x 1.8 cm at a = 3 mm: 12 x 12 x 6 = 864 nodes, E = 100 kPa.
std::shared_ptr<const Model> Block(double poisson) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.036, 0.036, 0.018);
  lattice_options.lattice.spacing = 0.003;
  return std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, poisson, 1100.0), lattice_options));
}

// The deepest overlap (m) of a border node's collision sphere with the collider:
// max over the nodes of r - signed distance (<= 0: none).
double Overlap(const World& world, int body, int collider) {
  const BorderNodes& border = world.border(body);
  const Collider& c = world.collider(collider);
  const Eigen::Isometry3d inverse = c.pose.inverse();
  double deepest = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    Eigen::Vector3d normal, closest;
    const Eigen::Vector3d x = world.state(body).positions.col(border.nodes[k]);
    deepest =
        std::max(deepest, border.radii[k] - c.shape.SignedDistance(inverse * x, &normal, &closest));
  }
  return deepest;
}

struct Recovery {
  double overlap_before, overlap_at_50ms, overlap_after, force_after;
  double peak_kinetic, final_elastic, max_total, final_total;
  int rejected = 0;
};

// How an indenter reaches its pose `depth` past first contact.
enum class Arrival { kTeleported, kPressedSlowly };

// The block (base clamped, no gravity) and an indenter of `shape` whose bottom face is level:
// a 2 x 2 x 2 cm box, or the same box as a triangle mesh.
struct Indentation {
  std::unique_ptr<World> world;
  int body = 0, collider = 0;
  // m, the height at which a level face touches the first collision sphere of the block's top:
  // depths are counted from there, as msm_lab indent counts a sphere's.
  double touch = 0.0;
  Eigen::Vector3d centre;
};

Indentation MakeIndentation(double poisson, const ColliderShape& shape, Integrator integrator,
                            double max_speed) {
  WorldOptions options;
  options.penetration_max_speed = max_speed;
  options.gravity.setZero();
  options.integrator = integrator;
  Indentation s;
  s.world = std::make_unique<World>(options);
  const auto model = Block(poisson);
  BodyOptions body_options;
  body_options.damping_beta = 1e-4;
  s.body = s.world->AddBody("block", model, body_options);
  const double bottom = model->rest_positions().row(2).minCoeff();
  s.world->AddKinematicGroup(
      s.body, KinematicGroup{"base",
                             NodesInHalfSpace(*model, Eigen::Vector3d(0.0, 0.0, bottom + 0.0015),
                                              Eigen::Vector3d::UnitZ()),
                             {}});
  const BorderNodes& border = s.world->border(s.body);
  s.touch = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    s.touch = std::max(s.touch, model->rest_positions()(2, border.nodes[k]) + border.radii[k]);
  }
  s.centre = 0.5 * (model->rest_positions().rowwise().minCoeff() +
                    model->rest_positions().rowwise().maxCoeff());
  Collider indenter;
  indenter.name = "indenter";
  indenter.shape = shape;
  s.collider = s.world->AddCollider(indenter);
  return s;
}

// Presses the indenter, its bottom face level, from 0.5 mm above first contact to `depth` past
// it at 5 mm/s in 1 ms steps. Each step starts where the last one's velocity
// took the indenter (the World moves a collider by its velocity); it ends at rest. Returns the
// rejected steps.
int PressTo(Indentation* s, double depth) {
  World& world = *s->world;
  Collider& indenter = world.collider(s->collider);
  const double speed = 0.005, start = s->touch + 5e-4, end = s->touch - depth, dt = 1e-3;
  int rejected = 0;
  for (double z = start; z > end;) {
    const double next = std::max(end, z - speed * dt);
    indenter.pose.translation() = Eigen::Vector3d(s->centre.x(), s->centre.y(), z + 0.01);
    indenter.linear_velocity = Eigen::Vector3d(0.0, 0.0, (next - z) / dt);
    if (!world.Step(dt).accepted) ++rejected;
    z = next;
  }
  indenter.linear_velocity.setZero();
  return rejected;
}

// The indenter's bottom face `depth` past first contact, either placed there at once or pressed
// there (PressTo); then held still for 0.2 s in 1 ms steps. The force is the mean over the
// hold's last 20 ms.
Recovery Indent(double poisson, double depth, const ColliderShape& shape, Integrator integrator,
                Arrival arrival, double max_speed = 0.1) {
  Indentation s = MakeIndentation(poisson, shape, integrator, max_speed);
  World& world = *s.world;
  Collider& indenter = world.collider(s.collider);
  const auto place = [&](double bottom_z) {
    indenter.pose.translation() = Eigen::Vector3d(s.centre.x(), s.centre.y(), bottom_z + 0.01);
  };
  Recovery r;
  if (arrival == Arrival::kPressedSlowly) r.rejected += PressTo(&s, depth);
  place(s.touch - depth);
  r.overlap_before = Overlap(world, s.body, s.collider);
  r.peak_kinetic = 0.0;
  r.max_total = -std::numeric_limits<double>::infinity();
  double force = 0.0;
  for (int k = 0; k < 200; ++k) {
    if (!world.Step(1e-3).accepted) ++r.rejected;
    const Energies energies = world.ComputeEnergies(s.body);
    r.peak_kinetic = std::max(r.peak_kinetic, energies.kinetic);
    if (k == 49) r.overlap_at_50ms = Overlap(world, s.body, s.collider);
    r.max_total = std::max(r.max_total, energies.total());
    if (k >= 180) force += world.wrenches(s.body)[s.collider].force.z() / 20.0;
    r.final_elastic = energies.elastic;
    r.final_total = energies.total();
  }
  r.overlap_after = Overlap(world, s.body, s.collider);
  r.force_after = force;
  std::printf(
      "  %s %s %.1f mm past first contact, nu %.2f, %s: overlap %.3f mm -> %.3f mm (50 ms) -> %.4f "
      "mm (0.2 s), "
      "force %.3f N, kinetic peak %.3g J, elastic %.3g J, total max %.4g / final %.4g J\n",
      shape.type() == ColliderShape::Type::kMesh ? "mesh box" : "box",
      arrival == Arrival::kTeleported ? "teleported" : "pressed", 1e3 * depth, poisson,
      IntegratorName(integrator), 1e3 * r.overlap_before, 1e3 * r.overlap_at_50ms,
      1e3 * r.overlap_after, r.force_after, r.peak_kinetic, r.final_elastic, r.max_total,
      r.final_total);
  return r;
}

ColliderShape Box2cm() { return ColliderShape::Box(Eigen::Vector3d(0.02, 0.02, 0.02)); }

ColliderShape MeshBox2cm() {
  BodyShape box;
  box.kind = BodyShape::Kind::kBox;
  box.size = Eigen::Vector3d(0.02, 0.02, 0.02);
  return ColliderShape::Mesh(std::make_shared<const SolidMesh>(MakeBodySolid(box)));
}

Recovery RecoverFromBox(double poisson, double depth, Integrator integrator,
                        double max_speed = 0.1) {
  return Indent(poisson, depth, Box2cm(), integrator, Arrival::kTeleported, max_speed);
}

void ExpectRecovered(const Recovery& r, double depth = 0.004) {
  EXPECT_EQ(r.rejected, 0);
  EXPECT_GT(r.overlap_before, 0.99 * depth);
  // After 0.2 s no collision sphere overlaps the box by more than 0.2 mm (measured 0.07-0.09
  // mm: the press-in's remaining distance decays as exp(-t / 50 ms) once below 5 mm; the issue's
  // bound is a collision radius, 1.8 mm here).
  EXPECT_LT(r.overlap_after, 2e-4);
}

// Teleported 4 mm past first contact and held: recovered, and within 10 % of the force of the same
// indenter pressed slowly to the same pose (the tolerance), with either integrator. The
// box's node centres are inside it, so it is moved out of the block and pressed back in (World::
// BeginColliderEntries). 4 mm past first contact is 2.2 mm below the top node centres; at 5.6
// mm the lattice under the box's rim gives way even when pressed slowly, and the two paths'
// states then depend on when each reaches it (docs/physics.md §7.2).
void ExpectRecoveredToThePressedForce(double poisson, const ColliderShape& shape) {
  const double depth = 0.004;
  for (const Integrator integrator : {Integrator::kExplicit, Integrator::kImplicit}) {
    const Recovery teleported = Indent(poisson, depth, shape, integrator, Arrival::kTeleported);
    const Recovery pressed = Indent(poisson, depth, shape, integrator, Arrival::kPressedSlowly);
    ExpectRecovered(teleported, depth);
    // No burst: the block rings with at most 5 % of the elastic energy the press-in stores
    // (measured 0.05-1.2 %), and the total energy never exceeds its final value by more than 2 %
    // (the press-in stores it, the dampers take the ringing).
    EXPECT_LT(teleported.peak_kinetic, 0.05 * teleported.final_elastic);
    EXPECT_LT(teleported.max_total, 1.02 * teleported.final_total);
    EXPECT_EQ(pressed.rejected, 0);
    EXPECT_NEAR(teleported.force_after, pressed.force_after, 0.1 * pressed.force_after)
        << "nu " << poisson << ", " << IntegratorName(integrator);
  }
}

TEST(PenetrationRecovery, BoxTeleportedIntoABlockIsPushedOut) {
  for (const double poisson : {0.25, 0.45}) ExpectRecoveredToThePressedForce(poisson, Box2cm());
}

// A long implicit substep and an indenter that backs off by a hair: a block pressed 3.8 mm past
// first contact by the box (2 mm below its top node centres), which then stands 5 um higher. The
// top nodes' collision spheres no longer touch it, and before the kick held them speculatively
// (kSpeculativeReach) the released block sprang back through the box's face in one 1 ms substep
// (2.3 m/s; 36 node centres inside the box, force 18.5 N -> 6.3 N, recovering to 12.8 N in a state
// with 1.8 times the elastic energy). Both integrators must keep the contact: no sphere overlapping
// the box by more than 0.25 mm in any step (a seventh of its radius; measured 0.15 mm explicit,
// whose substeps let a pressed node sink a little before stopping it, and 0.00 implicit), and the
// force within 2 % of the pressed one.
TEST(PenetrationRecovery, ContactSurvivesTheIndenterBackingOffAHair) {
  for (const Integrator integrator : {Integrator::kExplicit, Integrator::kImplicit}) {
    Indentation s = MakeIndentation(0.25, Box2cm(), integrator, 0.1);
    World& world = *s.world;
    ASSERT_EQ(PressTo(&s, 0.0038), 0);
    const double pressed = world.wrenches(s.body)[s.collider].force.z();
    world.collider(s.collider).pose.translation().z() += 5e-6;
    double deepest = 0.0, force = 0.0;
    for (int k = 0; k < 50; ++k) {
      ASSERT_TRUE(world.Step(1e-3).accepted);
      deepest = std::max(deepest, Overlap(world, s.body, s.collider));
      force = world.wrenches(s.body)[s.collider].force.z();
    }
    std::printf(
        "  box pressed 3.8 mm, backed off 5 um (%s): force %.3f -> %.3f N, deepest "
        "overlap %.4f mm\n",
        IntegratorName(integrator), pressed, force, 1e3 * deepest);
    EXPECT_GT(pressed, 10.0);
    EXPECT_LT(deepest, 2.5e-4) << IntegratorName(integrator);
    EXPECT_NEAR(force, pressed, 0.02 * pressed) << IntegratorName(integrator);
  }
}

TEST(PenetrationRecovery, MeshColliderTeleportedIntoABlockIsPushedOut) {
  for (const double poisson : {0.25, 0.45}) {
    ExpectRecoveredToThePressedForce(poisson, MeshBox2cm());
  }
}

// A sphere (R = 8 mm) teleported 4 mm past first contact into the block's side face, its centre
// 3 mm above the block's middle (clear of the clamped base nodes): it is moved out along the face's
// normal (minus the sum of the inside nodes' star directions) and pressed back in. The first step
// starts from touching (almost no force), the block then pushes back along the normal, and after
// 0.2 s no collision sphere overlaps it by more than 0.2 mm.
TEST(PenetrationRecovery, SphereTeleportedIntoASideFaceIsPressedBackAlongItsNormal) {
  for (const Integrator integrator : {Integrator::kExplicit, Integrator::kImplicit}) {
    constexpr double kRadius = 0.008, kDepth = 0.004;
    Indentation s = MakeIndentation(0.45, ColliderShape::Sphere(kRadius), integrator, 0.1);
    World& world = *s.world;
    const BorderNodes& border = world.border(s.body);
    double side = -std::numeric_limits<double>::infinity();  // first contact along +x
    for (std::size_t k = 0; k < border.nodes.size(); ++k) {
      side = std::max(side, world.state(s.body).positions(0, border.nodes[k]) + border.radii[k]);
    }
    world.collider(s.collider).pose.translation() =
        Eigen::Vector3d(side + kRadius - kDepth, s.centre.y(), s.centre.z() + 0.003);
    ASSERT_TRUE(world.Step(1e-3).accepted);
    const Eigen::Vector3d first = world.wrenches(s.body)[s.collider].force;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (int k = 1; k < 200; ++k) {
      ASSERT_TRUE(world.Step(1e-3).accepted);
      if (k >= 180) force += world.wrenches(s.body)[s.collider].force / 20.0;
    }
    const double overlap = Overlap(world, s.body, s.collider);
    std::printf(
        "  sphere teleported 4 mm into the side face (%s): first step %.4f N, after 0.2 s "
        "(%.3f, %.3f, %.3f) N, overlap %.4f mm\n",
        IntegratorName(integrator), first.norm(), force.x(), force.y(), force.z(), 1e3 * overlap);
    EXPECT_LT(overlap, 2e-4) << IntegratorName(integrator);
    EXPECT_GT(force.x(), 1.0) << IntegratorName(integrator);  // the block pushes it out, along +x
    // Mostly along the normal; the contact, nearer the top's free edge than the base, also
    // pushes up (measured z / x 0.30 explicit, 0.18 implicit).
    EXPECT_GT(force.x(), 0.9 * force.norm()) << IntegratorName(integrator);
    EXPECT_LT(std::abs(force.y()), 0.01 * force.norm()) << IntegratorName(integrator);
    EXPECT_LT(first.norm(), 0.1 * force.norm()) << IntegratorName(integrator);
  }
}

// The deepest overlap (m) of two bodies' collision spheres: max over their border nodes' pairs
// of r_i + r_j - distance (<= 0: none).
double PairOverlap(const World& world, int a, int b) {
  double deepest = -std::numeric_limits<double>::infinity();
  const BorderNodes& p = world.border(a);
  const BorderNodes& q = world.border(b);
  for (std::size_t i = 0; i < p.nodes.size(); ++i) {
    for (std::size_t j = 0; j < q.nodes.size(); ++j) {
      const double distance =
          (world.state(a).positions.col(p.nodes[i]) - world.state(b).positions.col(q.nodes[j]))
              .norm();
      deepest = std::max(deepest, p.radii[i] + q.radii[j] - distance);
    }
  }
  return deepest;
}

// Issue "Contact", must-show 1 (MSM-MSM): a free 1.2 cm cube (a = 3 mm, 64 nodes) spawned with
// its collision spheres half a node spacing into the clamped block's (no gravity), held by
// nothing. The pairs are pushed apart like a collider's contacts: after 0.2 s no pair of
// collision spheres overlaps by more than 0.2 mm, no step is rejected, and the cube leaves no
// faster than the recovery's speed allows the stored springs to throw it.
TEST(PenetrationRecovery, TwoBodiesSpawnedOverlappingArePushedApart) {
  for (const Integrator integrator : {Integrator::kExplicit, Integrator::kImplicit}) {
    WorldOptions options;
    options.gravity.setZero();
    options.integrator = integrator;
    World world(options);
    BodyOptions body_options;
    body_options.damping_beta = 1e-4;
    const auto block = Block(0.45);
    const int below = world.AddBody("block", block, body_options);
    const double bottom = block->rest_positions().row(2).minCoeff();
    world.AddKinematicGroup(
        below, KinematicGroup{"base",
                              NodesInHalfSpace(*block, Eigen::Vector3d(0.0, 0.0, bottom + 0.0015),
                                               Eigen::Vector3d::UnitZ()),
                              {}});
    CubicLatticeOptions lattice_options;
    lattice_options.size = Eigen::Vector3d(0.012, 0.012, 0.012);
    lattice_options.lattice.spacing = 0.003;
    const auto cube = std::make_shared<const Model>(
        BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1100.0), lattice_options));
    const int above = world.AddBody("cube", cube, body_options);
    // Touching would put the cube's lowest layer 2r above the block's top layer; half a spacing
    // lower they overlap by 1.5 mm.
    const double r = world.border(below).radii[0];
    State state = world.state(above);
    const Eigen::Vector3d centre(0.012, 0.012, 0.0);
    state.positions.colwise() += centre;  // node above node
    state.positions.row(2).array() += block->rest_positions().row(2).maxCoeff() + 2.0 * r - 0.0015 -
                                      state.positions.row(2).minCoeff();
    world.SetState(above, state);
    const double before = PairOverlap(world, above, below);
    int rejected = 0;
    double peak_speed = 0.0;
    for (int k = 0; k < 200; ++k) {
      if (!world.Step(1e-3).accepted) ++rejected;
      peak_speed = std::max(peak_speed, world.state(above).velocities.rowwise().mean().norm());
    }
    const double after = PairOverlap(world, above, below);
    const double speed = world.state(above).velocities.rowwise().mean().norm();
    std::printf(
        "  cube spawned into the block (%s): pair overlap %.3f mm -> %.4f mm after 0.2 s, %d "
        "rejected steps, cube speed %.4f m/s (peak %.4f)\n",
        IntegratorName(integrator), 1e3 * before, 1e3 * after, rejected, speed, peak_speed);
    EXPECT_GT(before, 0.0014);
    EXPECT_EQ(rejected, 0);
    EXPECT_LT(after, 2e-4);
    EXPECT_TRUE(world.state(above).positions.allFinite());
    EXPECT_LT(peak_speed, 0.1);  // penetration_max_speed
  }
}

TEST(PenetrationRecovery, SeparationSpeedIsBounded) {
  // At 0.02 m/s at most, the overlap shrinks by no more than 1 mm in 50 ms (depth / recovery
  // time alone would take it from 5.9 to 2.2 mm).
  const Recovery r = RecoverFromBox(0.25, 0.004, Integrator::kExplicit, 0.02);
  EXPECT_GT(r.overlap_at_50ms, r.overlap_before - 0.02 * 0.05 - 1e-5);
  EXPECT_LT(r.overlap_at_50ms, r.overlap_before - 0.5 * 0.02 * 0.05);  // but it does shrink
}

TEST(PenetrationRecovery, OptionsAreChecked) {
  WorldOptions options;
  options.penetration_recovery_time = 0.0;
  EXPECT_THROW(World{options}, std::invalid_argument);
  options.penetration_recovery_time = 0.05;
  options.penetration_max_speed = -1.0;
  EXPECT_THROW(World{options}, std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
