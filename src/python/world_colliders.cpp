#include "world_colliders.h"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "msm_sim/lattice/body_shape.h"
#include "py_model.h"

namespace msm_sim::python {
namespace py = pybind11;
namespace {

void CheckCollider(const core::World& world, int collider) {
  if (collider < 0 || collider >= world.num_colliders()) {
    throw std::invalid_argument("no collider " + std::to_string(collider));
  }
}

// Shapes by the scene YAML's names; a cylinder's and a capsule's axis is the frame's z.
core::ColliderShape Shape(const std::string& shape, const Eigen::Vector3d& size, double radius,
                          double length, const std::string& mesh, double scale) {
  if (shape == "plane") return core::ColliderShape::Plane();
  if (shape == "box") return core::ColliderShape::Box(size);
  if (shape == "sphere") return core::ColliderShape::Sphere(radius);
  if (shape == "cylinder") return core::ColliderShape::Cylinder(radius, length);
  if (shape == "capsule") return core::ColliderShape::Capsule(radius, length);
  if (shape == "mesh") {
    core::BodyShape body;
    body.kind = core::BodyShape::Kind::kMesh;
    body.mesh_path = mesh;
    body.mesh_scale = scale;
    return core::ColliderShape::Mesh(
        std::make_shared<const core::SolidMesh>(core::MakeBodySolid(body)));
  }
  throw std::invalid_argument("collider shape must be plane, box, sphere, cylinder, capsule or " +
                              std::string("mesh, not '") + shape + "'");
}

py::dict WrenchDict(const core::ContactWrench& wrench) {
  py::dict out;
  out["force"] = Eigen::Vector3d(wrench.force);
  out["torque"] = Eigen::Vector3d(wrench.torque);
  out["centroid"] = Eigen::Vector3d(wrench.centroid);
  out["normal"] = Eigen::Vector3d(wrench.normal);
  out["microcollisions"] = wrench.microcollisions;
  out["normal_force"] = wrench.normal_force;
  out["area"] = wrench.area;
  out["mean_pressure"] = wrench.mean_pressure;
  return out;
}

// One array per field, one row per microcollision (copies).
py::dict ContactPoints(const core::World& world, int body) {
  CheckBody(world, body);
  const std::vector<core::ContactPoint>& points = world.contact_points(body);
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  Eigen::Matrix<std::int32_t, Eigen::Dynamic, 1> collider(n), node(n), substep(n);
  Eigen::MatrixX3d point(n, 3), normal(n, 3), tangential(n, 3);
  Eigen::VectorXd normal_impulse(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const core::ContactPoint& p = points[static_cast<std::size_t>(i)];
    collider(i) = p.collider;
    node(i) = p.node;
    substep(i) = p.substep;
    point.row(i) = p.point.transpose();
    normal.row(i) = p.normal.transpose();
    tangential.row(i) = p.tangential_impulse.transpose();
    normal_impulse(i) = p.normal_impulse;
  }
  py::dict out;
  out["collider"] = collider;
  out["node"] = node;
  out["substep"] = substep;
  out["point"] = point;
  out["normal"] = normal;
  out["normal_impulse"] = normal_impulse;
  out["tangential_impulse"] = tangential;
  return out;
}

int AddCollider(core::World& world, const std::string& name, const std::string& shape,
                const Eigen::Vector3d& size, double radius, double length, const std::string& mesh,
                double scale, const Eigen::Vector3d& position, const Eigen::Vector3d& rpy,
                double friction, double restitution) {
  core::Collider collider;
  collider.name = name;
  collider.shape = Shape(shape, size, radius, length, mesh, scale);
  collider.pose = Pose(position, rpy);
  collider.friction = friction;
  collider.restitution = restitution;
  return world.AddCollider(collider);
}

// Clamps only: a moving group's pose would be a Python callback run inside Step, which holds no
// GIL there.
void BindPushesAndClamps(py::class_<core::World>& world) {
  world.def(
      "add_clamp",
      [](core::World& w, int body, const std::string& name,
         const std::vector<core::NodeIndex>& nodes) {
        CheckBody(w, body);
        core::KinematicGroup group;
        group.name = name;
        group.nodes = nodes;
        return w.AddKinematicGroup(body, group);
      },
      py::arg("body"), py::arg("name"), py::arg("nodes"),
      "Fixes the body's nodes where they are; returns the group's index. Its reaction comes "
      "after the colliders in wrenches(body).");
  world.def(
      "apply_force",
      [](core::World& w, int body, const Eigen::Vector3d& point, const Eigen::Vector3d& force,
         double radius,
         double duration) { return w.ApplyForce(body, point, force, radius, duration); },
      py::arg("body"), py::arg("point"), py::arg("force"), py::kw_only(), py::arg("radius") = 0.0,
      py::arg("duration") = 0.0, "Pushes a body (World::ApplyForce); returns pushes dropped.");
}

}  // namespace

void BindColliders(py::class_<core::World>& world) {
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  world
      .def("add_collider", &AddCollider, py::arg("name"), py::arg("shape"), py::kw_only(),
           py::arg("size") = Eigen::Vector3d(0.1, 0.1, 0.1), py::arg("radius") = 0.05,
           py::arg("length") = 0.1, py::arg("mesh") = "", py::arg("scale") = 1.0,
           py::arg("position") = zero, py::arg("rpy") = zero, py::arg("friction") = 0.5,
           py::arg("restitution") = 1.0, "Adds a kinematic collider; returns its index.")
      .def(
          "set_collider_pose",
          [](core::World& w, int index, const Eigen::Vector3d& position,
             const Eigen::Vector3d& rpy) {
            CheckCollider(w, index);
            w.collider(index).pose = Pose(position, rpy);
          },
          py::arg("index"), py::arg("position"), py::arg("rpy") = zero)
      .def(
          "set_collider_twist",
          [](core::World& w, int index, const Eigen::Vector3d& linear,
             const Eigen::Vector3d& angular) {
            CheckCollider(w, index);
            w.collider(index).linear_velocity = linear;
            w.collider(index).angular_velocity = angular;
          },
          py::arg("index"), py::arg("linear"), py::arg("angular") = zero)
      .def(
          "wrenches",
          [](const core::World& w, int body) {
            CheckBody(w, body);
            py::list out;
            for (const core::ContactWrench& wrench : w.wrenches(body))
              out.append(WrenchDict(wrench));
            return out;
          },
          py::arg("body"), "Per collider (then per kinematic group) what the body exerted.")
      .def("contact_points", &ContactPoints, py::arg("body"),
           "The last step's microcollisions (record_contact_points=True), as arrays.");
  BindPushesAndClamps(world);
}

}  // namespace msm_sim::python
