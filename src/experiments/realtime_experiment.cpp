#include "msm_sim/experiments/realtime_experiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "experiments/indenter.h"
#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {
namespace {

void CheckOptions(const RealtimeExperimentOptions& options) {
  const double sum = options.sphere_radius + options.speed + options.seconds + options.step +
                     options.damping_beta + options.gravity + options.friction +
                     options.time_step_safety;
  if (!(options.sphere_radius > 0.0) || !(options.speed > 0.0) || !(options.seconds > 0.0) ||
      !(options.step > 0.0) || !(options.damping_beta >= 0.0) || !(options.gravity >= 0.0) ||
      !(options.friction >= 0.0) || !(options.time_step_safety > 0.0) ||
      !(options.time_step_safety <= 1.0) || !std::isfinite(sum)) {
    throw std::invalid_argument(
        "real-time run: sphere radius, speed, seconds and step must be finite and > 0, damping, "
        "gravity and friction finite and >= 0, the time step safety in (0, 1]");
  }
}

}  // namespace

RealtimeExperimentResult RunRealtimeExperiment(std::shared_ptr<const Model> model,
                                               const RealtimeExperimentOptions& options) {
  CheckOptions(options);
  WorldOptions world_options;
  world_options.gravity = Eigen::Vector3d(0.0, 0.0, -options.gravity);
  world_options.integrator = options.integrator;
  world_options.implicit_max_substep = options.step;
  world_options.threads = options.threads;
  world_options.spring_precision = options.spring_precision;
  world_options.time_step_safety = options.time_step_safety;
  World world(world_options);
  BodyOptions body_options;
  body_options.damping_beta = options.damping_beta;
  body_options.friction = options.friction;
  const int body = world.AddBody("block", model, body_options);
  world.AddCollider(GroundTouching(model->rest_positions(), world.border(body), options.friction));
  Collider sphere =
      SphereIndenter(*model, world.border(body), options.sphere_radius, 0.0, options.speed);
  sphere.friction = options.friction;
  const int finger = world.AddCollider(sphere);

  RealtimeExperimentResult result;
  result.nodes = model->num_nodes();
  result.springs = model->num_springs();
  result.integrator = IntegratorName(options.integrator);
  result.step = options.step;
  long solver_iterations = 0;
  const int steps = std::max(1, static_cast<int>(std::lround(options.seconds / options.step)));
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) {
    const StepReport report = world.Step(options.step);
    if (!report.accepted) throw std::runtime_error("real-time run: " + report.reason);
    result.substeps = std::max(result.substeps, report.substeps);
    result.substep = report.substep;
    solver_iterations += report.solver_iterations;
    result.final_force = world.wrenches(body)[finger].force.norm();
    result.peak_force = std::max(result.peak_force, result.final_force);
  }
  result.substep_refinement = world.substep_refinement();
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.steps = steps;
  result.solver_iterations_per_step = static_cast<double>(solver_iterations) / steps;
  result.seconds_simulated = world.time();
  result.wall_per_simulated_second = result.wall_seconds / result.seconds_simulated;
  result.real_time_factor = 1.0 / result.wall_per_simulated_second;
  return result;
}

}  // namespace msm_sim::core
