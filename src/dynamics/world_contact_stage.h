#pragma once
// Private to msm_sim's World: the collider frames and contacts of a substep's contact stage,
// shared by the stage (world_contacts.cpp) and the substep that runs it inside the force loops'
// node shares (world_step.cpp).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msm_sim/dynamics/world.h"

namespace msm_sim::core {

// A collider's frame for detection, computed once per body and substep.
struct World::ColliderFrame {
  bool bounded;            // planes are unbounded
  Eigen::Vector3d lo, hi;  // bounds in the collider's frame
  // The bounds' box in the world frame: most border nodes are far from a bounded collider, and
  // this test skips their transform into its frame (docs/design/speed-against-bullet.md).
  Eigen::AlignedBox3d world_box;
  // A plane's normal and offset in the world frame (distance = normal . x - offset): the same
  // shortcut for the nodes high above the ground.
  Eigen::Vector3d plane_normal;
  double plane_offset;
  Eigen::Isometry3d inverse;
  // Whether the collider has a twist: a still one's material is at rest, and skipping
  // VelocityAt's cross product (through the stack) took a sixth of a resting block's detection.
  bool moving;

  Eigen::Vector3d VelocityAt(const Collider& collider, const Eigen::Vector3d& point) const {
    return moving ? collider.VelocityAt(point) : Eigen::Vector3d::Zero();
  }
};

// A contact of one node with one collider during the detection of a substep.
struct World::NodeContact {
  int collider;
  Eigen::Vector3d normal;    // unit, out of the collider
  Eigen::Vector3d point;     // on the collider's surface
  Eigen::Vector3d velocity;  // of the collider's material there
  double distance;           // signed, of the node from the surface (m)
  double stopped = 0.0;      // normal velocity change that stopped the approach (>= 0)
};

// What a body's contact stage of one substep shares between its node shares.
struct World::ContactStage {
  std::vector<ColliderFrame> frames;  // FrameColliders()
  std::vector<double> frictions;      // Friction(body, c) per collider: once per substep, not a
                                      // square root per contact
  std::vector<int> counts;            // microcollisions per node share
};

}  // namespace msm_sim::core
