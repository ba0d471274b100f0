// Penetration recovery of a body found with border node centres inside another (docs/physics.md
// §7.2, "A body found inside another"): its pair contacts see it moved out of the other body
// until no collision spheres touch and pressed back in at the recovery's speed. Node by node the
// pairs cannot resolve such an overlap: three spacings deep a body's outer layer is out of reach
// of the other's border nodes, and coincident nodes have no line between them.
#include "dynamics/body_entries.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dynamics/pair_contacts.h"
#include "dynamics/recovery_speed.h"
#include "geometry/spatial_hash_grid.h"

namespace msm_sim::core::internal {
namespace {

// An entry this close to the body (m) is over: the pairs' own recovery slop is larger.
constexpr double kFinishedEntry = 1e-7;

// The bounding box of a body's border nodes moved by offset (m).
Eigen::AlignedBox3d BorderBox(const Body& body, const Eigen::Vector3d& offset) {
  Eigen::AlignedBox3d box;
  for (const NodeIndex node : body.border.nodes)
    box.extend(body.state.positions.col(node) + offset);
  return box;
}

bool HasConstrainedNodes(const Body& body) {
  return std::any_of(body.constrained.begin(), body.constrained.end(), [](char c) { return c; });
}

}  // namespace

void BodyEntries::Begin(double dt) {
  dt_ = dt;
  const int count = static_cast<int>(world_.bodies.size());
  if (static_cast<int>(entries_.size()) != count)
    entries_.assign(static_cast<std::size_t>(count), BodyEntry{});
  const bool recovering = world_.options.penetration_max_speed > 0.0;
  for (BodyEntry& entry : entries_) entry.step_depth = recovering ? entry.depth : 0.0;
  for (int a = 0; a < count && recovering; ++a) {
    for (int b = a + 1; b < count; ++b) EnterIfInside(a, b);
  }
  for (int b = 0; b < count; ++b) {
    BodyEntry& entry = entries_[static_cast<std::size_t>(b)];
    Body& body = world_.bodies[static_cast<std::size_t>(b)];
    body.contact_offset.setZero();
    body.contact_offset_velocity.setZero();
    entry.depth_after = 0.0;  // dropped, once the step is accepted
    if (entry.step_depth <= 0.0) continue;
    // Pressed back in at the recovery's speed: min(max speed, depth / recovery time).
    entry.depth_after =
        std::max(0.0, entry.step_depth - dt * RecoverySpeed(world_.options, entry.step_depth));
    if (entry.depth_after < kFinishedEntry) entry.depth_after = 0.0;
    body.contact_offset = entry.step_depth * entry.direction;
    body.contact_offset_velocity = (entry.depth_after - entry.step_depth) / dt * entry.direction;
  }
}

void BodyEntries::EnterIfInside(int a, int b) {
  const int entering = Entering(a, b);
  const int other = entering == a ? b : a;
  BodyEntry& entry = entries_[static_cast<std::size_t>(entering)];
  if (entry.step_depth > 0.0 && entry.other != other) return;  // one entry at a time
  if (!Overlapping(entering, entry.step_depth * entry.direction, other)) return;
  // Centres inside: (further) out along the way out, to where no collision spheres touch.
  if (entry.step_depth <= 0.0) {
    entry.other = other;
    entry.direction = WayOut(entering, other);
  }
  entry.step_depth = DistanceToClear(entering, other, entry.direction, entry.step_depth);
}

void BodyEntries::Place(double tau) {
  for (std::size_t b = 0; b < entries_.size() && b < world_.bodies.size(); ++b) {
    const BodyEntry& entry = entries_[b];
    if (entry.step_depth <= 0.0) continue;
    world_.bodies[b].contact_offset =
        (entry.step_depth + (entry.depth_after - entry.step_depth) * tau / dt_) * entry.direction;
  }
}

void BodyEntries::End(bool accepted) {
  for (std::size_t b = 0; b < entries_.size() && b < world_.bodies.size(); ++b) {
    world_.bodies[b].contact_offset.setZero();
    world_.bodies[b].contact_offset_velocity.setZero();
    BodyEntry& entry = entries_[b];
    if (!accepted) continue;
    entry.depth = entry.depth_after;
    if (entry.depth <= 0.0) entry.other = -1;
  }
}

int BodyEntries::Entering(int a, int b) const {
  const Body& first = world_.bodies[static_cast<std::size_t>(a)];
  const Body& second = world_.bodies[static_cast<std::size_t>(b)];
  // A clamped or driven body is placed by its frames, as a collider is: the free one moves.
  const bool held_a = HasConstrainedNodes(first), held_b = HasConstrainedNodes(second);
  if (held_a != held_b) return held_a ? b : a;
  const double mass_a = first.model->masses().sum(), mass_b = second.model->masses().sum();
  if (mass_a != mass_b) return mass_a < mass_b ? a : b;
  return std::max(a, b);
}

bool BodyEntries::Overlapping(int a, const Eigen::Vector3d& offset, int b) const {
  const Body& first = world_.bodies[static_cast<std::size_t>(a)];
  const Body& second = world_.bodies[static_cast<std::size_t>(b)];
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  return Inside(first, offset, second, none) || Inside(second, none, first, offset);
}

bool BodyEntries::Inside(const Body& body, const Eigen::Vector3d& offset, const Body& other,
                         const Eigen::Vector3d& other_offset) {
  // Only the nodes within the other's border box are looked at: for bodies resting on each other
  // there are none, and the test costs two passes over the border nodes.
  const Eigen::AlignedBox3d box = BorderBox(other, other_offset);
  if (box.isEmpty()) return false;
  std::vector<Eigen::Vector3d> points;
  Eigen::AlignedBox3d near;
  for (const NodeIndex node : body.border.nodes) {
    const Eigen::Vector3d p = body.state.positions.col(node) + offset;
    if (!box.contains(p)) continue;
    points.push_back(p);
    near.extend(p);
  }
  if (points.empty()) return false;
  double largest_radius = 0.0;
  for (const double r : other.border.radii) largest_radius = std::max(largest_radius, r);
  // Every point of a lattice lies within a cell's half diagonal of a node, less than the two
  // radii (a border node's radius is the mean half-length of its springs).
  const double search = 2.0 * largest_radius;
  if (!(search > 0.0)) return false;
  near.min().array() -= search;
  near.max().array() += search;
  const Eigen::Matrix3Xd& x = other.state.positions;
  SpatialHashGrid grid(search);
  for (Eigen::Index n = 0; n < x.cols(); ++n) {
    if (near.contains(Eigen::Vector3d(x.col(n) + other_offset))) {
      grid.Insert(static_cast<int>(n), x.col(n) + other_offset);
    }
  }
  std::vector<char> border(static_cast<std::size_t>(x.cols()), 0);
  for (const NodeIndex node : other.border.nodes) border[static_cast<std::size_t>(node)] = 1;
  for (const Eigen::Vector3d& p : points) {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity();
    grid.ForEachWithin(p, search, [&](int index, const Eigen::Vector3d& xn) {
      const double distance_sq = (xn - p).squaredNorm();
      if (distance_sq < best) {
        best = distance_sq;
        nearest = index;
      }
    });
    if (nearest < 0) continue;
    if (!border[static_cast<std::size_t>(nearest)]) return true;
    // A border node's star points into its body: on or behind it is inside.
    const Eigen::Vector3d xk = x.col(nearest) + other_offset;
    if ((p - xk).dot(NodeStar(other, nearest)) >= 0.0) return true;
  }
  return false;
}

Eigen::Vector3d BodyEntries::WayOut(int a, int b) const {
  const Eigen::AlignedBox3d box_a =
      BorderBox(world_.bodies[static_cast<std::size_t>(a)], {0, 0, 0});
  const Eigen::AlignedBox3d box_b =
      BorderBox(world_.bodies[static_cast<std::size_t>(b)], {0, 0, 0});
  // Bodies placed at one pose tie up and down, or along equal sides: then against gravity, the
  // way a body dropped into another would be lifted out.
  const double tie = 1e-9 * (box_a.diagonal().norm() + box_b.diagonal().norm());
  Eigen::Vector3d best = Eigen::Vector3d::UnitZ();
  double best_travel = std::numeric_limits<double>::infinity(), best_up = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Vector3d direction = sign * Eigen::Vector3d::Unit(axis);
      const double travel = sign > 0.0 ? box_b.max()(axis) - box_a.min()(axis)
                                       : box_a.max()(axis) - box_b.min()(axis);
      const double up = -world_.options.gravity.dot(direction);
      if (travel < best_travel - tie || (travel <= best_travel + tie && up > best_up)) {
        best = direction;
        best_travel = travel;
        best_up = up;
      }
    }
  }
  return best;
}

