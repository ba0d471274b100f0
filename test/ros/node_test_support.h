#pragma once
// What the rostests of msm_sim_node share (test_msm_sim_node's sources): spinning until a
// condition holds, and a listener to the node's outputs that can also push on its objects.
#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/Point.h>
#include <msm_sim/ContactArray.h>
#include <msm_sim/ContactForce.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <Eigen/Core>

namespace msm_sim_test {

/// Texts that must appear in the node's ROS_ERROR messages (the --expect=TEXT arguments main
/// collects).
extern std::vector<std::string> g_expected_errors;

// Spins until `done` holds or `seconds` of wall time pass; returns done().
inline bool WaitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (done()) return true;
    ros::WallDuration(0.002).sleep();
  }
  return done();
}

// The rate (Hz) a topic is published at by the node's own stamps: 1 / the median interval
// between consecutive stamps (0 for fewer than two). Not arrivals counted by the wall clock: on a
// machine another build keeps busy, deliveries bunch and a late timer tick shortens the next
// interval, while the median stays the node's period.
inline double StampedRate(const std::vector<ros::Time>& stamps) {
  std::vector<double> intervals;
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    intervals.push_back((stamps[i] - stamps[i - 1]).toSec());
  }
  if (intervals.empty()) return 0.0;
  const auto middle = intervals.begin() + intervals.size() / 2;
  std::nth_element(intervals.begin(), middle, intervals.end());
  return *middle > 0.0 ? 1.0 / *middle : 0.0;
}

// Listens to the node's outputs.
class NodeOutputs {
 public:
  NodeOutputs() {
    contacts_ = handle_.subscribe("/msm_sim/contacts", 1000, &NodeOutputs::OnContacts, this);
    diagnostics_ = handle_.subscribe("/diagnostics", 100, &NodeOutputs::OnDiagnostics, this);
    state_ = handle_.subscribe("/msm_sim/state", 10, &NodeOutputs::OnState, this);
    rosout_ = handle_.subscribe("/rosout", 1000, &NodeOutputs::OnLog, this);
    force_ = handle_.advertise<msm_sim::ContactForce>("/msm_sim/apply_force", 10);
  }

  // Simulated time reported by the node's diagnostics (s), < 0 before the first report.
  double simulated_time = -1.0;
  std::vector<msm_sim::ContactArray> contacts;
  sensor_msgs::PointCloud2 state;
  bool has_state = false;
  std::vector<std::string> warnings, infos;
  std::set<std::string> robot_problems;  // from the diagnostics

  bool WaitForNode() {
    return WaitFor([&] { return simulated_time >= 0.0 && force_.getNumSubscribers() > 0; }, 30.0);
  }
  // Waits until the simulation has advanced by `seconds` of simulated time.
  bool WaitSimulated(double seconds) {
    const double target = simulated_time + seconds;
    return WaitFor([&] { return simulated_time >= target; }, 60.0);
  }
  void Push(const std::string& object, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
            double radius, double duration, const std::string& frame = "world") {
    msm_sim::ContactForce message;
    message.header.frame_id = frame;
    message.object = object;
    message.point.x = point.x();
    message.point.y = point.y();
    message.point.z = point.z();
    message.force.x = force.x();
    message.force.y = force.y();
    message.force.z = force.z();
    message.radius = radius;
    message.duration = duration;
    force_.publish(message);
  }
  // Mean force on `collider` over the last `count` contact messages.
  Eigen::Vector3d MeanForce(const std::string& collider, std::size_t count) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    const std::size_t first = contacts.size() > count ? contacts.size() - count : 0;
    for (std::size_t m = first; m < contacts.size(); ++m) {
      for (const msm_sim::Contact& c : contacts[m].contacts) {
        if (c.collider == collider) {
          sum += Eigen::Vector3d(c.wrench.force.x, c.wrench.force.y, c.wrench.force.z);
        }
      }
    }
    return sum / static_cast<double>(contacts.size() - first);
  }
  std::vector<Eigen::Vector3d> Points() const {
    std::vector<Eigen::Vector3d> points;
    sensor_msgs::PointCloud2ConstIterator<float> x(state, "x"), y(state, "y"), z(state, "z");
    for (; x != x.end(); ++x, ++y, ++z) points.emplace_back(*x, *y, *z);
    return points;
  }

 private:
  void OnContacts(const msm_sim::ContactArray::ConstPtr& message) { contacts.push_back(*message); }
  void OnDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& message) {
    for (const auto& status : message->status) {
      for (const auto& entry : status.values) {
        if (entry.key == "simulated time [s]") simulated_time = std::stod(entry.value);
        if (entry.key.rfind("robot problem", 0) == 0) robot_problems.insert(entry.value);
      }
    }
  }
  void OnState(const sensor_msgs::PointCloud2::ConstPtr& message) {
    state = *message;
    has_state = true;
  }
  void OnLog(const rosgraph_msgs::Log::ConstPtr& message) {
    if (message->level == rosgraph_msgs::Log::WARN && message->name == "/msm_sim") {
      warnings.push_back(message->msg);
    }
    if (message->level == rosgraph_msgs::Log::INFO && message->name == "/msm_sim") {
      infos.push_back(message->msg);
    }
  }

  ros::NodeHandle handle_;
  ros::Subscriber contacts_, diagnostics_, state_, rosout_;
  ros::Publisher force_;
};

inline bool Finite(const geometry_msgs::Point& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace msm_sim_test
