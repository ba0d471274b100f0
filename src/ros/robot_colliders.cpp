#include "robot_colliders.h"

#include <algorithm>
#include <memory>
#include <set>
#include <sstream>

#include <tf2/exceptions.h>
#include <urdf_parser/urdf_parser.h>

#include "conversions.h"
#include "msm_sim/geometry/mesh_import.h"
#include "msm_sim/geometry/solid_mesh.h"

namespace msm_sim::ros_interface {
namespace {

// Gives the collider the twist that takes it from where it is to `end` in `seconds` (the World
// advances colliders with their twists); at `end`, still, if seconds is 0. Never a jump: a
// collider pressing on a body keeps pressing instead of appearing inside it.
void MoveColliderTo(const Eigen::Isometry3d& end, double seconds, core::Collider* collider) {
  collider->linear_velocity.setZero();
  collider->angular_velocity.setZero();
  if (!(seconds > 0.0)) {
    collider->pose = end;
    return;
  }
  const Eigen::Isometry3d& start = collider->pose;
  collider->linear_velocity = (end.translation() - start.translation()) / seconds;
  const Eigen::AngleAxisd turn(end.linear() * start.linear().transpose());
  collider->angular_velocity = turn.axis() * (turn.angle() / seconds);
}

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  result.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
          .normalized()
          .toRotationMatrix();
  return result;
}

// The collider shape of one URDF geometry; throws with the reason it cannot be made.
core::ColliderShape ShapeOf(const urdf::Geometry& geometry) {
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      return core::ColliderShape::Box(Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z));
    }
    case urdf::Geometry::SPHERE:
      return core::ColliderShape::Sphere(static_cast<const urdf::Sphere&>(geometry).radius);
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      return core::ColliderShape::Cylinder(cylinder.radius, cylinder.length);
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      const std::string path = ResolveUri(mesh.filename, "mesh " + mesh.filename);
      core::MeshImportOptions options;
      options.min_extent = 0.0;
      options.max_extent = 1e6;  // checked after the URDF's scale below
      core::TriangleMesh triangles = core::ImportTriangleMesh(path, options).mesh;
      triangles.vertices = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z).asDiagonal() *
                           triangles.vertices;
      return core::ColliderShape::Mesh(std::make_shared<const core::SolidMesh>(triangles));
    }
  }
  throw std::invalid_argument("unknown geometry type");
}

// What in `world` already has the name `name` (a collider such as the ground, or an object), or
// empty.
std::string NameClash(const core::World& world, const std::string& name) {
  for (int c = 0; c < world.num_colliders(); ++c) {
    if (world.collider(c).name == name) return "the collider '" + name + "'";
  }
  for (int b = 0; b < world.num_bodies(); ++b) {
    if (world.body_name(b) == name) return "the object '" + name + "'";
  }
  return {};
}

}  // namespace

void RobotColliders::Problem(const std::string& message) {
  ROS_ERROR("msm_sim: robot: %s", message.c_str());
  problems_.push_back(message);
}

RobotColliders::RobotColliders(const RobotConfig& config, const std::string& description,
                               const std::string& world_frame, double max_distance,
                               core::World* world)
    : config_(config), world_frame_(world_frame), max_distance_(max_distance), world_(world) {
  if (!config.enabled) return;
  const std::string& key = config.description_param;
  if (description.empty()) {
    Problem("no robot description '" + key + "' (the URDF); running without robot colliders");
    return;
  }
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(description);
  if (!model) {
    Problem("'" + key +
            "' is not a valid URDF (see the urdfdom error above); running without robot "
            "colliders");
    return;
  }
  std::vector<std::string> names = config.links;
  if (names.empty()) {
    std::vector<urdf::LinkSharedPtr> all;
    model->getLinks(all);
    for (const auto& link : all) {
      if (!link->collision_array.empty() || link->collision) names.push_back(link->name);
    }
    std::sort(names.begin(), names.end());
  }
  for (const std::string& name : names) AddLink(*model, name);
  ROS_INFO("msm_sim: robot: %d links as colliders", static_cast<int>(links_.size()));
}

void RobotColliders::AddLink(const urdf::ModelInterface& model, const std::string& name) {
  const urdf::LinkConstSharedPtr link = model.getLink(name);
  if (!link) {
    Problem("link '" + name + "' listed in ~robot/links is not in '" + config_.description_param +
            "'; it is left out");
    return;
  }
  const std::string clash = NameClash(*world_, name);
  if (!clash.empty()) {
    Problem("link '" + name + "' has the name of " + clash +
            ", so their contacts could not be told apart; it is left out (rename the link or "
            "the object)");
    return;
  }
  std::vector<urdf::CollisionSharedPtr> collisions = link->collision_array;
  if (collisions.empty() && link->collision) collisions.push_back(link->collision);
  Link entry;
  entry.name = name;
  for (const auto& collision : collisions) {
    if (!collision || !collision->geometry) continue;
    try {
      core::Collider collider;
      collider.name = name;
      collider.shape = ShapeOf(*collision->geometry);
      const auto friction = config_.link_friction.find(name);
      collider.friction =
          friction != config_.link_friction.end() ? friction->second : config_.friction;
      collider.enabled = false;  // until tf gives its pose
      entry.colliders.push_back(world_->AddCollider(collider));
      entry.origins.push_back(ToIsometry(collision->origin));
    } catch (const std::exception& e) {
      Problem("a collision element of link '" + name + "' cannot be used (" + e.what() +
              "); it is left out");
    }
  }
  if (entry.colliders.empty()) {
    ROS_WARN("msm_sim: robot: link '%s' has no usable collision geometry", name.c_str());
    return;
  }
  links_.push_back(std::move(entry));
}

