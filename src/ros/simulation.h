#pragma once
// The simulation a node (live) or msm_replay (offline) runs: the configured objects and robot
// in a core World, the conversion of input messages into forces and of the state into output
// messages. It holds no publishers, subscribers or timers, so both front ends run the same code
// and get the same outputs from the same inputs.
//
// simulation.cpp builds it and takes inputs and steps, simulation_outputs.cpp converts the state
// into output messages, simulation_contacts.cpp reports the contacts.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <msm_sim/ContactArray.h>
#include <msm_sim/ContactForce.h>
#include <ros/time.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <tf2/buffer_core.h>
#include <visualization_msgs/MarkerArray.h>

#include "msm_sim/dynamics/contact_point_average.h"
#include "msm_sim/dynamics/contact_wrench_average.h"
#include "msm_sim/dynamics/world.h"
#include "msm_sim/geometry/surface_skin.h"
#include "msm_sim/geometry/surface_strain.h"
#include "robot_colliders.h"
#include "simulation_config.h"

namespace msm_sim::ros_interface {

class Simulation {
 public:
  /// Builds every object and the robot (from the URDF text `robot_description`; empty: none
  /// given). Throws ConfigError for a configuration it cannot run.
  Simulation(const SimulationConfig& config, const std::string& robot_description);

  const SimulationConfig& config() const { return config_; }
  double time() const { return world_.time(); }

  // Inputs. Each returns an empty string when the message was used, else why it was dropped.
  std::string ApplyForce(const msm_sim::ContactForce& message, const tf2::BufferCore& tf);
  /// Holds the wrench on wrench input `input` (an index into config().wrench_inputs; throws
  /// std::out_of_range otherwise) until the next message, or for 0.5 s of `now` without one.
  std::string SetWrench(std::size_t input, const geometry_msgs::WrenchStamped& message,
                        const ros::Time& now, const tf2::BufferCore& tf);
  /// Places the robot's links at their tf poses of `now` (RobotColliders::Update over no time):
  /// what a paused simulation shows.
  void PlaceRobot(const tf2::BufferCore& tf, const ros::Time& now);
  /// Steps `seconds` of simulation (whole time steps), stopping early after `deadline` (zero:
  /// none); `now` (ROS time) ages the held wrench inputs and the robot's tf. With `tf`, before
  /// each step the robot's links move towards their tf poses at ROS time `robot_origin` plus
  /// the step's end time (RobotColliders::Update): the robot follows tf's trajectory in
  /// simulated time, however fast the simulation runs.
  void Advance(double seconds, const ros::Time& now, const ros::WallTime& deadline,
               const tf2::BufferCore* tf = nullptr, const ros::Time& robot_origin = ros::Time());
  void Reset();
  /// Recalibrates an object; returns an empty string or why it was refused.
  std::string SetMaterial(const std::string& object, double youngs, double poisson, double density,
                          double damping, double friction, std::string* described);

  // Outputs, stamped `stamp`. Contacts and link wrenches average everything since the last call
  // of Contacts (which then starts a new interval).
  visualization_msgs::MarkerArray Markers(const ros::Time& stamp) const;
  msm_sim::ContactArray Contacts(const ros::Time& stamp,
                                 std::vector<geometry_msgs::WrenchStamped>* link_wrenches);
  /// The contact points since the last Contacts, merged per object, collider and node (forces
  /// averaged over the interval): every one in the world frame (~contact_points) and, per
  /// robot link (in robot().links() order), the link's in its frame (~links/<link>/pressure).
  /// Call before Contacts, which starts a new interval. Points with NaN or Inf are left out
  /// with a throttled warning.
  void ContactPointClouds(const ros::Time& stamp, sensor_msgs::PointCloud2* world_cloud,
                          std::vector<sensor_msgs::PointCloud2>* link_clouds) const;
  /// Every node of every object (the ~state topic), with an `object` index field.
  sensor_msgs::PointCloud2 NodeCloud(const ros::Time& stamp) const;
  std::vector<geometry_msgs::TransformStamped> Frames(const ros::Time& stamp) const;
  /// `wall_seconds`: wall time since the last call, for the real-time factor. Without
  /// `timing` the wall-clock entries (step time, real-time factor) are left out, so that an
  /// offline replay's outputs depend on its inputs only.
  diagnostic_msgs::DiagnosticArray Diagnostics(const ros::Time& stamp, double wall_seconds,
                                               bool paused, bool timing = true);

