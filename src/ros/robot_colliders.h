#pragma once
// A robot's links as kinematic colliders: collision geometry from the URDF, poses from tf2,
// each moved from where it is to its tf pose over the next simulated step (docs/node.md, "Robot
// in the loop").

#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <tf2/buffer_core.h>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/world.h"

namespace urdf {
class ModelInterface;
}  // namespace urdf
#include "simulation_config.h"

namespace msm_sim::ros_interface {

class RobotColliders {
 public:
  struct Link {
    std::string name;
    std::vector<int> colliders;              // World collider indices
    std::vector<Eigen::Isometry3d> origins;  // collision origin in the link frame, per collider
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // link in the world frame, latest
    ros::Time stamp;                                         // of the pose (0: static)
    bool has_pose = false;
    bool live = false;      // tf is fresh: contacts on
    bool was_live = false;  // has been live before (for the "is back" message)
    // The pose tf gave last, taken or refused: a link is taken again only once its tf pose
    // moves no faster than robot/max_link_speed from it.
    Eigen::Isometry3d seen = Eigen::Isometry3d::Identity();
    bool has_seen = false;
  };

  /// Adds a collider per collision element of the selected links of the URDF `description`
  /// (empty: none was found). A missing or malformed description, an unknown link, an unreadable
  /// mesh or a link with the name of a collider or object already in `world` is reported with
  /// ROS_ERROR and left out: the simulation runs on without it. Link poses farther than
  /// `max_distance` (m) from the world origin are refused (Update).
  RobotColliders(const RobotConfig& config, const std::string& description,
                 const std::string& world_frame, double max_distance, core::World* world);

  /// Sends the links' colliders towards their tf poses at ROS time `at` minus robot/tf_delay
  /// (interpolated between tf's samples; the latest pose when `at` is past it), to be reached
  /// over the next `seconds` (>= 0) of simulation: each collider moves from where it is with
  /// the twist that takes it there in that time, never jumping. A link seen for the first time,
  /// or again after its contacts were off, is placed at once. A link whose latest transform is
  /// missing or older than tf_timeout at `now` gets its contacts turned off (throttled warning)
  /// until tf returns; so does one whose pose lies beyond max_distance or would move it faster
  /// than robot/max_link_speed, and the colliders never take that pose.
  void Update(const tf2::BufferCore& buffer, const ros::Time& now, const ros::Time& at,
              double seconds);

  const std::vector<Link>& links() const { return links_; }
  /// The link a World collider belongs to, or -1.
  int LinkOfCollider(int collider) const;
  /// What could not be used at start-up, one line each (also logged with ROS_ERROR).
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  RobotConfig config_;
  std::string world_frame_;
  double max_distance_;
  core::World* world_;
  std::vector<Link> links_;
  std::vector<std::string> problems_;
  void Problem(const std::string& message);
  /// Adds link `name` of `model` with a collider per collision element, or reports why not.
  void AddLink(const urdf::ModelInterface& model, const std::string& name);
  /// Update for one link; returns whether its contacts are on for the next step.
  bool UpdateLink(const tf2::BufferCore& buffer, const ros::Time& now, const ros::Time& at,
                  double seconds, Link* link);
  /// Empty if the link may take `pose`, `seconds` after the pose tf gave last (0: no speed
  /// check); else why not.
  std::string PoseProblem(const Link& link, const Eigen::Isometry3d& pose, double seconds) const;
  /// The link's pose at `at` - tf_delay, or `latest` (its latest transform) when that time is
  /// past it, before the buffer's oldest sample, or the transform is static.
  Eigen::Isometry3d PoseAt(const tf2::BufferCore& buffer, const std::string& link,
                           const ros::Time& at,
                           const geometry_msgs::TransformStamped& latest) const;
};

}  // namespace msm_sim::ros_interface
