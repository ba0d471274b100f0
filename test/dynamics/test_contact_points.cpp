// Per-contact output (issue 14): the contact points of a step, their average over an interval,
// and each collider's patch (normal, area, mean pressure), with both integrators.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/contact_point_average.h"
#include "msm_sim/dynamics/contact_wrench_average.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

constexpr double kStep = 1e-3;  // s
constexpr double kGravity = 9.81;
const Eigen::Vector3d kBlockSize(0.1, 0.08, 0.04);  // m; base 0.1 x 0.08 at a = 1 cm

// A soft block resting with its base on a plane whose normal `up` is tilted from z (gravity
// along -up), settled for 0.3 s.
struct RestingBlock {
  RestingBlock(Integrator integrator, const Eigen::Vector3d& up_direction)
      : up(up_direction.normalized()) {
    CubicLatticeOptions lattice_options;
    lattice_options.size = kBlockSize;
    lattice_options.lattice.spacing = 0.01;
    const Eigen::AngleAxisd tilt(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), up));
    if (tilt.angle() > 0.0) {
      lattice_options.lattice.rotation_axis = tilt.axis();
      lattice_options.lattice.rotation_angle = tilt.angle();
    }
    model = std::make_shared<const Model>(
        BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), lattice_options));
    WorldOptions options;
    options.gravity = -kGravity * up;
    options.integrator = integrator;
    options.record_contact_points = true;
    world = std::make_unique<World>(options);
    BodyOptions body_options;
    body_options.damping_beta = 2e-3;
    body_options.restitution = 0.0;
    body = world->AddBody("block", model, body_options);
    // The plane through the lowest collision sphere along -up.
    const BorderNodes& border = world->border(body);
    double lowest = INFINITY;
    for (std::size_t k = 0; k < border.nodes.size(); ++k) {
      lowest =
          std::min(lowest, up.dot(model->rest_positions().col(border.nodes[k])) - border.radii[k]);
    }
    Collider ground;
    ground.name = "ground";
    ground.pose = Eigen::Translation3d(lowest * up) * tilt;
    world->AddCollider(ground);
    for (int k = 0; k < 300; ++k) world->Step(kStep);
  }

  // Steps for `seconds`, averaging the collider's wrench and the contact points.
  void Average(double seconds, ContactWrenchAverage* wrench, ContactPointAverage* points) {
    const int steps = static_cast<int>(std::lround(seconds / kStep));
    for (int k = 0; k < steps; ++k) {
      ASSERT_TRUE(world->Step(kStep).accepted);
      wrench->Add(world->wrenches(body)[0], kStep);
      points->AddStep(kStep);
      points->Add(body, model->num_nodes(), world->contact_points(body));
    }
  }

  Eigen::Vector3d up;
  std::shared_ptr<const Model> model;
  std::unique_ptr<World> world;
  int body = 0;
};

class ContactPatch : public ::testing::TestWithParam<Integrator> {};

// A block resting on the ground: its patch's area is its base, its pressure its weight over it.
TEST_P(ContactPatch, RestingBlockReportsItsBaseAndWeight) {
  RestingBlock block(GetParam(), Eigen::Vector3d::UnitZ());
  ContactWrenchAverage wrench;
  ContactPointAverage points;
  block.Average(0.2, &wrench, &points);
  const ContactWrench mean = wrench.Average();
  const double base = kBlockSize.x() * kBlockSize.y();
  const double weight = block.model->masses().sum() * kGravity;
  std::printf(
      "[ %s ] area %.5g m^2 (base %.5g), pressure %.5g Pa (m g / area %.5g), "
      "normal force %.5g N (m g %.5g), %zu contact points\n",
      IntegratorName(GetParam()), mean.area, base, mean.mean_pressure, weight / mean.area,
      mean.normal_force, weight, points.size());
  EXPECT_NEAR(mean.area, base, 0.1 * base);
  EXPECT_NEAR(mean.mean_pressure, weight / mean.area, 0.1 * weight / mean.area);
  EXPECT_NEAR(mean.mean_pressure, weight / base, 0.1 * weight / base);
  EXPECT_NEAR(mean.mean_pressure, mean.normal_force / mean.area, 1e-9 * mean.mean_pressure);
  EXPECT_GT(mean.normal.dot(Eigen::Vector3d::UnitZ()), std::cos(M_PI / 180.0));
}

// The normals of a flat contact, on a tilted plane: each point's and the patch's are the
// plane's within 1 degree.
TEST_P(ContactPatch, NormalsOfAFlatContactAreThePlanes) {
  const Eigen::Vector3d up = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  RestingBlock block(GetParam(), up);
  ContactWrenchAverage wrench;
  ContactPointAverage points;
  block.Average(0.1, &wrench, &points);
  const double cos_limit = std::cos(M_PI / 180.0);
  ASSERT_GT(points.size(), 0u);
  double worst = 1.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    worst = std::min(worst, points.Average(k).normal.dot(up));
  }
  const double patch = wrench.Average().normal.dot(up);
  std::printf("[ %s ] worst point normal %.3g deg, patch normal %.3g deg off the plane's\n",
              IntegratorName(GetParam()), std::acos(std::min(worst, 1.0)) * 180.0 / M_PI,
              std::acos(std::min(patch, 1.0)) * 180.0 / M_PI);
  EXPECT_GT(worst, cos_limit);
  EXPECT_GT(patch, cos_limit);
  for (const ContactPoint& contact : block.world->contact_points(block.body)) {
    EXPECT_GT(contact.normal.dot(up), cos_limit);
  }
}

