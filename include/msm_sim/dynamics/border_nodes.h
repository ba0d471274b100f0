#pragma once

#include <vector>

#include <Eigen/Core>

#include "msm_sim/dynamics/collider.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

/// The nodes that carry collision spheres (docs/physics.md §7 "microcollisions") and their radii.
struct BorderNodes {
  std::vector<NodeIndex> nodes;
  std::vector<double> radii;  ///< m, the mean half-length of the node's springs
};

/// A node is on the border when its star of springs is one-sided: the mean of the unit vectors
/// to its neighbours exceeds `imbalance` in length (0 for an interior node of a cubic lattice,
/// 0.29 on a face; below 0.24 for every interior node of a random lattice with <S> = 22), or
/// when it has fewer than 4 springs. Interior nodes cannot reach a surface without a border node
/// touching it first, so only border nodes are tested. Precondition: imbalance in (0, 1).
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
