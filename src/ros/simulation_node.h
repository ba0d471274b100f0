#pragma once
// msm_sim_node: the ROS layer over the core World. It only converts parameters and messages;
// the physics lives in the core library (README "msm_sim_node").

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

#include "msm_sim/core/surface_skin.h"
#include "msm_sim/core/world.h"
#include "robot_colliders.h"
#include "simulation_config.h"

namespace msm_sim::node {

class SimulationNode {
 public:
  /// Loads the configuration, builds every object and starts publishing. Throws ConfigError
  /// (one line naming the parameter) for a configuration it cannot run.
  SimulationNode(ros::NodeHandle handle, ros::NodeHandle private_handle);

 private:
  struct Object {
    ObjectConfig config;
    int body = 0;
    std::shared_ptr<const core::SurfaceSkin> skin;
    std::vector<std::string> clamp_names;  // wrench index = colliders + position here
    Eigen::VectorXd rest_edge_lengths;     // of the surface's triangle edges, for colouring
  };
  // Impulse sums between publications, per object, per collider then clamp.
  struct ContactSum {
    Eigen::Vector3d force_time = Eigen::Vector3d::Zero();
    Eigen::Vector3d torque_time = Eigen::Vector3d::Zero();
    Eigen::Vector3d weighted_centroid = Eigen::Vector3d::Zero();
    double weight = 0.0;
    long microcollisions = 0;
  };
  struct WrenchInput {
    WrenchInputConfig config;
    int object = 0;
    ros::Subscriber subscriber;
    bool active = false;
    ros::Time received;
    Eigen::Vector3d point, force, torque;  // world frame
  };

  void OnTimer(const ros::TimerEvent& event);
  void OnWallTimer(const ros::WallTimerEvent& event);
  /// Steps `seconds` of simulation, stopping early at `deadline` (zero: none).
  void Advance(double seconds, const ros::WallTime& deadline);
  void Publish(const ros::Time& stamp);
  void PublishMarkers(const ros::Time& stamp);
  void PublishContacts(const ros::Time& stamp);
  void PublishState(const ros::Time& stamp);
  void PublishFrames(const ros::Time& stamp);
  void PublishDiagnostics(const ros::Time& stamp);
  void OnApplyForce(const msm_sim::ContactForce::ConstPtr& message);
  void OnWrench(std::size_t input, const geometry_msgs::WrenchStamped::ConstPtr& message);
  bool OnReset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnPause(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnResume(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);
  bool OnSetMaterial(msm_sim::SetMaterial::Request& request,
                     msm_sim::SetMaterial::Response& response);
  int FindObject(const std::string& name) const;
  /// The transform from `frame` to the world frame at `stamp` (latest if zero); false if tf
  /// cannot give it.
  bool LookUp(const std::string& frame, const ros::Time& stamp, Eigen::Isometry3d* transform,
              std::string* error) const;
  core::BodyOptions BodyOptionsOf(const ObjectConfig& config) const;

  ros::NodeHandle handle_, private_handle_;
  SimulationConfig config_;
  core::World world_;
  std::vector<Object> objects_;
  std::vector<std::vector<ContactSum>> contact_sums_;
  double contact_time_ = 0.0;  // s of simulation summed into contact_sums_
  std::vector<WrenchInput> wrench_inputs_;
  std::unique_ptr<RobotColliders> robot_;
  std::vector<ros::Publisher> link_wrenches_;  // ~links/<link>/wrench, per robot link

  ros::Publisher markers_, contacts_, state_, diagnostics_;
  ros::Subscriber apply_force_;
  ros::ServiceServer reset_, pause_, resume_, set_material_;
  ros::Timer timer_;
  ros::WallTimer wall_timer_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  bool paused_ = false;
  ros::Time origin_;  // ROS time at which the simulation time was 0 (real-time pacing)
  ros::Time last_frame_stamp_;
  bool started_ = false;
  long steps_ = 0, rejected_steps_ = 0, steps_since_publish_ = 0;
  int last_substeps_ = 0;
  double step_wall_seconds_ = 0.0;  // since the last publication
  double simulated_since_publish_ = 0.0;
  ros::WallTime last_publish_wall_;
  std::string last_rejection_;
};

}  // namespace msm_sim::node
