#include "simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <sensor_msgs/point_cloud2_iterator.h>
#include <tf2/exceptions.h>

#include "conversions.h"
#include "object_builder.h"

namespace msm_sim::ros_interface {
namespace {

// Applied forces hold this long after their last message on a wrench topic.
constexpr double kWrenchHoldSeconds = 0.5;

core::WorldOptions WorldOptionsOf(const WorldConfig& config) {
  core::WorldOptions options;
  options.gravity = config.gravity;
  return options;
}

// Blue (compressed) - a light silicone tone (unstrained) - red (stretched).
std_msgs::ColorRGBA StrainColour(double strain, double range) {
  const double s = std::clamp(strain / range, -1.0, 1.0);
  const Eigen::Vector3d neutral(0.95, 0.82, 0.62);
  const Eigen::Vector3d end =
      s >= 0.0 ? Eigen::Vector3d(0.85, 0.1, 0.1) : Eigen::Vector3d(0.1, 0.25, 0.9);
  const Eigen::Vector3d c = neutral + std::abs(s) * (end - neutral);
  std_msgs::ColorRGBA colour;
  colour.r = c.x();
  colour.g = c.y();
  colour.b = c.z();
  colour.a = 1.0;
  return colour;
}

}  // namespace

Simulation::Simulation(const SimulationConfig& config, const std::string& robot_description)
    : config_(config), world_(WorldOptionsOf(config_.world)) {
  if (config_.world.ground) {
    core::Collider ground;
    ground.name = "ground";
    ground.friction = config_.world.ground_friction;
    ground.pose.translation() = Eigen::Vector3d(0.0, 0.0, config_.world.ground_height);
    world_.AddCollider(ground);
  }
  for (std::size_t i = 0; i < config_.objects.size(); ++i) {
    const ObjectConfig& object_config = config_.objects[i];
    const std::string path = "~objects[" + std::to_string(i) + "]";
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
    const core::TriangleMesh& surface = object.skin->rest_surface();
    object.rest_edge_lengths.resize(3 * surface.num_triangles());
    for (int t = 0; t < surface.num_triangles(); ++t) {
      for (int e = 0; e < 3; ++e) {
        object.rest_edge_lengths[3 * t + e] =
            (surface.vertices.col(surface.triangles(e, t)) -
             surface.vertices.col(surface.triangles((e + 1) % 3, t)))
                .norm();
      }
    }
    ROS_INFO("msm_sim: object '%s': %d nodes, %d springs, %.4g kg, %d clamps, stable step %.3g s",
             object_config.name.c_str(), built.model->num_nodes(), built.model->num_springs(),
             built.model->masses().sum(), static_cast<int>(built.clamps.size()),
             world_.stable_time_step());
    objects_.push_back(std::move(object));
  }
  robot_ = std::make_unique<RobotColliders>(config_.robot, robot_description, config_.world.frame,
                                            &world_);
  contact_sums_.resize(objects_.size());

  for (const WrenchInputConfig& input_config : config_.wrench_inputs) {
    WrenchInput input;
    input.config = input_config;
    input.object = FindObject(input_config.object);
    wrench_inputs_.push_back(input);
  }
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
  world_.ApplyForce(objects_[object].body, to_world * point, to_world.linear() * force,
                    message.radius, message.duration);
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
  Eigen::Isometry3d to_world;
  std::string error;
  if (!LookUp(tf, message.header.frame_id, message.header.stamp, &to_world, &error)) {
    return "unknown frame '" + message.header.frame_id + "' (" + error + ")";
  }
  input.active = true;
  input.received = now;
  input.point = to_world.translation();
  input.force = to_world.linear() * force;
  input.torque = to_world.linear() * torque;
  return {};
}

void Simulation::UpdateRobot(const tf2::BufferCore& tf, const ros::Time& now) {
  robot_->Update(tf, now);
}

void Simulation::Reset() {
  world_.Reset();
  for (WrenchInput& input : wrench_inputs_) input.active = false;
  for (auto& sums : contact_sums_) std::fill(sums.begin(), sums.end(), ContactSum{});
  contact_time_ = 0.0;
}

std::string Simulation::SetMaterial(const std::string& name, double youngs, double poisson,
                                    double density, double damping, double friction,
                                    std::string* described) {
  const int index = FindObject(name);
  if (index < 0) return "unknown object '" + name + "'";
  Object& object = objects_[index];
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
    world_.ReplaceModel(object.body, BuildObjectModel(config, material), BodyOptionsOf(config));
    object.config = config;
    *described = material.Describe();
    return {};
  } catch (const std::exception& e) {
    return e.what();
  }
}

