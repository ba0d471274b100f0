// rostest of the node's per-contact output (contact_points.test): ~contact_points and
// ~links/<link>/pressure at the configured rate, finite, in the documented frames, the
// fingertip's points summing to its wrench. Part of test_msm_sim_node (main is there).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <Eigen/Core>

#include "node_test_support.h"

namespace {

bool Spin(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (done()) return true;
    ros::WallDuration(0.002).sleep();
  }
  return done();
}

// A cloud topic's messages.
struct Clouds {
  explicit Clouds(const std::string& topic) {
    subscriber = handle.subscribe<sensor_msgs::PointCloud2>(
        topic, 1000, [this](const sensor_msgs::PointCloud2::ConstPtr& message) {
          messages.push_back(*message);
        });
  }
  ros::NodeHandle handle;
  ros::Subscriber subscriber;
  std::vector<sensor_msgs::PointCloud2> messages;

  // The node's rate by its stamps, from message `from` on (msm_sim_test::StampedRate).
  double Rate(std::size_t from) const {
    std::vector<ros::Time> stamps;
    for (std::size_t m = from; m < messages.size(); ++m) stamps.push_back(messages[m].header.stamp);
    return msm_sim_test::StampedRate(stamps);
  }
};

// The documented fields, in order, and whether every value is finite; the force sum (N).
void CheckCloud(const sensor_msgs::PointCloud2& cloud, const std::string& frame,
                Eigen::Vector3d* force_sum) {
  ASSERT_EQ(cloud.header.frame_id, frame);
  const std::vector<std::string> names = {"x",        "y",        "z",       "normal_x",
                                          "normal_y", "normal_z", "force_x", "force_y",
                                          "force_z",  "collider", "object"};
  ASSERT_EQ(cloud.fields.size(), names.size());
  for (std::size_t f = 0; f < names.size(); ++f) {
    EXPECT_EQ(cloud.fields[f].name, names[f]);
    EXPECT_EQ(cloud.fields[f].datatype,
              f < 9 ? sensor_msgs::PointField::FLOAT32 : sensor_msgs::PointField::UINT32);
  }
  *force_sum = Eigen::Vector3d::Zero();
  if (cloud.width == 0) return;
  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), n(cloud, "normal_x"),
      f(cloud, "force_x");
  sensor_msgs::PointCloud2ConstIterator<std::uint32_t> object(cloud, "object");
  for (; x != x.end(); ++x, ++n, ++f, ++object) {
    for (int d = 0; d < 3; ++d) {
      ASSERT_TRUE(std::isfinite(x[d]) && std::isfinite(n[d]) && std::isfinite(f[d]));
    }
    EXPECT_NEAR(Eigen::Vector3f(n[0], n[1], n[2]).norm(), 1.0f, 1e-4f);
    EXPECT_EQ(*object, 0u);  // the one object
    *force_sum += Eigen::Vector3d(f[0], f[1], f[2]);
  }
}

// Sends the demo finger's joints to slide_x = 0, slide_z = `z` (m) through /joint_states.
void PublishJoints(ros::Publisher& joints, double z) {
  sensor_msgs::JointState message;
  message.header.stamp = ros::Time::now();
  message.name = {"slide_x", "slide_z"};
  message.position = {0.0, z};
  joints.publish(message);
}

// Checks the clouds from message `from` on (CheckCloud, in `frame`); returns the most points.
std::size_t MostPointsOfCheckedClouds(const Clouds& clouds, std::size_t from,
                                      const std::string& frame) {
  std::size_t points = 0;
  for (std::size_t m = from; m < clouds.messages.size(); ++m) {
    Eigen::Vector3d sum;
    CheckCloud(clouds.messages[m], frame, &sum);
    points = std::max<std::size_t>(points, clouds.messages[m].width);
  }
  return points;
}

// The demo finger pressed 4 mm into the default block (clamped to the table) through
// /joint_states and robot_state_publisher.
TEST(ContactPoints, CloudsAtTheConfiguredRateFiniteInTheirFrames) {
  ros::NodeHandle handle;
  double rate = 0.0;
  ASSERT_TRUE(handle.getParam("/msm_sim/world/publish_rate", rate));
  Clouds world("/msm_sim/contact_points"), tip("/msm_sim/links/fingertip/pressure");
  std::map<double, Eigen::Vector3d> wrenches;  // fingertip wrench by stamp
  ros::Subscriber wrench = handle.subscribe<geometry_msgs::WrenchStamped>(
      "/msm_sim/links/fingertip/wrench", 1000,
      [&](const geometry_msgs::WrenchStamped::ConstPtr& m) {
        wrenches[m->header.stamp.toSec()] =
            Eigen::Vector3d(m->wrench.force.x, m->wrench.force.y, m->wrench.force.z);
      });
  ros::Publisher joints = handle.advertise<sensor_msgs::JointState>("/joint_states", 10);
  ASSERT_TRUE(Spin([&] { return world.messages.size() > 3 && tip.messages.size() > 3; }, 30.0));
  // Press from above (tip at slide_z = -0.089 touches) to 4 mm deep over 1.5 s, then hold.
  for (int k = 0; k <= 150; ++k) {
    PublishJoints(joints, -0.07 + (-0.093 + 0.07) * k / 150.0);
    Spin([] { return false; }, 0.01);
  }
  const std::size_t world_from = world.messages.size(), tip_from = tip.messages.size();
  for (int k = 0; k < 300; ++k) {  // 3 s held
    PublishJoints(joints, -0.093);
    Spin([] { return false; }, 0.01);
  }
  const double world_rate = world.Rate(world_from);
  const double tip_rate = tip.Rate(tip_from);
  std::size_t tip_points = 0;
  double worst_sum = 0.0, tip_force = 0.0;
  const std::size_t world_points = MostPointsOfCheckedClouds(world, world_from, "world");
  for (std::size_t m = tip_from; m < tip.messages.size(); ++m) {
    Eigen::Vector3d sum;
    CheckCloud(tip.messages[m], "fingertip", &sum);
    tip_points = std::max<std::size_t>(tip_points, tip.messages[m].width);
    const auto it = wrenches.find(tip.messages[m].header.stamp.toSec());
    if (it == wrenches.end() || it->second.norm() < 0.1) continue;
    // The link wrench is what the object exerts on the link, like the points' forces.
    worst_sum = std::max(worst_sum, (sum - it->second).norm() / it->second.norm());
    tip_force = std::max(tip_force, it->second.norm());
  }
  std::printf(
      "  ~contact_points at %.2f Hz, ~links/fingertip/pressure at %.2f Hz (configured "
      "%.0f Hz); up to %zu world and %zu fingertip points; fingertip points' sum off its "
      "wrench by %.2g relative at most (wrench up to %.3f N)\n",
      world_rate, tip_rate, rate, world_points, tip_points, worst_sum, tip_force);
  EXPECT_NEAR(world_rate / rate, 1.0, 0.10);
  EXPECT_NEAR(tip_rate / rate, 1.0, 0.10);
  EXPECT_GT(tip_points, 0u);
  EXPECT_GE(world_points, tip_points);  // the fingertip's points are among them
  EXPECT_GT(tip_force, 0.5);
  EXPECT_LT(worst_sum, 1e-4);  // float32 points
}

}  // namespace
