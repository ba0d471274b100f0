// Simulation: the contact report, the wrenches averaged since the last report per object and
// collider (or clamp), robot links' collision elements summed into their link.
#include "simulation.h"

#include <cstdint>
#include <string>
#include <vector>

#include "conversions.h"

namespace msm_sim::ros_interface {
namespace {

// A contact with a collider of no robot link or with a clamp, reported in the world frame.
msm_sim::Contact WorldContact(const std::string& object, const std::string& collider,
                              const std::string& world_frame,
                              const core::ContactWrenchAverage& sum) {
  const core::ContactWrench average = sum.Average();
  msm_sim::Contact contact;
  contact.object = object;
  contact.collider = collider;
  contact.frame_id = world_frame;
  contact.wrench.force = ToVector(average.force);
  contact.wrench.torque = ToVector(average.torque);
  contact.centroid = ToPoint(average.centroid);
  contact.microcollisions = static_cast<std::uint32_t>(sum.microcollisions());
  contact.normal = ToVector(average.normal);
  contact.area = average.area;
  contact.mean_pressure = average.mean_pressure;
  return contact;
}

// A robot link's contact with `object`, reported in the link's frame about its origin;
// `average` is in the world frame about the link origin.
msm_sim::Contact LinkContact(const std::string& object, const RobotColliders::Link& link,
                             const core::ContactWrench& average, long microcollisions) {
  const Eigen::Matrix3d to_link = link.pose.linear().transpose();
  msm_sim::Contact contact;
  contact.object = object;
  contact.collider = link.name;
  contact.frame_id = link.name;
  contact.wrench.force = ToVector(to_link * average.force);
  contact.wrench.torque = ToVector(to_link * average.torque);
  contact.centroid = ToPoint(link.pose.inverse() * average.centroid);
  contact.microcollisions = static_cast<std::uint32_t>(microcollisions);
  contact.normal = ToVector(to_link * average.normal);
  contact.area = average.area;
  contact.mean_pressure = average.mean_pressure;
  return contact;
}

// A link's wrench summed over the objects (world frame, about the link origin), published in the
// link's frame.
geometry_msgs::WrenchStamped LinkWrench(const RobotColliders::Link& link, const ros::Time& stamp,
                                        const Eigen::Vector3d& force,
                                        const Eigen::Vector3d& torque) {
  geometry_msgs::WrenchStamped wrench;
  wrench.header.stamp = stamp;
  wrench.header.frame_id = link.name;
  const Eigen::Matrix3d to_link = link.pose.linear().transpose();
  wrench.wrench.force = ToVector(to_link * force);
  wrench.wrench.torque = ToVector(to_link * torque);
  return wrench;
}

}  // namespace

msm_sim::ContactArray Simulation::Contacts(
    const ros::Time& stamp, std::vector<geometry_msgs::WrenchStamped>* link_wrenches) {
  link_wrenches->clear();
  msm_sim::ContactArray array;
  array.header.stamp = stamp;
  array.header.frame_id = config_.world.frame;
  const std::vector<RobotColliders::Link>& links = robot_->links();
  // Per robot link, summed over objects: force and torque about the link origin (world axes).
  std::vector<Eigen::Vector3d> link_force(links.size(), Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> link_torque(links.size(), Eigen::Vector3d::Zero());
  for (std::size_t o = 0; o < objects_.size(); ++o) {
    const std::vector<core::ContactWrenchAverage> per_link = ReportColliderContacts(o, &array);
    // Robot links report in their own frame, about their origin.
    for (std::size_t l = 0; l < links.size(); ++l) {
      if (per_link[l].microcollisions() == 0) continue;
      const core::ContactWrench average = per_link[l].Average();
      link_force[l] += average.force;
      link_torque[l] += average.torque;
      array.contacts.push_back(
          LinkContact(objects_[o].config.name, links[l], average, per_link[l].microcollisions()));
    }
  }
  for (std::size_t l = 0; l < links.size(); ++l) {
    link_wrenches->push_back(LinkWrench(links[l], stamp, link_force[l], link_torque[l]));
  }
  ResetContactAverages();
  return array;
}

std::vector<core::ContactWrenchAverage> Simulation::ReportColliderContacts(
    std::size_t o, msm_sim::ContactArray* array) const {
  const Object& object = objects_[o];
  const int colliders = world_.num_colliders();
  const std::vector<RobotColliders::Link>& links = robot_->links();
  std::vector<core::ContactWrenchAverage> per_link(links.size());
  for (std::size_t w = 0; w < contact_averages_[o].size(); ++w) {
    const core::ContactWrenchAverage& sum = contact_averages_[o][w];
    if (sum.microcollisions() == 0) continue;
    const int link = static_cast<int>(w) < colliders ? robot_->LinkOfCollider(w) : -1;
    if (link >= 0) {
      // Move the torque from the collision element's origin to the link's.
      per_link[link].AddMoved(
          sum, world_.collider(w).pose.translation() - links[link].pose.translation());
      continue;
    }
    const std::string& collider = static_cast<int>(w) < colliders
                                      ? world_.collider(static_cast<int>(w)).name
                                      : object.clamp_names[w - colliders];
    array->contacts.push_back(WorldContact(object.config.name, collider, config_.world.frame, sum));
  }
  return per_link;
}

}  // namespace msm_sim::ros_interface
