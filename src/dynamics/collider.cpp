#include "msm_sim/dynamics/collider.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace msm_sim::core {
namespace {

void RequirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("collider ") + what + " must be finite and > 0");
  }
}

// Unit vector along v, or `fallback` when v vanishes (a point exactly on an axis or centre).
Eigen::Vector3d UnitOr(const Eigen::Vector3d& v, const Eigen::Vector3d& fallback) {
  const double length = v.norm();
  return length > 1e-300 ? Eigen::Vector3d(v / length) : fallback;
}

double BoxDistance(const Eigen::Vector3d& h, const Eigen::Vector3d& p, Eigen::Vector3d* normal,
                   Eigen::Vector3d* closest) {
  const Eigen::Vector3d q = p.cwiseAbs() - h;
  if ((q.array() > 0.0).any()) {
    // Outside: the closest point clamps p to the box.
    *closest = p.cwiseMax(-h).cwiseMin(h);
    *normal = UnitOr(p - *closest, Eigen::Vector3d::UnitZ());
    return (p - *closest).norm();
  }
  // Inside: the nearest face.
  Eigen::Index axis = 0;
  const double depth = q.maxCoeff(&axis);
  const double side = p[axis] >= 0.0 ? 1.0 : -1.0;
  *normal = side * Eigen::Vector3d::Unit(axis);
  *closest = p;
  (*closest)[axis] = side * h[axis];
  return depth;
}

double CylinderDistance(double radius, double half_length, const Eigen::Vector3d& p,
                        Eigen::Vector3d* normal, Eigen::Vector3d* closest) {
  const Eigen::Vector2d radial(p.x(), p.y());
  const double r = radial.norm();
  const Eigen::Vector3d out =
      r > 1e-300 ? Eigen::Vector3d(p.x() / r, p.y() / r, 0.0) : Eigen::Vector3d::UnitX();
  const double d_side = r - radius;
  const double d_cap = std::abs(p.z()) - half_length;
  const double cap_sign = p.z() >= 0.0 ? 1.0 : -1.0;
  if (d_side > 0.0 && d_cap > 0.0) {  // beyond the rim
    *closest = radius * out + cap_sign * half_length * Eigen::Vector3d::UnitZ();
    *normal = UnitOr(p - *closest, out);
    return (p - *closest).norm();
  }
  if (d_side >= d_cap) {  // nearest to the side (outside beside it, or inside closer to it)
    *closest = Eigen::Vector3d(radius * out.x(), radius * out.y(), p.z());
    *normal = out;
    return d_side;
  }
  *closest = Eigen::Vector3d(p.x(), p.y(), cap_sign * half_length);  // nearest to a cap
  if (d_side > 0.0) closest->head<2>() = radius * out.head<2>();
  *normal = cap_sign * Eigen::Vector3d::UnitZ();
  return d_cap;
}

}  // namespace

ColliderShape ColliderShape::Plane() { return ColliderShape(); }

ColliderShape ColliderShape::Box(const Eigen::Vector3d& size) {
  for (int axis = 0; axis < 3; ++axis) RequirePositive(size[axis], "box size");
  ColliderShape shape;
  shape.type_ = Type::kBox;
  shape.half_extents_ = 0.5 * size;
  return shape;
}

ColliderShape ColliderShape::Sphere(double radius) {
  RequirePositive(radius, "sphere radius");
  ColliderShape shape;
  shape.type_ = Type::kSphere;
  shape.radius_ = radius;
  return shape;
}

ColliderShape ColliderShape::Capsule(double radius, double length) {
  RequirePositive(radius, "capsule radius");
  if (!(length >= 0.0) || !std::isfinite(length)) {
    throw std::invalid_argument("collider capsule length must be finite and >= 0");
  }
  ColliderShape shape;
  shape.type_ = Type::kCapsule;
  shape.radius_ = radius;
  shape.half_length_ = 0.5 * length;
  return shape;
}

ColliderShape ColliderShape::Cylinder(double radius, double length) {
  RequirePositive(radius, "cylinder radius");
  RequirePositive(length, "cylinder length");
  ColliderShape shape;
  shape.type_ = Type::kCylinder;
  shape.radius_ = radius;
  shape.half_length_ = 0.5 * length;
  return shape;
}

ColliderShape ColliderShape::Mesh(std::shared_ptr<const SolidMesh> mesh) {
  if (!mesh) throw std::invalid_argument("collider mesh must not be null");
  ColliderShape shape;
  shape.type_ = Type::kMesh;
  shape.mesh_ = std::move(mesh);
  return shape;
}

double ColliderShape::SignedDistance(const Eigen::Vector3d& p, Eigen::Vector3d* normal,
                                     Eigen::Vector3d* closest) const {
  switch (type_) {
    case Type::kPlane:
      *normal = Eigen::Vector3d::UnitZ();
      *closest = Eigen::Vector3d(p.x(), p.y(), 0.0);
      return p.z();
    case Type::kBox:
      return BoxDistance(half_extents_, p, normal, closest);
    case Type::kSphere: {
      *normal = UnitOr(p, Eigen::Vector3d::UnitZ());
      *closest = radius_ * *normal;
      return p.norm() - radius_;
    }
    case Type::kCapsule: {
      const Eigen::Vector3d axis_point(0.0, 0.0, std::clamp(p.z(), -half_length_, half_length_));
      *normal = UnitOr(p - axis_point, Eigen::Vector3d::UnitX());
      *closest = axis_point + radius_ * *normal;
      return (p - axis_point).norm() - radius_;
    }
    case Type::kCylinder:
      return CylinderDistance(radius_, half_length_, p, normal, closest);
    case Type::kMesh: {
      int triangle = 0;
      *closest = mesh_->ClosestPoint(p, &triangle);
      const bool inside = mesh_->Contains(p);
      const TriangleMesh& surface = mesh_->surface();
      const Eigen::Vector3d face_normal =
          UnitOr((surface.vertices.col(surface.triangles(1, triangle)) -
                  surface.vertices.col(surface.triangles(0, triangle)))
                     .cross(surface.vertices.col(surface.triangles(2, triangle)) -
                            surface.vertices.col(surface.triangles(0, triangle))),
                 Eigen::Vector3d::UnitZ());
      const Eigen::Vector3d away = p - *closest;
      const double distance = away.norm();
      // Off an edge or vertex the direction to the closest point is the normal; on a face (or
      // too close to tell) the face's.
      *normal =
          distance > 1e-12 ? Eigen::Vector3d((inside ? -away : away) / distance) : face_normal;
      return inside ? -distance : distance;
    }
  }
  return 0.0;
}

bool ColliderShape::Bounds(Eigen::Vector3d* min, Eigen::Vector3d* max) const {
  switch (type_) {
    case Type::kPlane:
      return false;
    case Type::kBox:
      *min = -half_extents_;
      *max = half_extents_;
      return true;
    case Type::kSphere:
      *min = Eigen::Vector3d::Constant(-radius_);
      *max = Eigen::Vector3d::Constant(radius_);
      return true;
    case Type::kCapsule:
    case Type::kCylinder: {
      const double reach = type_ == Type::kCapsule ? half_length_ + radius_ : half_length_;
      *min = Eigen::Vector3d(-radius_, -radius_, -reach);
      *max = Eigen::Vector3d(radius_, radius_, reach);
      return true;
    }
    case Type::kMesh:
      *min = mesh_->min_corner();
      *max = mesh_->max_corner();
      return true;
  }
  return false;
}

}  // namespace msm_sim::core
