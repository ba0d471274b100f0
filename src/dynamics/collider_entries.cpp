// Penetration recovery of a collider that appears with border node centres inside it (docs/
// physics.md §7.2, "A collider that appears inside a body"): it is moved back out of the body
// until no collision sphere touches it and pressed back in, so the body meets it as it would a
// press instead of having its nodes pushed out through whichever face is nearest.
#include "dynamics/collider_entries.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dynamics/recovery_speed.h"

namespace msm_sim::core::internal {
namespace {

// Sphere tracing gives up after this many steps (a collider that cannot be cleared along the
// way out, e.g. one enclosed by a body); the nodes are then recovered one by one as before.
constexpr int kMaxTraceSteps = 64;

// An entry this close to the collider's pose (m) is over: the contacts' own recovery slop is
// larger.
constexpr double kFinishedEntry = 1e-7;

}  // namespace

double ColliderEntries::DeepestBorderOverlap(const Collider& collider,
                                             const Eigen::Isometry3d& pose, bool centres) const {
  Eigen::Vector3d lo, hi;
  collider.shape.Bounds(&lo, &hi);
  const Eigen::Isometry3d inverse = pose.inverse();
  double deepest = -std::numeric_limits<double>::infinity();
  for (const Body& body : world_.bodies) {
    for (std::size_t k = 0; k < body.border.nodes.size(); ++k) {
      const double reach = centres ? 0.0 : body.border.radii[k];
      const Eigen::Vector3d local = inverse * body.state.positions.col(body.border.nodes[k]);
      if ((local.array() < lo.array() - reach).any() ||
          (local.array() > hi.array() + reach).any()) {
        continue;
      }
      Eigen::Vector3d normal, closest;
      deepest = std::max(deepest, reach - collider.shape.SignedDistance(local, &normal, &closest));
    }
  }
  return deepest;
}

Eigen::Vector3d ColliderEntries::WayOutOfBodies(const Collider& collider,
                                                const Eigen::Isometry3d& pose) const {
  // A border node's star is one-sided: the mean unit vector to its spring neighbours points
  // into its body, so minus its sum over the node centres inside the collider points out.
  const Eigen::Isometry3d inverse = pose.inverse();
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (const Body& body : world_.bodies) {
    const Model& model = *body.model;
    std::vector<char> inside(static_cast<std::size_t>(model.num_nodes()), 0);
    bool any = false;
    for (const NodeIndex node : body.border.nodes) {
      Eigen::Vector3d normal, closest;
      const Eigen::Vector3d local = inverse * body.state.positions.col(node);
      if (collider.shape.SignedDistance(local, &normal, &closest) < 0.0) {
        inside[static_cast<std::size_t>(node)] = 1;
        any = true;
      }
    }
    if (!any) continue;
    const Eigen::Matrix3Xd& x = body.state.positions;
    for (int s = 0; s < model.num_springs(); ++s) {
      const NodeIndex a = model.spring_node_a()[s], b = model.spring_node_b()[s];
      if (!inside[static_cast<std::size_t>(a)] && !inside[static_cast<std::size_t>(b)]) continue;
      const Eigen::Vector3d d = x.col(b) - x.col(a);
      const double length = d.norm();
      if (length <= 0.0) continue;
      if (inside[static_cast<std::size_t>(a)]) out -= d / length;
      if (inside[static_cast<std::size_t>(b)]) out += d / length;
    }
  }
  const double norm = out.norm();
  return norm > 0.0 ? Eigen::Vector3d(out / norm) : Eigen::Vector3d::Zero();
}

double ColliderEntries::DistanceToClear(const Collider& collider, const Eigen::Isometry3d& pose,
                                        const Eigen::Vector3d& direction, double from) const {
  // Sphere tracing along the way out: moving the collider by w changes no node's signed
  // distance by more than w, so a step of the deepest overlap never passes the first clear
  // pose.
  Eigen::Vector3d lo, hi;
  collider.shape.Bounds(&lo, &hi);
  double largest_radius = 0.0;
  for (const Body& body : world_.bodies) {
    for (const double r : body.border.radii) largest_radius = std::max(largest_radius, r);
  }
  const double limit = from + (hi - lo).norm() + 2.0 * largest_radius;
  double distance = from;
  for (int step = 0; step < kMaxTraceSteps && distance <= limit; ++step) {
    Eigen::Isometry3d moved = pose;
    moved.pretranslate(distance * direction);
    const double overlap = DeepestBorderOverlap(collider, moved, false);
    if (overlap <= 0.0) return distance;
    distance += std::max(overlap, 1e-6 * largest_radius);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::vector<Eigen::Isometry3d> ColliderEntries::Begin(double dt,
                                                      const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Isometry3d> entered = poses;
  entries_.resize(world_.colliders.size());
  for (std::size_t c = 0; c < world_.colliders.size(); ++c) {
    Collider& collider = world_.colliders[c];
    ColliderEntry& entry = entries_[c];
    entry.user_velocity = collider.linear_velocity;
    Eigen::Vector3d lo, hi;
    if (!collider.enabled || world_.options.penetration_max_speed <= 0.0 ||
        !collider.shape.Bounds(&lo, &hi)) {
      entry.depth_after = 0.0;  // dropped, once the step is accepted
      continue;
    }
    // The entry at this step's start; entry.depth itself moves on only if the step is accepted.
    double depth = entry.depth;
    Eigen::Isometry3d pose = poses[c];
    pose.pretranslate(depth * entry.direction);
    if (DeepestBorderOverlap(collider, pose, true) > 0.0) {
      // Node centres inside: (further) out along the way out of the bodies, to where no
      // collision sphere touches the collider.
      if (depth <= 0.0) entry.direction = WayOutOfBodies(collider, pose);
      const double clear = entry.direction.isZero(0.0)
                               ? std::numeric_limits<double>::quiet_NaN()
                               : DistanceToClear(collider, poses[c], entry.direction, depth);
      if (std::isfinite(clear)) depth = clear;
    }
    entry.depth_after = depth;
    if (depth <= 0.0) continue;
    // Pressed back in at the recovery's speed: min(max speed, depth / recovery time).
    entry.depth_after = std::max(0.0, depth - dt * RecoverySpeed(world_.options, depth));
    if (entry.depth_after < kFinishedEntry) entry.depth_after = 0.0;
    entered[c].pretranslate(depth * entry.direction);
    collider.linear_velocity += (entry.depth_after - depth) / dt * entry.direction;
  }
  return entered;
}

void ColliderEntries::End(bool accepted) {
  for (std::size_t c = 0; c < entries_.size(); ++c) {
    ColliderEntry& entry = entries_[c];
    world_.colliders[c].linear_velocity = entry.user_velocity;
    if (accepted) entry.depth = entry.depth_after;
  }
}

}  // namespace msm_sim::core::internal
