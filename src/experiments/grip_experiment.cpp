#include "msm_sim/experiments/grip_experiment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "msm_sim/dynamics/border_nodes.h"
#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {
namespace {

void CheckOptions(const GripExperimentOptions& o) {
  const double sum = o.squeeze + o.hold_ratio + o.gravity + o.damping_beta + o.close_time +
                     o.settle_time + o.measure_time + o.lift_speed + o.lift_ramp + o.lift_time +
                     o.step + o.held_slip;
  if (!std::isfinite(sum) || !(o.squeeze > 0.0) || !(o.hold_ratio > 0.0) || !(o.gravity > 0.0) ||
      !(o.damping_beta >= 0.0) || !(o.close_time > 0.0) || !(o.settle_time > 0.0) ||
      !(o.measure_time > 0.0) || o.measure_time > o.settle_time || !(o.lift_speed >= 0.0) ||
      !(o.lift_ramp > 0.0) || !(o.lift_time > 0.0) || !(o.step > 0.0) || !(o.held_slip > 0.0)) {
    throw std::invalid_argument(
        "grip: squeeze, hold ratio, gravity, times, step and held slip must be finite and > 0, "
        "damping and lift speed finite and >= 0, measure time at most the settle time");
  }
}

// The box the body's collision spheres fill at `positions`.
struct SphereBounds {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = -Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
};

SphereBounds BoundsOfSpheres(const Eigen::Matrix3Xd& positions, const BorderNodes& border) {
  if (border.nodes.empty()) throw std::invalid_argument("grip: the model has no border nodes");
  SphereBounds bounds;
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    const Eigen::Vector3d x = positions.col(border.nodes[k]);
    const Eigen::Vector3d radius = Eigen::Vector3d::Constant(border.radii[k]);
    bounds.min = bounds.min.cwiseMin(x - radius);
    bounds.max = bounds.max.cwiseMax(x + radius);
  }
  return bounds;
}

// A jaw: a box as thick as the body is wide along x, overhanging it by that much along y and z,
// its face at x = face (facing +x if side = -1, i.e. the left jaw; -x if side = +1).
Collider Jaw(const std::string& name, const SphereBounds& bounds, double face, double side) {
  const Eigen::Vector3d extent = bounds.max - bounds.min;
  const double thickness = extent.x();
  Collider jaw;
  jaw.name = name;
  jaw.shape = ColliderShape::Box(
      Eigen::Vector3d(thickness, extent.y() + 2.0 * thickness, extent.z() + 2.0 * thickness));
  jaw.pose.translation() = 0.5 * (bounds.min + bounds.max);
  jaw.pose.translation().x() = face + side * 0.5 * thickness;
  return jaw;
}

double CentreOfMassZ(const World& world, int body) {
  const Eigen::VectorXd& m = world.model(body).masses();
  return world.state(body).positions.row(2).dot(m.transpose()) / m.sum();
}

// The scene: the body on a frictionless ground between two frictionless jaws that just touch it.
struct Scene {
  int body = 0;
  int ground = 0;
  int left = 0;
  int right = 0;
  double jaw_height = 0.0;  // m
};

Scene BuildScene(World* world, std::shared_ptr<const Model> model,
                 const GripExperimentOptions& options) {
  BodyOptions body_options;
  body_options.damping_beta = options.damping_beta;
  Scene scene;
  scene.body = world->AddBody("block", model, body_options);
  const Eigen::Matrix3Xd& x = model->rest_positions();
  const BorderNodes& border = world->border(scene.body);
  const SphereBounds bounds = BoundsOfSpheres(x, border);
  scene.ground = world->AddCollider(GroundTouching(x, border, 0.0));
  scene.left = world->AddCollider(Jaw("left_jaw", bounds, bounds.min.x(), -1.0));
  scene.right = world->AddCollider(Jaw("right_jaw", bounds, bounds.max.x(), +1.0));
  for (const int collider : {scene.ground, scene.left, scene.right}) {
    world->SetPairFriction(scene.body, collider, 0.0);
  }
  const Eigen::Vector3d extent = bounds.max - bounds.min;
  scene.jaw_height = extent.z() + 2.0 * extent.x();
  return scene;
}

double MeanJawNormalForce(const World& world, const Scene& scene) {
  const auto& wrenches = world.wrenches(scene.body);
  return 0.5 * (wrenches[scene.left].normal_force + wrenches[scene.right].normal_force);
}

