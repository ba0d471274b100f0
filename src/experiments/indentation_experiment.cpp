#include "msm_sim/experiments/indentation_experiment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "experiments/indenter.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/model/node_selection.h"

namespace msm_sim::core {
namespace {

void CheckOptions(const IndentationExperimentOptions& options) {
  const double sum = options.sphere_radius + options.depth + options.speed + options.step +
                     options.damping_beta + options.start_gap + options.start_depth + options.hold +
                     options.friction;
  if (!(options.sphere_radius > 0.0) || !(options.depth > 0.0) || !(options.speed > 0.0) ||
      !(options.step > 0.0) || !(options.damping_beta >= 0.0) || !(options.start_gap >= 0.0) ||
      !(options.start_depth >= 0.0) || !(options.hold > 0.0) || !(options.friction >= 0.0) ||
      !std::isfinite(sum)) {
    throw std::invalid_argument(
        "indentation: sphere radius, depth, speed, step and hold must be finite and > 0, "
        "damping, friction, start gap and start depth finite and >= 0");
  }
  if (!(options.time_step_safety > 0.0 && options.time_step_safety <= 1.0)) {
    throw std::invalid_argument("indentation: the time step safety must be in (0, 1]");
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

// The sphere centre's height when its lowest point reaches the body's surface under it: the
// plane through the highest collision-sphere top among the border nodes within one
// characteristic length of its axis. A measured curve counts depth from the flat surface, so
// the lattice's does too. The first collision sphere the sphere touches is no such reference:
// where the axis falls between nodes, the sphere touches them about s^2 / (2 (R + r)) below
// their tops (s their horizontal distance from the axis), a depth offset that reads as a force
// above Hertz's at shallow depths and depends on where the probe lands on the lattice
// (docs/design/indentation-fit.md). Falls back to that first touch if no node is that near.
double SurfaceContactHeight(const Model& model, const BorderNodes& border,
                            const Eigen::Vector2d& axis, double radius) {
  const Eigen::Matrix3Xd& x = model.rest_positions();
  const double near = model.characteristic_length();
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    const Eigen::Vector3d p = x.col(border.nodes[k]);
    if ((p.head<2>() - axis).squaredNorm() > near * near) continue;
    top = std::max(top, p.z() + border.radii[k]);
  }
  if (!std::isfinite(top)) return SphereTouchdownHeight(x, border, axis, radius);
  return top + radius;
}

// Presses from first contact to the full depth, one profile row per run of steps covering
// about D / samples of depth: the mean depth and force of its steps. Depth is measured from
// `surface_z`, SurfaceContactHeight, not from the end of the step that first records a force:
// that step ends up to one step's travel later, which reads as a force above Hertz's, the more
// the shallower (docs/lab.md, "indent").
std::vector<IndentationSample> Press(World* world, int body, int sphere, double surface_z,
                                     const IndentationExperimentOptions& options) {
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
    depth = surface_z - world->collider(sphere).pose.translation().z();
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

// Holds the sphere start_depth past first contact for the hold time (penetration recovery).
void Hold(World* world, int body, int sphere, const IndentationExperimentOptions& options,
          IndentationExperimentResult* result) {
  const auto overlap = [&] {
    return SphereOverlap(world->border(body), world->state(body).positions,
                         world->collider(sphere).pose.translation(), options.sphere_radius);
  };
  result->overlap_before = overlap();
  const int steps = std::max(1, static_cast<int>(std::lround(options.hold / options.step)));
  const int averaged = std::max(1, steps / 10);
  for (int k = 0; k < steps; ++k) {
    StepOrThrow(world, options.step);
    result->peak_kinetic = std::max(result->peak_kinetic, world->ComputeEnergies(body).kinetic);
    if (k >= steps - averaged) result->force_after += world->wrenches(body)[sphere].force.z();
  }
  result->force_after /= averaged;
  result->overlap_after = overlap();
  const Energies energies = world->ComputeEnergies(body);
  result->final_kinetic = energies.kinetic;
  result->final_elastic = energies.elastic;
  result->steps = steps;
  result->seconds_simulated = world->time();
}

}  // namespace

double SphereOverlap(const BorderNodes& border, const Eigen::Matrix3Xd& positions,
                     const Eigen::Vector3d& centre, double radius) {
  double deepest = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    const double distance = (positions.col(border.nodes[k]) - centre).norm();
    deepest = std::max(deepest, radius + border.radii[k] - distance);
  }
  return deepest;
}

double ProfileForceAt(const std::vector<IndentationSample>& profile, double depth) {
  if (profile.empty()) return 0.0;
  if (profile.size() == 1) return profile.front().force;
  std::size_t k = 1;
  while (k + 1 < profile.size() && profile[k].depth < depth) ++k;
  const IndentationSample& a = profile[k - 1];
  const IndentationSample& b = profile[k];
  const double t = b.depth > a.depth ? (depth - a.depth) / (b.depth - a.depth) : 1.0;
  return a.force + t * (b.force - a.force);
}

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
  world_options.spring_precision = options.spring_precision;
  world_options.implicit_max_substep = options.step;
  world_options.time_step_safety = options.time_step_safety;
  World world(world_options);
  BodyOptions body_options;
  body_options.damping_beta = options.damping_beta;
  const int body = world.AddBody("block", model, body_options);
  world.AddKinematicGroup(body, KinematicGroup{"base", BaseNodes(*model), {}});
  const bool held = options.start_depth > 0.0;
  const int sphere = world.AddCollider(
      SphereIndenter(*model, world.border(body), options.sphere_radius,
                     held ? -options.start_depth : options.start_gap, held ? 0.0 : options.speed));
  world.SetPairFriction(body, sphere, options.friction);
  IndentationExperimentResult result;
  if (held) {
    Hold(&world, body, sphere, options, &result);
    return result;
  }
  const double surface_z = SurfaceContactHeight(*model, world.border(body),
                                                world.collider(sphere).pose.translation().head<2>(),
                                                options.sphere_radius);
  result.touch_depth =
      surface_z - (world.collider(sphere).pose.translation().z() - options.start_gap);
  StepToFirstContact(&world, body, sphere, options);
  result.contact_time = world.time();
  result.profile = Press(&world, body, sphere, surface_z, options);
  result.seconds_simulated = world.time();
  result.steps = static_cast<int>(std::lround(world.time() / options.step));
  return result;
}

}  // namespace msm_sim::core
