#include "msm_sim/dynamics/contact_point_average.h"

namespace msm_sim::core {

void ContactPointAverage::Add(int body, int num_nodes, const std::vector<ContactPoint>& points) {
  if (static_cast<int>(first_.size()) <= body) first_.resize(body + 1);
  if (static_cast<int>(first_[body].size()) < num_nodes) first_[body].resize(num_nodes, -1);
  for (const ContactPoint& contact : points) {
    Sum& sum = sums_[Find(body, contact.collider, contact.node)];
    const Eigen::Vector3d impulse = contact.impulse();
    const double weight = impulse.norm();
    sum.weighted_point += weight * contact.point;
    sum.weight += weight;
    sum.normal_impulse += contact.normal_impulse * contact.normal;
    sum.impulse += impulse;
  }
}

int ContactPointAverage::Find(int body, int collider, NodeIndex node) {
  int previous = -1;
  for (int k = first_[body][node]; k >= 0; k = sums_[k].next) {
    if (sums_[k].collider == collider) return k;
    previous = k;
  }
  const int added = static_cast<int>(sums_.size());
  sums_.push_back({body, collider, node, -1, Eigen::Vector3d::Zero(), 0.0, Eigen::Vector3d::Zero(),
                   Eigen::Vector3d::Zero()});
  (previous < 0 ? first_[body][node] : sums_[previous].next) = added;
  return added;
}

void ContactPointAverage::Reset() {
  for (const Sum& sum : sums_) first_[sum.body][sum.node] = -1;
  sums_.clear();
  seconds_ = 0.0;
}

ContactPointAverage::Point ContactPointAverage::Average(std::size_t k) const {
  const Sum& sum = sums_[k];
  Point point;
  point.body = sum.body;
  point.collider = sum.collider;
  point.node = sum.node;
  point.position =
      sum.weight > 0.0 ? Eigen::Vector3d(sum.weighted_point / sum.weight) : Eigen::Vector3d::Zero();
  const double normal_norm = sum.normal_impulse.norm();
  point.normal = normal_norm > 0.0 ? Eigen::Vector3d(sum.normal_impulse / normal_norm)
                                   : Eigen::Vector3d::Zero();
  point.force = sum.impulse / seconds_;
  return point;
}

}  // namespace msm_sim::core
