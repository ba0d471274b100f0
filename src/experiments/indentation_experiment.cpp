#include "msm_sim/experiments/indentation_experiment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "experiments/indenter.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

void CheckOptions(const IndentationExperimentOptions& options) {
  const double sum = options.sphere_radius + options.depth + options.speed + options.step +
                     options.damping_beta + options.start_gap;
  if (!(options.sphere_radius > 0.0) || !(options.depth > 0.0) || !(options.speed > 0.0) ||
      !(options.step > 0.0) || !(options.damping_beta >= 0.0) || !(options.start_gap >= 0.0) ||
      !std::isfinite(sum)) {
    throw std::invalid_argument(
        "indentation: sphere radius, depth, speed and step must be finite and > 0, damping and "
        "start gap finite and >= 0");
  }
  if (options.samples < 1) throw std::invalid_argument("indentation: samples must be >= 1");
}

// The clamped base: every node within half a characteristic length of the lowest one.
std::vector<NodeIndex> BaseNodes(const Model& model) {
  const double bottom = model.rest_positions().row(2).minCoeff();
  const Eigen::Vector3d plane(0.0, 0.0, bottom + 0.5 * model.characteristic_length());
  return NodesInHalfSpace(model, plane, Eigen::Vector3d::UnitZ());
}

void StepOrThrow(World* world, double dt) {
  const StepReport report = world->Step(dt);
  if (!report.accepted) throw std::runtime_error("indentation: " + report.reason);
}

// Steps until the body exerts a force on the sphere (first contact).
void StepToFirstContact(World* world, int body, int sphere,
                        const IndentationExperimentOptions& options) {
  const double start = world->collider(sphere).pose.translation().z();
  const double give_up = options.start_gap + 2.0 * world->model(body).characteristic_length();
  while (world->wrenches(body).empty() ||
         world->wrenches(body)[sphere].force.squaredNorm() == 0.0) {
    if (start - world->collider(sphere).pose.translation().z() > give_up) {
      throw std::runtime_error("indentation: the sphere did not touch the body");
    }
    StepOrThrow(world, options.step);
  }
}

// Presses from first contact to the full depth, one profile row per run of steps covering
// about D / samples of depth: the mean depth and force of its steps.
std::vector<IndentationSample> Press(World* world, int body, int sphere,
                                     const IndentationExperimentOptions& options) {
  const double contact_z = world->collider(sphere).pose.translation().z();
  const int steps_per_row =
      std::max(1, static_cast<int>(std::lround(options.depth / options.samples /
                                               (options.speed * options.step))));
  const Material& material = world->model(body).material();
  std::vector<IndentationSample> profile;
  IndentationSample row;
  int in_row = 0;
  double depth = 0.0;
  while (depth < options.depth * (1.0 - 1e-9)) {
    StepOrThrow(world, options.step);
    depth = contact_z - world->collider(sphere).pose.translation().z();
    row.depth += depth;
    row.force += world->wrenches(body)[sphere].force.z();
    if (++in_row < steps_per_row && depth < options.depth * (1.0 - 1e-9)) continue;
    row.depth /= in_row;
    row.force /= in_row;
    row.hertz_force = HertzForce(material.youngs_modulus(), material.poisson_ratio(),
                                 options.sphere_radius, row.depth);
    profile.push_back(row);
    row = IndentationSample{};
    in_row = 0;
  }
  return profile;
}

}  // namespace

double HertzForce(double youngs, double poisson, double radius, double depth) {
  if (!(depth > 0.0)) return 0.0;
  return 4.0 / 3.0 * youngs / (1.0 - poisson * poisson) * std::sqrt(radius) * std::pow(depth, 1.5);
}

IndentationExperimentResult RunIndentationExperiment(std::shared_ptr<const Model> model,
                                                     const IndentationExperimentOptions& options) {
  CheckOptions(options);
  const Eigen::VectorXd heights = model->rest_positions().row(2).transpose();
  if (!(options.depth < heights.maxCoeff() - heights.minCoeff())) {
    throw std::invalid_argument("indentation: the depth must be less than the body's height");
  }
  WorldOptions world_options;
  world_options.gravity.setZero();
  world_options.integrator = options.integrator;
  world_options.implicit_max_substep = options.step;
  World world(world_options);
  BodyOptions body_options;
  body_options.damping_beta = options.damping_beta;
  body_options.dispersion = options.dispersion;
  const int body = world.AddBody("block", model, body_options);
  world.AddKinematicGroup(body, KinematicGroup{"base", BaseNodes(*model), {}});
  const int sphere = world.AddCollider(SphereIndenter(
      *model, world.border(body), options.sphere_radius, options.start_gap, options.speed));

  StepToFirstContact(&world, body, sphere, options);
  IndentationExperimentResult result;
  result.contact_time = world.time();
  result.profile = Press(&world, body, sphere, options);
  result.seconds_simulated = world.time();
  result.steps = static_cast<int>(std::lround(world.time() / options.step));
  return result;
}

}  // namespace msm_sim::core
