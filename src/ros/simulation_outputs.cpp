// Simulation: the state as output messages (markers, node cloud, frames, diagnostics).
#include "simulation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include <sensor_msgs/point_cloud2_iterator.h>

#include "conversions.h"
#include "msm_sim/model/body_frame.h"

namespace msm_sim::ros_interface {
namespace {

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

visualization_msgs::MarkerArray Simulation::Markers(const ros::Time& stamp) const {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = config_.world.frame;
  visualization_msgs::MarkerArray array;
  for (const Object& object : objects_) {
    array.markers.push_back(SurfaceMarker(object, header));
    if (config_.markers.nodes) array.markers.push_back(NodeMarker(object, header));
    if (config_.markers.springs) array.markers.push_back(SpringMarker(object, header));
  }
  return array;
}

// The deformed visual surface, optionally coloured by its strain.
visualization_msgs::Marker Simulation::SurfaceMarker(const Object& object,
                                                     const std_msgs::Header& header) const {
  const Eigen::Matrix3Xd vertices =
      object.skin->DeformedVertices(world_.state(object.body).positions);
  const core::TriangleMesh& surface = object.skin->rest_surface();
  const bool coloured = config_.markers.colour_by_strain;
  const Eigen::VectorXd strain =
      coloured ? object.strain.VertexStrains(vertices) : Eigen::VectorXd();
  visualization_msgs::Marker mesh;
  mesh.header = header;
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
      if (coloured) mesh.colors.push_back(StrainColour(strain[v], config_.markers.strain_range));
    }
  }
  return mesh;
}

// The object's nodes as spheres of 0.3 characteristic lengths.
visualization_msgs::Marker Simulation::NodeMarker(const Object& object,
                                                  const std_msgs::Header& header) const {
  const Eigen::Matrix3Xd& positions = world_.state(object.body).positions;
  visualization_msgs::Marker nodes;
  nodes.header = header;
  nodes.ns = object.config.name;
  nodes.id = 1;
  nodes.type = visualization_msgs::Marker::SPHERE_LIST;
  nodes.pose.orientation.w = 1.0;
  const double size = 0.3 * world_.model(object.body).characteristic_length();
  nodes.scale.x = nodes.scale.y = nodes.scale.z = size;
  nodes.color.b = nodes.color.a = 1.0;
  for (int i = 0; i < positions.cols(); ++i) nodes.points.push_back(ToPoint(positions.col(i)));
  return nodes;
}

// The object's springs as lines between their nodes.
visualization_msgs::Marker Simulation::SpringMarker(const Object& object,
                                                    const std_msgs::Header& header) const {
  const Eigen::Matrix3Xd& positions = world_.state(object.body).positions;
  const core::Model& model = world_.model(object.body);
  visualization_msgs::Marker springs;
  springs.header = header;
  springs.ns = object.config.name;
  springs.id = 2;
  springs.type = visualization_msgs::Marker::LINE_LIST;
  springs.pose.orientation.w = 1.0;
  springs.scale.x = 0.05 * model.characteristic_length();
  springs.color.g = springs.color.a = 1.0;
  for (int s = 0; s < model.num_springs(); ++s) {
    springs.points.push_back(ToPoint(positions.col(model.spring_node_a()[s])));
    springs.points.push_back(ToPoint(positions.col(model.spring_node_b()[s])));
  }
  return springs;
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
    const Eigen::Isometry3d frame =
        core::BodyFrame(world_.model(object.body), world_.state(object.body));
    geometry_msgs::TransformStamped transform;
    transform.header.stamp = stamp;
    transform.header.frame_id = config_.world.frame;
    transform.child_frame_id = object.config.name;
    transform.transform.translation = ToVector(frame.translation());
    const Eigen::Quaterniond q(frame.linear());
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
    const core::Model& model = world_.model(object.body);
    add("nodes " + object.config.name, std::to_string(model.num_nodes()));
    add("mass " + object.config.name + " [kg]", text(model.masses().sum()));
    add("added mass " + object.config.name + " [kg]", text(model.added_mass()));
    if (model.mass_scaling_limited()) {
      add("mass scaling " + object.config.name, "limited by mass_scaling (the bound)");
    }
    add("energy " + object.config.name + " [J]", text(world_.ComputeEnergies(object.body).total()));
    // The calibrated springs, so that a new material (~set_material, ~reconfigure) shows.
    const std::vector<double>& k = model.spring_stiffness();
    const double mean = k.empty() ? 0.0 : std::accumulate(k.begin(), k.end(), 0.0) / k.size();
    add("mean spring stiffness " + object.config.name + " [N/m]", text(mean));
  }
  array.status.push_back(status);
  steps_since_report_ = 0;
  step_wall_seconds_ = 0.0;
  simulated_since_report_ = 0.0;
  return array;
}

}  // namespace msm_sim::ros_interface
