// Simulation: the contact points averaged since the last report, as point clouds: every object's
// in the world frame (~contact_points) and each robot link's in the link frame
// (~links/<link>/pressure).
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <ros/console.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "simulation.h"

namespace msm_sim::ros_interface {
namespace {

// An empty cloud of the contact-point fields, stamped, in `frame`, sized for `points` points.
sensor_msgs::PointCloud2 EmptyContactCloud(const ros::Time& stamp, const std::string& frame,
                                           std::size_t points) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = frame;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  const auto f32 = sensor_msgs::PointField::FLOAT32;
  const auto u32 = sensor_msgs::PointField::UINT32;
  modifier.setPointCloud2Fields(11, "x", 1, f32, "y", 1, f32, "z", 1, f32, "normal_x", 1, f32,
                                "normal_y", 1, f32, "normal_z", 1, f32, "force_x", 1, f32,
                                "force_y", 1, f32, "force_z", 1, f32, "collider", 1, u32, "object",
                                1, u32);
  modifier.resize(points);
  return cloud;
}

// Writes point k of `cloud` (sized beforehand): the 9 float32 fields, then the 2 uint32 ones,
// packed in that order (EmptyContactCloud).
void SetContactPoint(std::size_t k, const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                     const Eigen::Vector3d& force, int collider, int object,
                     sensor_msgs::PointCloud2* cloud) {
  std::uint8_t* data = cloud->data.data() + k * cloud->point_step;
  float values[9];
  for (int d = 0; d < 3; ++d) {
    values[d] = static_cast<float>(position[d]);
    values[3 + d] = static_cast<float>(normal[d]);
    values[6 + d] = static_cast<float>(force[d]);
  }
  const std::uint32_t indices[2] = {static_cast<std::uint32_t>(collider),
                                    static_cast<std::uint32_t>(object)};
  std::memcpy(data, values, sizeof values);
  std::memcpy(data + sizeof values, indices, sizeof indices);
}

// Whether the point's values are finite as float32 (a finite double may overflow a float).
bool FiniteAsFloat(const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                   const Eigen::Vector3d& force) {
  return position.cast<float>().allFinite() && normal.cast<float>().allFinite() &&
         force.cast<float>().allFinite();
}

// Keeps the first `points` points of `cloud`.
void Shrink(std::size_t points, sensor_msgs::PointCloud2* cloud) {
  cloud->width = static_cast<std::uint32_t>(points);
  cloud->row_step = cloud->width * cloud->point_step;
  cloud->data.resize(cloud->row_step);
}

}  // namespace

void Simulation::ContactPointClouds(const ros::Time& stamp, sensor_msgs::PointCloud2* world_cloud,
                                    std::vector<sensor_msgs::PointCloud2>* link_clouds) const {
  const std::vector<RobotColliders::Link>& links = robot_->links();
  // Sized for every point, shrunk to those written (a point with NaN or Inf is left out).
  std::vector<std::size_t> in_link(links.size(), 0);
  for (std::size_t k = 0; k < contact_points_.size(); ++k) {
    const int link = robot_->LinkOfCollider(contact_points_.Average(k).collider);
    if (link >= 0) ++in_link[link];
  }
  *world_cloud = EmptyContactCloud(stamp, config_.world.frame, contact_points_.size());
  link_clouds->clear();
  for (std::size_t l = 0; l < links.size(); ++l) {
    link_clouds->push_back(EmptyContactCloud(stamp, links[l].name, in_link[l]));
  }
  std::size_t written = 0, dropped = 0;
  std::vector<std::size_t> link_written(links.size(), 0);
  for (std::size_t k = 0; k < contact_points_.size(); ++k) {
    const core::ContactPointAverage::Point point = contact_points_.Average(k);
    const int link = robot_->LinkOfCollider(point.collider);
    // In the link frame for the link's cloud.
    const Eigen::Isometry3d to_link =
        link >= 0 ? links[link].pose.inverse() : Eigen::Isometry3d::Identity();
    const Eigen::Vector3d position = to_link * point.position;
    const Eigen::Vector3d normal = to_link.linear() * point.normal;
    const Eigen::Vector3d force = to_link.linear() * point.force;
    if (!FiniteAsFloat(point.position, point.normal, point.force) ||
        !FiniteAsFloat(position, normal, force)) {
      ++dropped;
      continue;
    }
    SetContactPoint(written++, point.position, point.normal, point.force, point.collider,
                    point.body, world_cloud);
    if (link >= 0) {
      SetContactPoint(link_written[link]++, position, normal, force, point.collider, point.body,
                      &(*link_clouds)[link]);
    }
  }
  if (dropped > 0) {
    ROS_WARN_THROTTLE(1.0, "msm_sim: %zu contact points with NaN or Inf left out of the clouds",
                      dropped);
  }
  Shrink(written, world_cloud);
  for (std::size_t l = 0; l < links.size(); ++l) Shrink(link_written[l], &(*link_clouds)[l]);
}

}  // namespace msm_sim::ros_interface
