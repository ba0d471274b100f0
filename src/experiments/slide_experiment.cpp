#include "msm_sim/experiments/slide_experiment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {
namespace {

double CentreOfMass(const Eigen::Matrix3Xd& values, const Eigen::VectorXd& masses, int axis) {
  return values.row(axis).dot(masses.transpose()) / masses.sum();
}

}  // namespace

SlideExperimentResult RunSlideExperiment(std::shared_ptr<const Model> model,
                                         const SlideExperimentOptions& options) {
  if (!(options.initial_speed > 0.0) || !(options.friction > 0.0) || !(options.gravity > 0.0) ||
      !(options.step > 0.0) || !(options.stop_fraction > 0.0) ||
      !std::isfinite(options.initial_speed + options.friction + options.gravity + options.step)) {
    throw std::invalid_argument("slide test: v0, mu, g, step and stop fraction must be > 0");
  }
  WorldOptions world_options;
  world_options.gravity = Eigen::Vector3d(0.0, 0.0, -options.gravity);
  world_options.integrator = options.integrator;
  world_options.implicit_max_substep = options.step;
  World world(world_options);
  BodyOptions body_options;
  body_options.friction = options.friction;
  const int body = world.AddBody("body", model, body_options);

  const int ground_index = world.AddCollider(
      GroundTouching(model->rest_positions(), world.border(body), options.friction));
  world.SetPairFriction(body, ground_index, options.friction);

  State state = world.state(body);
  state.velocities.row(0).setConstant(options.initial_speed);
  world.SetState(body, state);

  SlideExperimentResult result;
  const double v0 = options.initial_speed;
  result.theory_distance = v0 * v0 / (2.0 * options.friction * options.gravity);
  const double stop_time = v0 / (options.friction * options.gravity);
  const double max_time = options.max_time > 0.0 ? options.max_time : 3.0 * stop_time + 1.0;
  const Eigen::VectorXd& m = model->masses();
  const double start = CentreOfMass(world.state(body).positions, m, 0);
  while (world.time() < max_time) {
    const StepReport report = world.Step(options.step);
    if (!report.accepted) throw std::runtime_error("slide test: " + report.reason);
    ++result.steps;
    // Past half the theoretical stopping time, so that the start is never mistaken for a stop.
    const double forward = CentreOfMass(world.state(body).velocities, m, 0);
    if (world.time() > 0.5 * stop_time && forward < options.stop_fraction * v0) {
      result.stopped = true;
      break;
    }
  }
  result.distance = CentreOfMass(world.state(body).positions, m, 0) - start;
  result.seconds_simulated = world.time();
  return result;
}

}  // namespace msm_sim::core
