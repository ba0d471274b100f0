// Simulation: construction, inputs and stepping. The outputs are in simulation_outputs.cpp, the
// contact report in simulation_contacts.cpp.
#include "simulation.h"

#include <cmath>
#include <sstream>

#include <tf2/exceptions.h>

#include "msm_sim/mechanics/stable_time_step.h"

#include "conversions.h"
#include "object_builder.h"

namespace msm_sim::ros_interface {
namespace {

// Applied forces hold this long after their last message on a wrench topic.
constexpr double kWrenchHoldSeconds = 0.5;

core::WorldOptions WorldOptionsOf(const WorldConfig& config) {
  core::WorldOptions options;
  options.gravity = config.gravity;
  options.time_step_safety = config.time_step_safety;
  options.max_substep_refinement = config.max_substep_refinement;
  options.integrator = config.integrator;
  options.threads = config.threads;
  options.spring_precision = config.spring_precision;
  options.penetration_recovery_time = config.penetration_recovery_time;
  options.penetration_max_speed = config.penetration_max_speed;
  options.record_contact_points = true;  // ~contact_points, ~links/<link>/pressure
  options.max_pending_pushes = config.max_pending_pushes;
  options.max_pending_force = config.max_pending_force;
  return options;
}

// More explicit substeps per step than this would stall the node (a denormal density asked for
// 10^150); a material needing them is refused.
constexpr double kMaxSubstepsPerStep = 1000.0;

// Empty if a step of the explicit integrator at `stable_step` (s) takes at most
// kMaxSubstepsPerStep substeps (always with the implicit one); else why not.
std::string SubstepProblem(const WorldConfig& world, double stable_step) {
  if (world.integrator != core::Integrator::kExplicit) return {};
  // A lattice always has springs: an infinite (or NaN) stable step means the stiffness-to-mass
  // ratio overflowed.
  const double substeps = world.time_step / stable_step;
  if (std::isfinite(stable_step) && substeps <= kMaxSubstepsPerStep) return {};
  std::ostringstream problem;
  if (!std::isfinite(stable_step)) {
    return "the material's stiffness-to-mass ratio overflows (no finite stable step; too stiff "
           "or too light)";
  }
  problem << "the material gives a stable step of " << stable_step << " s, " << substeps
          << " substeps per ~world/time_step, more than " << kMaxSubstepsPerStep
          << " (too stiff or too light for this lattice)";
  return problem.str();
}

// Empty if `point` (m, world) lies within ~world/max_distance of the origin; else why not. A
// finite but huge pose (a link's tf at 10^30 m) once reversed a contact force silently.
std::string DistanceProblem(const Eigen::Vector3d& point, double max_distance) {
  if (point.norm() <= max_distance) return {};
  std::ostringstream problem;
  problem << "the point lies " << point.norm() << " m from the world origin, beyond "
          << "~world/max_distance = " << max_distance << " m";
  return problem.str();
}

}  // namespace

Simulation::Simulation(const SimulationConfig& config, const std::string& robot_description)
    : config_(config), world_(WorldOptionsOf(config_.world)) {
  if (config_.world.ground) AddGround();
  for (std::size_t i = 0; i < config_.objects.size(); ++i) AddObject(i);
  robot_ = std::make_unique<RobotColliders>(config_.robot, robot_description, config_.world.frame,
                                            config_.world.max_distance, &world_);
  contact_averages_.resize(objects_.size());

  for (const WrenchInputConfig& input_config : config_.wrench_inputs) {
    WrenchInput input;
    input.config = input_config;
    input.object = FindObject(input_config.object);
    wrench_inputs_.push_back(input);
  }
}

void Simulation::AddGround() {
  core::Collider ground;
  ground.name = "ground";
  ground.friction = config_.world.ground_friction;
  ground.pose.translation() = Eigen::Vector3d(0.0, 0.0, config_.world.ground_height);
  world_.AddCollider(ground);
}

void Simulation::AddObject(std::size_t index) {
  const ObjectConfig& object_config = config_.objects[index];
  const std::string path = "~objects[" + std::to_string(index) + "]";
  BuiltObject built = BuildObject(object_config, path);
  Object object;
  object.config = object_config;
  object.body = world_.AddBody(object_config.name, built.model, BodyOptionsOf(object_config));
  for (auto& [name, nodes] : built.clamps) {
    world_.AddKinematicGroup(object.body, core::KinematicGroup{name, nodes, {}});
    object.clamp_names.push_back(name);
  }
  try {
    object.skin = std::make_shared<const core::SurfaceSkin>(
        core::SurfaceSkin::Embed(*built.model, built.surface));
  } catch (const std::exception& e) {
    throw ConfigError("parameter " + path + "/visual_mesh: " + e.what());
  }
  object.strain = core::SurfaceStrain(object.skin->rest_surface());
  const std::string substeps = SubstepProblem(config_.world, world_.stable_time_step());
  if (!substeps.empty()) {
    throw ConfigError("parameter " + path + " (object '" + object_config.name + "'): " + substeps);
  }
  ROS_INFO("msm_sim: object '%s': %d nodes, %d springs, %.4g kg, %d clamps, stable step %.3g s",
           object_config.name.c_str(), built.model->num_nodes(), built.model->num_springs(),
           built.model->masses().sum(), static_cast<int>(built.clamps.size()),
           world_.stable_time_step());
  if (built.model->spring_law() == core::SpringLaw::kPower) {
    ROS_INFO(
        "msm_sim: object '%s' runs the fitted spring law (docs/physics.md 4.1): alpha %.6g, "
        "beta %.6g",
        object_config.name.c_str(), built.model->power_spring_law().alpha,
        built.model->power_spring_law().beta);
  }
  if (const auto& calibration = built.model->self_calibration()) {
    ROS_INFO("msm_sim: object '%s' self-calibrated (docs/physics.md 2.2): k x %.4f, q %.4g",
             object_config.name.c_str(), calibration->stiffness_factor,
             calibration->dispersion_fraction);
  }
  objects_.push_back(std::move(object));
}

std::string Simulation::ApplyForce(const msm_sim::ContactForce& message,
                                   const tf2::BufferCore& tf) {
  const int object = FindObject(message.object);
  if (object < 0) return "unknown object '" + message.object + "'";
  const Eigen::Vector3d point(message.point.x, message.point.y, message.point.z);
  const Eigen::Vector3d force(message.force.x, message.force.y, message.force.z);
  if (!point.allFinite() || !force.allFinite() || !std::isfinite(message.radius) ||
      !std::isfinite(message.duration)) {
    return "NaN or Inf in point, force, radius or duration";
  }
  if (message.radius < 0.0 || message.duration < 0.0) return "negative radius or duration";
  if (force.norm() > config_.world.max_force) {
    std::ostringstream reason;
    reason << "|force| = " << force.norm()
           << " N exceeds ~world/max_force = " << config_.world.max_force
           << " N (absurd magnitude)";
    return reason.str();
  }
  Eigen::Isometry3d to_world;
  std::string error;
  if (!LookUp(tf, message.header.frame_id, message.header.stamp, &to_world, &error)) {
    return "unknown frame '" + message.header.frame_id + "' (" + error + ")";
  }
  const Eigen::Vector3d world_point = to_world * point;
  const std::string far = DistanceProblem(world_point, config_.world.max_distance);
  if (!far.empty()) return far + " (in frame '" + message.header.frame_id + "')";
  const int dropped =
      world_.ApplyForce(objects_[object].body, world_point, to_world.linear() * force,
                        message.radius, message.duration);
  if (dropped > 0) {
    ROS_WARN_THROTTLE(1.0,
                      "msm_sim: ~apply_force: object '%s' had more pending pushes than "
                      "~world/max_pending_pushes (%d) or ~world/max_pending_force (%g N); the "
                      "oldest %d dropped",
                      message.object.c_str(), config_.world.max_pending_pushes,
                      config_.world.max_pending_force, dropped);
  }
  return {};
}

std::string Simulation::SetWrench(std::size_t index, const geometry_msgs::WrenchStamped& message,
                                  const ros::Time& now, const tf2::BufferCore& tf) {
  WrenchInput& input = wrench_inputs_.at(index);
  const Eigen::Vector3d force(message.wrench.force.x, message.wrench.force.y,
                              message.wrench.force.z);
  const Eigen::Vector3d torque(message.wrench.torque.x, message.wrench.torque.y,
                               message.wrench.torque.z);
  if (!force.allFinite() || !torque.allFinite()) return "NaN or Inf in the wrench";
  if (force.norm() > config_.world.max_force) {
    std::ostringstream reason;
    reason << "|force| = " << force.norm() << " N exceeds ~world/max_force (absurd magnitude)";
    return reason.str();
  }
  // The torque acts as forces of about |torque| / radius on the input's nodes: bounded like forces
  // (a huge finite torque overflowed the clamps' reactions to Inf and NaN).
  const double max_torque = config_.world.max_force * input.config.radius;
  if (torque.norm() > max_torque) {
    std::ostringstream reason;
    reason << "|torque| = " << torque.norm()
           << " N m exceeds ~world/max_force x radius = " << max_torque
           << " N m (absurd magnitude)";
    return reason.str();
  }
  Eigen::Isometry3d to_world;
  std::string error;
  if (!LookUp(tf, message.header.frame_id, message.header.stamp, &to_world, &error)) {
    return "unknown frame '" + message.header.frame_id + "' (" + error + ")";
  }
  const std::string far = DistanceProblem(to_world.translation(), config_.world.max_distance);
  if (!far.empty()) return far + " (the origin of frame '" + message.header.frame_id + "')";
  input.active = true;
  input.received = now;
  input.point = to_world.translation();
  input.force = to_world.linear() * force;
  input.torque = to_world.linear() * torque;
  return {};
}

void Simulation::PlaceRobot(const tf2::BufferCore& tf, const ros::Time& now) {
  robot_->Update(tf, now, now, 0.0);
}

void Simulation::Reset() {
  world_.Reset();
  for (WrenchInput& input : wrench_inputs_) input.active = false;
  ResetContactAverages();
}

std::string Simulation::SetMaterial(const std::string& name, double youngs, double poisson,
                                    double density, double damping, double friction,
                                    std::string* described) {
  const int index = FindObject(name);
  if (index < 0) return "unknown object '" + name + "'";
  Object& object = objects_[index];
  const std::string material_problem = MaterialProblem(youngs, poisson, density);
  if (!material_problem.empty()) return material_problem;
  try {
    const core::Material material = core::Material::FromYoungsPoisson(youngs, poisson, density);
    if (!(damping >= 0.0) || !(friction >= 0.0) || !std::isfinite(damping) ||
        !std::isfinite(friction)) {
      throw std::invalid_argument("damping and friction must be finite and >= 0");
    }
    ObjectConfig config = object.config;
    config.youngs = youngs;
    config.poisson = poisson;
    config.density = density;
    config.damping = damping;
    config.friction = friction;
    const std::shared_ptr<const core::Model> model =
        BuildObjectModel(config, material, world_.model(object.body).self_calibration());
    core::StableTimeStepOptions stability;
    stability.damping_beta = damping;
    stability.safety = config_.world.time_step_safety;
    stability.fixed_nodes = world_.constrained_nodes(object.body);  // as the World counts them
    const std::string substeps =
        SubstepProblem(config_.world, core::StableTimeStep(*model, stability));
    if (!substeps.empty()) return substeps;
    world_.ReplaceModel(object.body, model, BodyOptionsOf(config));
    object.config = config;
    *described = material.Describe();
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

std::string Simulation::SetPublishing(double publish_rate, bool real_time) {
  if (!std::isfinite(publish_rate) || publish_rate <= 0.0) {
    return "publish_rate must be finite and > 0 Hz";
  }
  config_.world.publish_rate = publish_rate;
  config_.world.real_time = real_time;
  return {};
}

void Simulation::Advance(double seconds, const ros::Time& now, const ros::WallTime& deadline,
                         const tf2::BufferCore* tf, const ros::Time& robot_origin) {
  const double dt = config_.world.time_step;
  const int steps = static_cast<int>(std::floor(seconds / dt + 1e-9));
  for (int k = 0; k < steps; ++k) {
    if (!deadline.isZero() && ros::WallTime::now() > deadline) break;
    if (tf != nullptr) robot_->Update(*tf, now, robot_origin + ros::Duration(time() + dt), dt);
    ApplyHeldWrenches(now);
    const ros::WallTime start = ros::WallTime::now();
    const core::StepReport report = world_.Step(dt);
    step_wall_seconds_ += (ros::WallTime::now() - start).toSec();
    ++steps_;
    ++steps_since_report_;
    last_substeps_ = report.substeps;
    if (!report.refined_because.empty() && report.accepted) {
      ROS_WARN(
          "msm_sim: a step diverged at the stable substep (%s); it was taken again and every "
          "step now takes %d substeps (%dx finer, until reset). Deep presses of nearly "
          "incompressible objects do this; a lower ~world/time_step_safety avoids it",
          report.refined_because.c_str(), report.substeps, report.substep_refinement);
    }
    if (!report.accepted) {
      ++rejected_steps_;
      last_rejection_ = report.reason;
      ROS_WARN_THROTTLE(1.0, "msm_sim: step rejected, state kept: %s", report.reason.c_str());
      continue;
    }
    simulated_since_report_ += dt;
    AddStepContacts(dt);
  }
}

void Simulation::ApplyHeldWrenches(const ros::Time& now) {
  // Wrench topics hold their last value until it goes stale.
  for (WrenchInput& input : wrench_inputs_) {
    if (!input.active) continue;
    if ((now - input.received).toSec() > kWrenchHoldSeconds) {
      input.active = false;
      continue;
    }
    world_.ApplyWrench(objects_[input.object].body, input.point, input.force, input.torque,
                       input.config.radius, 0.0);
  }
}

void Simulation::AddStepContacts(double dt) {
  for (std::size_t o = 0; o < objects_.size(); ++o) {
    const std::vector<core::ContactWrench>& wrenches = world_.wrenches(objects_[o].body);
    std::vector<core::ContactWrenchAverage>& averages = contact_averages_[o];
    averages.resize(wrenches.size());
    for (std::size_t w = 0; w < wrenches.size(); ++w) averages[w].Add(wrenches[w], dt);
    const int body = objects_[o].body;
    contact_points_.Add(static_cast<int>(o), world_.model(body).num_nodes(),
                        world_.contact_points(body));
  }
  contact_points_.AddStep(dt);
}

void Simulation::ResetContactAverages() {
  for (std::vector<core::ContactWrenchAverage>& averages : contact_averages_) {
    for (core::ContactWrenchAverage& average : averages) average.Reset();
  }
  contact_points_.Reset();
}

bool Simulation::LookUp(const tf2::BufferCore& tf, const std::string& frame, const ros::Time& stamp,
                        Eigen::Isometry3d* transform, std::string* error) const {
  if (frame.empty() || frame == config_.world.frame) {
    *transform = Eigen::Isometry3d::Identity();
    return true;
  }
  try {
    *transform = ToIsometry(tf.lookupTransform(config_.world.frame, frame, stamp).transform);
    return true;
  } catch (const tf2::TransformException& e) {
    // A stamp tf has not reached yet: take the latest.
    try {
      *transform =
          ToIsometry(tf.lookupTransform(config_.world.frame, frame, ros::Time(0)).transform);
      return true;
    } catch (const tf2::TransformException& latest) {
      *error = latest.what();
      return false;
    }
  }
}

core::BodyOptions Simulation::BodyOptionsOf(const ObjectConfig& config) const {
  core::BodyOptions options;
  options.damping_beta = config.damping;
  options.friction = config.friction;
  options.restitution = config.restitution;
  options.orientation_threshold = config.orientation_threshold;
  return options;
}

int Simulation::FindObject(const std::string& name) const {
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    if (objects_[i].config.name == name) return static_cast<int>(i);
  }
  for (std::size_t i = 0; i < config_.objects.size(); ++i) {
    if (config_.objects[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace msm_sim::ros_interface