// The contact points of an interval sum to the collider's wrench: a block on the ground pushed
// sideways (friction, tangential impulses) and pressed by a sphere moving across it.
TEST_P(ContactPatch, PointForcesSumToTheWrench) {
  RestingBlock block(GetParam(), Eigen::Vector3d::UnitZ());
  Collider sphere;
  sphere.name = "sphere";
  sphere.shape = ColliderShape::Sphere(0.02);
  const double top = block.model->rest_positions().row(2).maxCoeff();
  sphere.pose.translation() = Eigen::Vector3d(0.03, 0.04, top + 0.02 + 0.003);
  sphere.linear_velocity = Eigen::Vector3d(0.1, 0.0, -0.02);
  const int sphere_index = block.world->AddCollider(sphere);
  block.world->ApplyForce(block.body, Eigen::Vector3d(0.05, 0.04, 0.02),
                          Eigen::Vector3d(0.5, 0.2, 0.0), 0.05, 0.1);
  std::vector<ContactWrenchAverage> wrenches(2);
  ContactPointAverage points;
  for (int k = 0; k < 100; ++k) {
    ASSERT_TRUE(block.world->Step(kStep).accepted);
    for (int c = 0; c < 2; ++c) wrenches[c].Add(block.world->wrenches(block.body)[c], kStep);
    points.AddStep(kStep);
    points.Add(block.body, block.model->num_nodes(), block.world->contact_points(block.body));
  }
  for (int c = 0; c < 2; ++c) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), tangential = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < points.size(); ++k) {
      const ContactPointAverage::Point point = points.Average(k);
      if (point.collider != c) continue;
      sum += point.force;
      tangential += point.force - point.force.dot(point.normal) * point.normal;
    }
    const Eigen::Vector3d force = wrenches[c].Average().force;
    const double relative = (sum - force).norm() / force.norm();
    std::printf(
        "[ %s ] collider %d: wrench %.6g N, points' sum off by %.3g relative, "
        "friction %.3g N\n",
        IntegratorName(GetParam()), c, force.norm(), relative, tangential.norm());
    EXPECT_GT(force.norm(), 0.0);
    EXPECT_LT(relative, 1e-9);
    EXPECT_GT(tangential.norm(), 1e-3 * force.norm()) << "no friction to check";
  }
  EXPECT_EQ(sphere_index, 1);
}

INSTANTIATE_TEST_SUITE_P(BothIntegrators, ContactPatch,
                         ::testing::Values(Integrator::kExplicit, Integrator::kImplicit),
                         [](const ::testing::TestParamInfo<Integrator>& info) {
                           return std::string(IntegratorName(info.param));
                         });

// Recording is off by default; the patch is reported all the same.
TEST(ContactPoints, AreRecordedOnlyWhenAsked) {
  CubicLatticeOptions lattice_options;
  lattice_options.size = Eigen::Vector3d(0.04, 0.04, 0.02);
  lattice_options.lattice.spacing = 0.01;
  const auto model = std::make_shared<const Model>(
      BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), lattice_options));
  World world;
  const int body = world.AddBody("block", model);
  world.AddCollider(GroundTouching(model->rest_positions(), world.border(body)));
  for (int k = 0; k < 20; ++k) world.Step(kStep);
  EXPECT_TRUE(world.contact_points(body).empty());
  EXPECT_GT(world.wrenches(body)[0].microcollisions, 0);
  EXPECT_GT(world.wrenches(body)[0].area, 0.0);
}

// A node-centred lattice's border nodes each stand for one lattice face; an element-corner
// lattice's for a[n edge's or corner's] fraction of it: a flat side sums to its area.
TEST(BorderNodes, SurfaceSharesOfAFlatSideSumToItsArea) {
  for (const CubicConstruction construction :
       {CubicConstruction::kNodeCentred, CubicConstruction::kElementCorner}) {
    CubicLatticeOptions lattice_options;
    lattice_options.size = Eigen::Vector3d(0.1, 0.08, 0.04);
    lattice_options.lattice.spacing = 0.01;
    lattice_options.construction = construction;
    const Model model =
        BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.3, 1000.0), lattice_options);
    const BorderNodes border = FindBorderNodes(model);
    ASSERT_EQ(border.surface_shares.size(), border.nodes.size());
    const double bottom = model.rest_positions().row(2).minCoeff();
    double area = 0.0;
    for (std::size_t k = 0; k < border.nodes.size(); ++k) {
      if (model.rest_positions()(2, border.nodes[k]) < bottom + 1e-9) {
        area += border.surface_shares[k];
      }
    }
    EXPECT_NEAR(area, 0.1 * 0.08, 1e-9) << static_cast<int>(construction);
  }
}

}  // namespace
}  // namespace msm_sim::core