visualization_msgs::MarkerArray Simulation::Markers(const ros::Time& stamp) const {
  visualization_msgs::MarkerArray array;
  for (const Object& object : objects_) {
    const core::State& state = world_.state(object.body);
    const Eigen::Matrix3Xd vertices = object.skin->DeformedVertices(state.positions);
    const core::TriangleMesh& surface = object.skin->rest_surface();
    // Surface strain at each vertex: the mean relative change of its edges.
    Eigen::VectorXd strain = Eigen::VectorXd::Zero(surface.num_vertices());
    Eigen::VectorXd count = Eigen::VectorXd::Zero(surface.num_vertices());
    for (int t = 0; t < surface.num_triangles(); ++t) {
      for (int e = 0; e < 3; ++e) {
        const int a = surface.triangles(e, t), b = surface.triangles((e + 1) % 3, t);
        const double rest = object.rest_edge_lengths[3 * t + e];
        if (!(rest > 0.0)) continue;
        const double s = (vertices.col(a) - vertices.col(b)).norm() / rest - 1.0;
        strain[a] += s;
        strain[b] += s;
        count[a] += 1.0;
        count[b] += 1.0;
      }
    }
    visualization_msgs::Marker mesh;
    mesh.header.stamp = stamp;
    mesh.header.frame_id = config_.world.frame;
    mesh.ns = object.config.name;
    mesh.id = 0;
    mesh.type = visualization_msgs::Marker::TRIANGLE_LIST;
    mesh.action = visualization_msgs::Marker::ADD;
    mesh.pose.orientation.w = 1.0;
    mesh.scale.x = mesh.scale.y = mesh.scale.z = 1.0;
    mesh.color.r = 0.9;
    mesh.color.g = 0.6;
    mesh.color.b = 0.3;
    mesh.color.a = 1.0;
    mesh.points.reserve(3 * surface.num_triangles());
    for (int t = 0; t < surface.num_triangles(); ++t) {
      for (int e = 0; e < 3; ++e) {
        const int v = surface.triangles(e, t);
        mesh.points.push_back(ToPoint(vertices.col(v)));
        if (config_.markers.colour_by_strain) {
          mesh.colors.push_back(StrainColour(count[v] > 0.0 ? strain[v] / count[v] : 0.0,
                                             config_.markers.strain_range));
        }
      }
    }
    array.markers.push_back(std::move(mesh));
    if (config_.markers.nodes) {
      visualization_msgs::Marker nodes;
      nodes.header = array.markers.back().header;
      nodes.ns = object.config.name;
      nodes.id = 1;
      nodes.type = visualization_msgs::Marker::SPHERE_LIST;
      nodes.pose.orientation.w = 1.0;
      const double size = 0.3 * world_.model(object.body).characteristic_length();
      nodes.scale.x = nodes.scale.y = nodes.scale.z = size;
      nodes.color.b = nodes.color.a = 1.0;
      for (int i = 0; i < state.positions.cols(); ++i) {
        nodes.points.push_back(ToPoint(state.positions.col(i)));
      }
      array.markers.push_back(std::move(nodes));
    }
    if (config_.markers.springs) {
      const core::Model& model = world_.model(object.body);
      visualization_msgs::Marker springs;
      springs.header = array.markers.back().header;
      springs.ns = object.config.name;
      springs.id = 2;
      springs.type = visualization_msgs::Marker::LINE_LIST;
      springs.pose.orientation.w = 1.0;
      springs.scale.x = 0.05 * model.characteristic_length();
      springs.color.g = springs.color.a = 1.0;
      for (int s = 0; s < model.num_springs(); ++s) {
        springs.points.push_back(ToPoint(state.positions.col(model.spring_node_a()[s])));
        springs.points.push_back(ToPoint(state.positions.col(model.spring_node_b()[s])));
      }
      array.markers.push_back(std::move(springs));
    }
  }
  return array;
}