int RobotColliders::LinkOfCollider(int collider) const {
  for (std::size_t l = 0; l < links_.size(); ++l) {
    for (const int c : links_[l].colliders) {
      if (c == collider) return static_cast<int>(l);
    }
  }
  return -1;
}

Eigen::Isometry3d RobotColliders::PoseAt(const tf2::BufferCore& buffer, const std::string& link,
                                         const ros::Time& at,
                                         const geometry_msgs::TransformStamped& latest) const {
  const ros::Time stamp = latest.header.stamp;
  // Static transforms (stamp 0) hold at every time; past the latest sample, the latest.
  if (stamp.isZero() || at.toSec() <= config_.tf_delay) return ToIsometry(latest.transform);
  const ros::Time target = at - ros::Duration(config_.tf_delay);
  if (target >= stamp) return ToIsometry(latest.transform);
  try {
    return ToIsometry(buffer.lookupTransform(world_frame_, link, target).transform);
  } catch (const tf2::TransformException&) {
    return ToIsometry(latest.transform);  // older than the buffer keeps
  }
}

void RobotColliders::Update(const tf2::BufferCore& buffer, const ros::Time& now,
                            const ros::Time& at, double seconds) {
  for (Link& link : links_) {
    const bool live = UpdateLink(buffer, now, at, seconds, &link);
    if (live && !link.live && link.was_live) {
      ROS_INFO("msm_sim: robot: tf for link '%s' is back; its contacts are on", link.name.c_str());
    }
    link.was_live = link.was_live || live;
    link.live = live;
    for (const int c : link.colliders) world_->collider(c).enabled = live;
  }
}

bool RobotColliders::UpdateLink(const tf2::BufferCore& buffer, const ros::Time& now,
                                const ros::Time& at, double seconds, Link* link) {
  geometry_msgs::TransformStamped latest;
  try {
    latest = buffer.lookupTransform(world_frame_, link->name, ros::Time(0));
  } catch (const tf2::TransformException& e) {
    // Before a link's first pose this is start-up (robot_state_publisher not up yet).
    if (link->has_pose) {
      ROS_WARN_THROTTLE(1.0, "msm_sim: robot: no tf for link '%s' (%s); its contacts are off",
                        link->name.c_str(), e.what());
    } else {
      ROS_INFO_THROTTLE(5.0, "msm_sim: robot: waiting for tf of link '%s'", link->name.c_str());
    }
    return false;
  }
  // Static transforms carry stamp 0 and never go stale.
  const ros::Time stamp = latest.header.stamp;
  if (!stamp.isZero() && (now - stamp).toSec() > config_.tf_timeout) {
    if (link->live) {
      ROS_WARN(
          "msm_sim: robot: tf for link '%s' is older than %.2f s; its contacts are off until "
          "tf returns",
          link->name.c_str(), config_.tf_timeout);
    }
    return false;
  }
  // Along tf's own samples, interpolated, tf_delay behind `at`: never ahead of tf (an
  // extrapolated twist once carried a fingertip through a block), never a jump (a link seen for
  // the first time, or again after its contacts were off, is placed at once).
  const Eigen::Isometry3d pose = PoseAt(buffer, link->name, at, latest);
  const double travel = link->live ? seconds : 0.0;
  // An absurd pose never reaches the colliders, whose swept motion would carry it into a
  // contact force: the link is off until tf is sane again (its pose within bounds and still
  // against the last one tf gave), then placed at once.
  const std::string problem = PoseProblem(*link, pose, seconds);
  link->seen = pose;
  link->has_seen = true;
  if (!problem.empty()) {
    ROS_WARN_THROTTLE(1.0,
                      "msm_sim: robot: tf pose of link '%s' refused: %s; its contacts are off "
                      "until tf is sane again",
                      link->name.c_str(), problem.c_str());
    return false;
  }
  link->pose = pose;
  link->stamp = stamp;
  link->has_pose = true;
  for (std::size_t k = 0; k < link->colliders.size(); ++k) {
    MoveColliderTo(pose * link->origins[k], travel, &world_->collider(link->colliders[k]));
  }
  return true;
}

std::string RobotColliders::PoseProblem(const Link& link, const Eigen::Isometry3d& pose,
                                        double seconds) const {
  std::ostringstream problem;
  const double distance = pose.translation().norm();
  if (!pose.matrix().allFinite() || distance > max_distance_) {
    problem << "it lies " << distance
            << " m from the world origin, beyond ~world/max_distance = " << max_distance_ << " m";
  } else if (seconds > 0.0 && link.has_seen) {
    const double speed = (pose.translation() - link.seen.translation()).norm() / seconds;
    if (speed > config_.max_link_speed) {
      problem << "it would move the link at " << speed
              << " m/s, faster than ~robot/max_link_speed = " << config_.max_link_speed << " m/s";
    }
  }
  return problem.str();
}

}  // namespace msm_sim::ros_interface
