#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/dynamics/collider.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The smallest collision sphere, as a fraction of the model's characteristic length: the
/// sphere of a sliver node whose centre lies outside the body (docs/physics.md §7).
inline constexpr double kSliverRadius = 0.05;

/// The nodes that carry collision spheres (docs/physics.md §7 "microcollisions") and their radii.
struct BorderNodes {
  std::vector<NodeIndex> nodes;
  /// m, the mean half-length r of the node's springs less its Model::surface_insets, at least
  /// kSliverRadius a (a the model's characteristic length): a node of a cell the surface cuts
  /// stands for the cell's inside part, and its sphere ends as far past the body's surface as a
  /// whole cell's ends past the cell's face (r - a / 2), so the spheres' envelope follows the
  /// surface; a sliver whose centre lies outside the surface keeps the small floor sphere
  /// (docs/physics.md §7).
  std::vector<double> radii;
  /// m^2, the body's surface each node stands for in a flat contact (a contact patch's area is
  /// the sum over its touching nodes): min(1, 2 f) a^2, with a the model's characteristic
  /// length and f = m V / (M a^3) the node's volume share in cells (m its mass, M and V the
  /// model's). A node-centred cubic lattice gives each node a whole cell (f = 1), one face of
  /// which lies on a flat side of the box, edge and corner nodes included: a^2. A lattice of
  /// element corners has its border nodes on the surface, a face node with half a cell (a^2 of
  /// the face), an edge node a quarter (a^2 / 2 of each face), a corner an eighth (a^2 / 4):
  /// 2 f a^2 each. A random lattice's nodes all have f = 1 (a = (V / N)^(1/3)), so a^2 each.
  /// The sum over a flat side of a box is its area, exactly for both cubic lattices.
  std::vector<double> surface_shares;
};

/// A node is on the border when its star of springs is one-sided: the mean of the unit vectors
/// to its neighbours exceeds `imbalance` in length (0 for an interior node of a cubic lattice,
/// 0.29 on a face; below 0.24 for every interior node of a random lattice with <S> = 22), or
/// when it has fewer than 4 springs. Interior nodes cannot reach a surface without a border node
/// touching it first, so only border nodes are tested.
/// Precondition: imbalance in (0, 1).
BorderNodes FindBorderNodes(const Model& model, double imbalance = 0.25);

/// Lowest z (m) reached by any border node's collision sphere with the nodes at `positions`
/// (3 x N): where a ground plane just touches the body. +infinity without border nodes.
double LowestSphereBottom(const Eigen::Matrix3Xd& positions, const BorderNodes& border);

/// The ground a body at `positions` rests on: a plane collider named "ground" with Coulomb
/// coefficient `friction`, its surface at LowestSphereBottom (it just touches the body).
/// Precondition: border has at least one node.
Collider GroundTouching(const Eigen::Matrix3Xd& positions, const BorderNodes& border,
                        double friction = 0.5);

/// Height (m) of the centre of a rigid sphere of `radius` (m, > 0) lowered along -z through
/// (x, y) = `axis` when it first touches a border node's collision sphere, the nodes at
/// `positions` (3 x N): where an indenter starts just in contact. -infinity if no collision
/// sphere lies under it.
double SphereTouchdownHeight(const Eigen::Matrix3Xd& positions, const BorderNodes& border,
                             const Eigen::Vector2d& axis, double radius);

}  // namespace msm_sim::core