msm_sim::ContactArray Simulation::Contacts(
    const ros::Time& stamp, std::vector<geometry_msgs::WrenchStamped>* link_wrenches) {
  link_wrenches->clear();
  msm_sim::ContactArray array;
  array.header.stamp = stamp;
  array.header.frame_id = config_.world.frame;
  const int colliders = world_.num_colliders();
  const std::vector<RobotColliders::Link>& links = robot_->links();
  // Per robot link, summed over objects: force and torque about the link origin (world axes).
  std::vector<Eigen::Vector3d> link_force(links.size(), Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> link_torque(links.size(), Eigen::Vector3d::Zero());
  if (contact_time_ > 0.0) {
    for (std::size_t o = 0; o < objects_.size(); ++o) {
      const Object& object = objects_[o];
      std::vector<ContactSum> per_link(links.size());
      std::vector<Eigen::Vector3d> per_link_torque(links.size(), Eigen::Vector3d::Zero());
      for (std::size_t w = 0; w < contact_sums_[o].size(); ++w) {
        ContactSum& sum = contact_sums_[o][w];
        if (sum.microcollisions == 0) continue;
        const int link = static_cast<int>(w) < colliders ? robot_->LinkOfCollider(w) : -1;
        if (link >= 0) {
          // Move the torque from the collision element's origin to the link's.
          const Eigen::Vector3d offset =
              world_.collider(w).pose.translation() - links[link].pose.translation();
          per_link[link].force_time += sum.force_time;
          per_link_torque[link] += sum.torque_time + offset.cross(sum.force_time);
          per_link[link].weighted_centroid += sum.weighted_centroid;
          per_link[link].weight += sum.weight;
          per_link[link].microcollisions += sum.microcollisions;
          continue;
        }
        msm_sim::Contact contact;
        contact.object = object.config.name;
        contact.collider = static_cast<int>(w) < colliders
                               ? world_.collider(static_cast<int>(w)).name
                               : object.clamp_names[w - colliders];
        contact.frame_id = config_.world.frame;
        contact.wrench.force = ToVector(sum.force_time / contact_time_);
        contact.wrench.torque = ToVector(sum.torque_time / contact_time_);
        contact.centroid =
            ToPoint(sum.weight > 0.0 ? Eigen::Vector3d(sum.weighted_centroid / sum.weight)
                                     : Eigen::Vector3d::Zero());
        contact.microcollisions = static_cast<std::uint32_t>(sum.microcollisions);
        array.contacts.push_back(contact);
      }
      // Robot links report in their own frame, about their origin.
      for (std::size_t l = 0; l < links.size(); ++l) {
        if (per_link[l].microcollisions == 0) continue;
        const Eigen::Isometry3d& pose = links[l].pose;
        const Eigen::Matrix3d to_link = pose.linear().transpose();
        const Eigen::Vector3d force = per_link[l].force_time / contact_time_;
        const Eigen::Vector3d torque = per_link_torque[l] / contact_time_;
        link_force[l] += force;
        link_torque[l] += torque;
        msm_sim::Contact contact;
        contact.object = object.config.name;
        contact.collider = links[l].name;
        contact.frame_id = links[l].name;
        contact.wrench.force = ToVector(to_link * force);
        contact.wrench.torque = ToVector(to_link * torque);
        contact.centroid = ToPoint(
            pose.inverse() * Eigen::Vector3d(per_link[l].weighted_centroid / per_link[l].weight));
        contact.microcollisions = static_cast<std::uint32_t>(per_link[l].microcollisions);
        array.contacts.push_back(contact);
      }
    }
  }
  for (std::size_t l = 0; l < links.size(); ++l) {
    geometry_msgs::WrenchStamped wrench;
    wrench.header.stamp = stamp;
    wrench.header.frame_id = links[l].name;
    const Eigen::Matrix3d to_link = links[l].pose.linear().transpose();
    wrench.wrench.force = ToVector(to_link * link_force[l]);
    wrench.wrench.torque = ToVector(to_link * link_torque[l]);
    link_wrenches->push_back(wrench);
  }
  for (auto& sums : contact_sums_) std::fill(sums.begin(), sums.end(), ContactSum{});
  contact_time_ = 0.0;
  return array;
}

sensor_msgs::PointCloud2 Simulation::NodeCloud(const ros::Time& stamp) const {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = config_.world.frame;
  std::size_t total = 0;
  for (const Object& object : objects_) total += world_.model(object.body).num_nodes();
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2Fields(
      4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32, "z", 1,
      sensor_msgs::PointField::FLOAT32, "object", 1, sensor_msgs::PointField::UINT32);
  modifier.resize(total);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  sensor_msgs::PointCloud2Iterator<std::uint32_t> index(cloud, "object");
  for (std::size_t o = 0; o < objects_.size(); ++o) {
    const Eigen::Matrix3Xd& positions = world_.state(objects_[o].body).positions;
    for (int i = 0; i < positions.cols(); ++i, ++x, ++y, ++z, ++index) {
      *x = static_cast<float>(positions(0, i));
      *y = static_cast<float>(positions(1, i));
      *z = static_cast<float>(positions(2, i));
      *index = static_cast<std::uint32_t>(o);
    }
  }
  return cloud;
}

std::vector<geometry_msgs::TransformStamped> Simulation::Frames(const ros::Time& stamp) const {
  std::vector<geometry_msgs::TransformStamped> frames;
  for (const Object& object : objects_) {
    const core::Model& model = world_.model(object.body);
    const Eigen::VectorXd& m = model.masses();
    const Eigen::Matrix3Xd& x = world_.state(object.body).positions;
    const Eigen::Matrix3Xd& rest = model.rest_positions();
    const Eigen::Vector3d centre = x * m / m.sum();
    const Eigen::Vector3d rest_centre = rest * m / m.sum();
    // The body's rotation: the rotation part of the best affine fit rest -> current (the polar
    // decomposition of sum m (x - c)(X - C)^T).
    const Eigen::Matrix3d covariance =
        (x.colwise() - centre) * m.asDiagonal() * (rest.colwise() - rest_centre).transpose();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d rotation = svd.matrixU() * svd.matrixV().transpose();
    if (rotation.determinant() < 0.0) {
      Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
      flip(2, 2) = -1.0;
      rotation = svd.matrixU() * flip * svd.matrixV().transpose();
    }
    geometry_msgs::TransformStamped transform;
    transform.header.stamp = stamp;
    transform.header.frame_id = config_.world.frame;
    transform.child_frame_id = object.config.name;
    transform.transform.translation = ToVector(centre);
    const Eigen::Quaterniond q(rotation);
    transform.transform.rotation.x = q.x();
    transform.transform.rotation.y = q.y();
    transform.transform.rotation.z = q.z();
    transform.transform.rotation.w = q.w();
    frames.push_back(transform);
  }
  return frames;
}

diagnostic_msgs::DiagnosticArray Simulation::Diagnostics(const ros::Time& stamp, double wall,
                                                         bool paused, bool timing) {
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = stamp;
  diagnostic_msgs::DiagnosticStatus status;
  status.name = ros::this_node::getName() + ": simulation";
  status.hardware_id = "msm_sim";
  status.level = rejected_steps_ > 0 ? diagnostic_msgs::DiagnosticStatus::WARN
                                     : diagnostic_msgs::DiagnosticStatus::OK;
  status.message = paused ? "paused" : (rejected_steps_ > 0 ? "steps rejected" : "running");
  auto add = [&status](const std::string& key, const std::string& value) {
    diagnostic_msgs::KeyValue entry;
    entry.key = key;
    entry.value = value;
    status.values.push_back(entry);
  };
  std::ostringstream number;
  auto text = [&number](double value) {
    number.str("");
    number << value;
    return number.str();
  };
  add("simulated time [s]", text(world_.time()));
  if (timing) {
    add("step time [ms]",
        text(steps_since_report_ > 0 ? 1e3 * step_wall_seconds_ / steps_since_report_ : 0.0));
    add("real-time factor", text(wall > 0.0 ? simulated_since_report_ / wall : 0.0));
  }
  add("substeps per step", text(last_substeps_));
  add("steps", text(static_cast<double>(steps_)));
  add("rejected steps", text(static_cast<double>(rejected_steps_)));
  if (!last_rejection_.empty()) add("last rejection", last_rejection_);
  const std::vector<std::string>& problems = robot_->problems();
  for (std::size_t p = 0; p < problems.size(); ++p) {
    add("robot problem " + std::to_string(p + 1), problems[p]);
  }
  if (!problems.empty()) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    status.message = "running without part of the robot (see robot problems)";
  }
  for (const Object& object : objects_) {
    add("energy " + object.config.name + " [J]", text(world_.ComputeEnergies(object.body).total()));
  }
  array.status.push_back(status);
  steps_since_report_ = 0;
  step_wall_seconds_ = 0.0;
  simulated_since_report_ = 0.0;
  return array;
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

void Simulation::Advance(double seconds, const ros::Time& now, const ros::WallTime& deadline) {
  const double dt = config_.world.time_step;
  const int steps = static_cast<int>(std::floor(seconds / dt + 1e-9));
  for (int k = 0; k < steps; ++k) {
    if (!deadline.isZero() && ros::WallTime::now() > deadline) break;
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
    const ros::WallTime start = ros::WallTime::now();
    const core::StepReport report = world_.Step(dt);
    step_wall_seconds_ += (ros::WallTime::now() - start).toSec();
    ++steps_;
    ++steps_since_report_;
    last_substeps_ = report.substeps;
    if (!report.accepted) {
      ++rejected_steps_;
      last_rejection_ = report.reason;
      ROS_WARN_THROTTLE(1.0, "msm_sim: step rejected, state kept: %s", report.reason.c_str());
      continue;
    }
    simulated_since_report_ += dt;
    contact_time_ += dt;
    for (std::size_t o = 0; o < objects_.size(); ++o) {
      const std::vector<core::ContactWrench>& wrenches = world_.wrenches(objects_[o].body);
      std::vector<ContactSum>& sums = contact_sums_[o];
      sums.resize(wrenches.size());
      for (std::size_t w = 0; w < wrenches.size(); ++w) {
        const double weight = wrenches[w].force.norm() * dt;
        sums[w].force_time += wrenches[w].force * dt;
        sums[w].torque_time += wrenches[w].torque * dt;
        sums[w].weighted_centroid += weight * wrenches[w].centroid;
        sums[w].weight += weight;
        sums[w].microcollisions += wrenches[w].microcollisions;
      }
    }
  }
}

core::BodyOptions Simulation::BodyOptionsOf(const ObjectConfig& config) const {
  core::BodyOptions options;
  options.damping_beta = config.damping;
  options.friction = config.friction;
  options.restitution = config.restitution;
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