  const RobotColliders& robot() const { return *robot_; }
  std::size_t num_objects() const { return objects_.size(); }
  /// Object `index`'s configuration as it is now (~set_material changes the material).
  const ObjectConfig& object_config(std::size_t index) const { return objects_.at(index).config; }
  /// Sets the publication rate (Hz, finite, > 0) and real-time pacing the node reads from
  /// config().world; returns an empty string or why it was refused (then nothing changed).
  std::string SetPublishing(double publish_rate, bool real_time);

 private:
  struct Object {
    ObjectConfig config;
    int body = 0;
    std::shared_ptr<const core::SurfaceSkin> skin;
    core::SurfaceStrain strain;            // of the skin's surface, for colouring
    std::vector<std::string> clamp_names;  // wrench index = colliders + position here
  };
  struct WrenchInput {
    WrenchInputConfig config;
    int object = 0;
    bool active = false;
    ros::Time received;
    Eigen::Vector3d point, force, torque;  // world frame
  };

  // Construction (simulation.cpp).
  void AddGround();
  /// Builds object `config_.objects[index]` into the World. Throws ConfigError.
  void AddObject(std::size_t index);
  int FindObject(const std::string& name) const;
  bool LookUp(const tf2::BufferCore& tf, const std::string& frame, const ros::Time& stamp,
              Eigen::Isometry3d* transform, std::string* error) const;
  core::BodyOptions BodyOptionsOf(const ObjectConfig& config) const;

  // Stepping (simulation.cpp).
  /// Applies the wrench inputs to their objects for the next step; those older than the hold
  /// time at `now` turn inactive instead.
  void ApplyHeldWrenches(const ros::Time& now);
  /// Adds the wrenches of the accepted step of `dt` seconds to the contact averages.
  void AddStepContacts(double dt);
  void ResetContactAverages();

  // Outputs (simulation_outputs.cpp): one object's markers, stamped by `header`.
  visualization_msgs::Marker SurfaceMarker(const Object& object,
                                           const std_msgs::Header& header) const;
  visualization_msgs::Marker NodeMarker(const Object& object, const std_msgs::Header& header) const;
  visualization_msgs::Marker SpringMarker(const Object& object,
                                          const std_msgs::Header& header) const;

  // Contacts (simulation_contacts.cpp).
  /// Appends object `object`'s contacts with the colliders that belong to no robot link and
  /// with its clamps to `array`; returns the averages of its robot links' contacts (per link,
  /// about the link origin, world axes).
  std::vector<core::ContactWrenchAverage> ReportColliderContacts(
      std::size_t object, msm_sim::ContactArray* array) const;

  SimulationConfig config_;
  core::World world_;
  std::vector<Object> objects_;
  std::unique_ptr<RobotColliders> robot_;
  std::vector<WrenchInput> wrench_inputs_;
  // Per object, per wrench (World colliders, then the object's clamps): the average since the
  // last Contacts.
  std::vector<std::vector<core::ContactWrenchAverage>> contact_averages_;
  // The contact points since the last Contacts (body = object index).
  core::ContactPointAverage contact_points_;
  long steps_ = 0, rejected_steps_ = 0, steps_since_report_ = 0;
  int last_substeps_ = 0;
  double step_wall_seconds_ = 0.0, simulated_since_report_ = 0.0;
  std::string last_rejection_;
};

}  // namespace msm_sim::ros_interface