double BodyEntries::DistanceToClear(int a, int b, const Eigen::Vector3d& direction,
                                    double from) const {
  const Body& first = world_.bodies[static_cast<std::size_t>(a)];
  const Body& second = world_.bodies[static_cast<std::size_t>(b)];
  // Beyond the other's border nodes along the direction, no centre of a is inside b.
  double lowest_a = std::numeric_limits<double>::infinity();
  double highest_b = -std::numeric_limits<double>::infinity();
  for (const NodeIndex node : first.border.nodes) {
    lowest_a = std::min(lowest_a, first.state.positions.col(node).dot(direction));
  }
  for (const NodeIndex node : second.border.nodes) {
    highest_b = std::max(highest_b, second.state.positions.col(node).dot(direction));
  }
  double distance = std::max(from, highest_b - lowest_a);
  // Then past the larger root of |q + D u| = reach of every pair that would still touch.
  for (std::size_t i = 0; i < first.border.nodes.size(); ++i) {
    const Eigen::Vector3d xi = first.state.positions.col(first.border.nodes[i]);
    for (std::size_t j = 0; j < second.border.nodes.size(); ++j) {
      const Eigen::Vector3d q = xi - second.state.positions.col(second.border.nodes[j]);
      const double reach = first.border.radii[i] + second.border.radii[j];
      const double along = q.dot(direction);
      const double discriminant = along * along - q.squaredNorm() + reach * reach;
      if (discriminant > 0.0) distance = std::max(distance, -along + std::sqrt(discriminant));
    }
  }
  return distance;
}

}  // namespace msm_sim::core::internal
