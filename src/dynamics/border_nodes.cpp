#include "msm_sim/dynamics/border_nodes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace msm_sim::core {
namespace {

// BorderNodes::surface_shares of `nodes`.
std::vector<double> SurfaceShares(const Model& model, const std::vector<NodeIndex>& nodes) {
  const double a = model.characteristic_length();
  const double total_mass = model.masses().sum();
  // Mass per cell: the model's mean density times a^3 (the material's density would miss
  // builders that lump mass differently).
  const double cell_mass = total_mass / model.volume() * a * a * a;
  std::vector<double> shares;
  shares.reserve(nodes.size());
  for (const NodeIndex node : nodes) {
    const double f =
        cell_mass > 0.0 && std::isfinite(cell_mass) ? model.masses()[node] / cell_mass : 1.0;
    shares.push_back(std::min(1.0, 2.0 * f) * a * a);
  }
  return shares;
}

}  // namespace

BorderNodes FindBorderNodes(const Model& model, double imbalance) {
  BorderNodes border;
  const Eigen::Matrix3Xd& x = model.rest_positions();
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double half_lengths = 0.0;
    const int count = model.num_incident_springs(i);
    for (int k = model.incidence_offsets()[i]; k < model.incidence_offsets()[i + 1]; ++k) {
      const SpringIndex s = model.incident_springs()[k];
      const NodeIndex j =
          model.spring_node_a()[s] == i ? model.spring_node_b()[s] : model.spring_node_a()[s];
      sum += (x.col(j) - x.col(i)) / model.spring_rest_length()[s];
      half_lengths += 0.5 * model.spring_rest_length()[s];
    }
    if (count >= 4 && sum.norm() <= imbalance * count) continue;
    // A node without springs still needs a size: half the model's node spacing. A cut cell's
    // sphere ends as far past the surface as a whole cell's past its face; a sliver whose centre
    // lies outside keeps the floor sphere (docs/physics.md §7).
    const double a = model.characteristic_length();
    const double mean = count > 0 ? half_lengths / count : 0.5 * a;
    border.nodes.push_back(i);
    border.radii.push_back(std::max(mean - model.surface_insets()[i], kSliverRadius * a));
  }
  border.surface_shares = SurfaceShares(model, border.nodes);
  return border;
}

double LowestSphereBottom(const Eigen::Matrix3Xd& positions, const BorderNodes& border) {
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    lowest = std::min(lowest, positions(2, border.nodes[k]) - border.radii[k]);
  }
  return lowest;
}

Collider GroundTouching(const Eigen::Matrix3Xd& positions, const BorderNodes& border,
                        double friction) {
  Collider ground;
  ground.name = "ground";
  ground.friction = friction;
  ground.pose.translation().z() = LowestSphereBottom(positions, border);
  return ground;
}

double SphereTouchdownHeight(const Eigen::Matrix3Xd& positions, const BorderNodes& border,
                             const Eigen::Vector2d& axis, double radius) {
  double height = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < border.nodes.size(); ++k) {
    const Eigen::Vector3d p = positions.col(border.nodes[k]);
    const double reach = radius + border.radii[k];  // centre distance at touch
    const double horizontal_sq = (p.head<2>() - axis).squaredNorm();
    if (horizontal_sq >= reach * reach) continue;
    height = std::max(height, p.z() + std::sqrt(reach * reach - horizontal_sq));
  }
  return height;
}

}  // namespace msm_sim::core