void StepOrThrow(World* world, double step, int* steps) {
  const StepReport report = world->Step(step);
  if (!report.accepted) throw std::runtime_error("grip: " + report.reason);
  ++*steps;
}

int StepsIn(double seconds, double step) {
  return std::max(1, static_cast<int>(std::lround(seconds / step)));
}

// Closes the jaws by the squeeze and lets the body settle; returns F_n over the last
// measure_time.
double SqueezeAndMeasure(World* world, const Scene& scene, const GripExperimentOptions& options,
                         int* steps) {
  const int closing = StepsIn(options.close_time, options.step);
  const double speed = options.squeeze / (closing * options.step);
  world->collider(scene.left).linear_velocity = Eigen::Vector3d(speed, 0.0, 0.0);
  world->collider(scene.right).linear_velocity = Eigen::Vector3d(-speed, 0.0, 0.0);
  for (int k = 0; k < closing; ++k) StepOrThrow(world, options.step, steps);
  world->collider(scene.left).linear_velocity.setZero();
  world->collider(scene.right).linear_velocity.setZero();
  const int settling = StepsIn(options.settle_time, options.step);
  const int measuring = std::min(settling, StepsIn(options.measure_time, options.step));
  double sum = 0.0;
  for (int k = 0; k < settling; ++k) {
    StepOrThrow(world, options.step, steps);
    if (k >= settling - measuring) sum += MeanJawNormalForce(*world, scene);
  }
  return sum / measuring;
}

// Removes the ground and lifts the jaws; fills the lift's part of *result.
void Lift(World* world, const Scene& scene, const GripExperimentOptions& options,
          GripExperimentResult* result) {
  world->collider(scene.ground).enabled = false;
  const double jaw_start = world->collider(scene.left).pose.translation().z();
  const double body_start = CentreOfMassZ(*world, scene.body);
  const int lifting = StepsIn(options.lift_time, options.step);
  double force_sum = 0.0;
  result->lift_normal_force_min = std::numeric_limits<double>::infinity();
  int k = 0;
  while (k < lifting && !result->left_jaws) {
    // The speed at the middle of the step, so that the jaws follow the ramp's integral.
    const double ramp = std::min(1.0, (k + 0.5) * options.step / options.lift_ramp);
    for (const int jaw : {scene.left, scene.right}) {
      world->collider(jaw).linear_velocity = Eigen::Vector3d(0.0, 0.0, ramp * options.lift_speed);
    }
    StepOrThrow(world, options.step, &result->steps);
    ++k;
    const double force = MeanJawNormalForce(*world, scene);
    force_sum += force;
    result->lift_normal_force_min = std::min(result->lift_normal_force_min, force);
    const double jaw_rise = world->collider(scene.left).pose.translation().z() - jaw_start;
    result->slip = jaw_rise - (CentreOfMassZ(*world, scene.body) - body_start);
    result->max_slip = std::max(result->max_slip, result->slip);
    result->left_jaws = result->slip > scene.jaw_height;
  }
  result->seconds_lifted = k * options.step;
  result->lift_normal_force_mean = force_sum / k;
  result->held = result->max_slip <= options.held_slip;
}

}  // namespace

GripExperimentResult RunGripExperiment(std::shared_ptr<const Model> model,
                                       const GripExperimentOptions& options) {
  CheckOptions(options);
  WorldOptions world_options;
  world_options.gravity = Eigen::Vector3d(0.0, 0.0, -options.gravity);
  world_options.integrator = options.integrator;
  world_options.implicit_max_substep = options.step;
  World world(world_options);
  const Scene scene = BuildScene(&world, model, options);

  GripExperimentResult result;
  result.mass = model->masses().sum();
  result.weight = result.mass * options.gravity;
  result.normal_force = SqueezeAndMeasure(&world, scene, options, &result.steps);
  if (!(result.normal_force > 0.0)) {
    throw std::runtime_error("grip: the jaws measured no normal force; squeeze deeper");
  }
  // docs/physics.md §7: Coulomb friction on both jaws holds up to 2 mu F_n.
  result.friction = options.hold_ratio * result.weight / (2.0 * result.normal_force);
  world.SetPairFriction(scene.body, scene.left, result.friction);
  world.SetPairFriction(scene.body, scene.right, result.friction);
  Lift(&world, scene, options, &result);
  return result;
}

}  // namespace msm_sim::core
