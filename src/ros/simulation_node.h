#pragma once
// msm_sim_node: the live ROS front end of Simulation. It only wires parameters, topics, services,
// tf and timers to the simulation (README "msm_sim_node").

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <geometry_msgs/WrenchStamped.h>
#include <msm_sim/ContactForce.h>
#include <msm_sim/SetMaterial.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "runtime_tuning.h"
#include "simulation.h"

namespace msm_sim::ros_interface {

/// The robot description a node's configuration names, from the parameter server (searched
/// upwards from the node's namespace); empty if there is none.
std::string RobotDescriptionParameter(const RobotConfig& config);

class SimulationNode {
 public:
  /// Loads the configuration, builds every object and starts publishing. Throws ConfigError
  /// (one line naming the parameter) for a configuration it cannot run.
  SimulationNode(ros::NodeHandle handle, ros::NodeHandle private_handle);

 private:
  void OnTimer(const ros::TimerEvent& event);
  void OnWallTimer(const ros::WallTimerEvent& event);
  /// world/publish_clock: steps a publication period (or what the wall clock allows, with
  /// real_time), publishing /clock every kClockPeriod of simulated time.
  void OnClockTimer(const ros::WallTimerEvent& event);
  void Publish(const ros::Time& stamp);
  void OnApplyForce(const msm_sim::ContactForce::ConstPtr& message);
  void OnWrench(std::size_t input, const geometry_msgs::WrenchStamped::ConstPtr& message);
  bool OnReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnPause(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnResume(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnSetMaterial(msm_sim::SetMaterial::Request& request,
                     msm_sim::SetMaterial::Response& response);
  /// (Re)starts the stepping and publication timer for config().world's rate and pacing.
  void StartTimer();
  /// ~reconfigure/world: a new publication rate and pacing; "" or why it was refused.
  std::string SetPublishing(double publish_rate, bool real_time);
  /// ROS_WARN for a dropped message, throttled to one a second per kind of problem.
  void WarnDropped(const std::string& source, const std::string& reason);

  ros::NodeHandle handle_, private_handle_;
  std::unique_ptr<Simulation> simulation_;

  ros::Publisher markers_, contacts_, state_, diagnostics_;
  ros::Publisher contact_points_;
  ros::Publisher clock_;                        // /clock, with world/publish_clock
  std::vector<ros::Publisher> link_wrenches_;   // ~links/<link>/wrench, per robot link
  std::vector<ros::Publisher> link_pressures_;  // ~links/<link>/pressure, per robot link
  ros::Subscriber apply_force_;
  std::vector<ros::Subscriber> wrench_subscribers_;
  ros::ServiceServer reset_, pause_, resume_, set_material_;
  ros::Timer timer_;
  ros::WallTimer wall_timer_;
  std::unique_ptr<RuntimeTuning> tuning_;  // after simulation_, which it uses
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  std::map<std::string, ros::WallTime> last_warning_;  // per kind of dropped message

  bool paused_ = false;
  ros::Time origin_;           // ROS time at which the simulation time was 0 (real-time pacing)
  ros::WallTime wall_origin_;  // wall time at which the simulation time was 0 (publish_clock)
  ros::Time last_frame_stamp_;
  bool started_ = false;
  ros::WallTime last_publish_wall_;
};

}  // namespace msm_sim::ros_interface
