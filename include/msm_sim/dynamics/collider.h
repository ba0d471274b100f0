#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msm_sim/geometry/solid_mesh.h"

namespace msm_sim::core {

/// The rigid shapes MSM nodes can collide with, in the shape's own frame (SI units):
/// - plane: the half-space z <= 0 (the ground, a table top, a clamp face);
/// - box: |x|, |y|, |z| <= half_extents;
/// - sphere: |p| <= radius;
/// - capsule: points within radius of the segment z in [-half_length, half_length];
/// - cylinder: x^2 + y^2 <= radius^2, |z| <= half_length;
/// - mesh: the inside of a closed triangle mesh (a SolidMesh, AABB tree).
class ColliderShape {
 public:
  enum class Type { kPlane, kBox, kSphere, kCapsule, kCylinder, kMesh };

  static ColliderShape Plane();
  /// Throws std::invalid_argument unless every dimension is finite and > 0.
  static ColliderShape Box(const Eigen::Vector3d& size);
  static ColliderShape Sphere(double radius);
  /// `length` is the distance between the centres of the end caps.
  static ColliderShape Capsule(double radius, double length);
  static ColliderShape Cylinder(double radius, double length);
  /// Precondition: mesh non-null (SolidMesh guarantees a closed surface).
  static ColliderShape Mesh(std::shared_ptr<const SolidMesh> mesh);

  Type type() const { return type_; }
  /// Signed distance (m) from p to the surface, negative inside; *normal receives the unit
  /// outward normal at the closest surface point, *closest that point. All in the shape frame.
  double SignedDistance(const Eigen::Vector3d& p, Eigen::Vector3d* normal,
                        Eigen::Vector3d* closest) const;
  /// Axis-aligned bounds of the shape in its frame; a plane is unbounded (returns false).
  bool Bounds(Eigen::Vector3d* min, Eigen::Vector3d* max) const;

 private:
  Type type_ = Type::kPlane;
  Eigen::Vector3d half_extents_ = Eigen::Vector3d::Zero();
  double radius_ = 0.0;
  double half_length_ = 0.0;
  std::shared_ptr<const SolidMesh> mesh_;
};

/// A static or kinematic rigid body the MSMs touch: the ground, a clamp, a robot link. It has
/// infinite mass: contacts change the nodes' velocities, never its motion, which its owner sets
/// (pose and twist, e.g. from tf for a robot link) before each step.
struct Collider {
  std::string name;
  ColliderShape shape = ColliderShape::Plane();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();      ///< shape frame in the world
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   ///< of the frame origin, world, m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< world, rad/s
  double friction = 0.5;     ///< Coulomb coefficient of this surface (pairs combine, see World)
  double restitution = 1.0;  ///< e in [0, 1]: 1 is the thesis' elastic exchange
  /// A disabled collider touches nothing (e.g. a robot link whose pose tf no longer gives).
  bool enabled = true;

  /// Velocity of the collider's material point at world position p.
  Eigen::Vector3d VelocityAt(const Eigen::Vector3d& p) const {
    return linear_velocity + angular_velocity.cross(p - pose.translation());
  }
};

}  // namespace msm_sim::core
