#include <cmath>
#include <stdexcept>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "msm_sim/dynamics/world.h"
#include "py_model.h"
#include "world_colliders.h"

namespace msm_sim::python {
namespace py = pybind11;
namespace {

core::WorldOptions Options(const std::string& integrator, const Eigen::Vector3d& gravity,
                           int threads, const std::string& spring_precision,
                           bool record_contact_points) {
  core::WorldOptions options;
  if (!core::ParseIntegrator(integrator, &options.integrator)) {
    throw std::invalid_argument("integrator must be explicit or implicit, not '" + integrator +
                                "'");
  }
  if (spring_precision != "single" && spring_precision != "double") {
    throw std::invalid_argument("spring_precision must be single or double, not '" +
                                spring_precision + "'");
  }
  if (threads < 1) throw std::invalid_argument("threads must be >= 1");
  options.spring_precision = spring_precision == "single" ? core::SpringPrecision::kSingle
                                                          : core::SpringPrecision::kDouble;
  options.gravity = gravity;
  options.threads = threads;
  options.record_contact_points = record_contact_points;
  return options;
}

py::dict Report(const core::StepReport& report) {
  py::dict out;
  out["accepted"] = report.accepted;
  out["reason"] = report.reason;
  out["substeps"] = report.substeps;
  out["substep"] = report.substep;
  out["microcollisions"] = report.microcollisions;
  out["solver_iterations"] = report.solver_iterations;
  out["substep_refinement"] = report.substep_refinement;
  return out;
}

py::dict EnergiesDict(const core::Energies& energies) {
  py::dict out;
  out["kinetic"] = energies.kinetic;
  out["elastic"] = energies.elastic;
  out["gravitational"] = energies.gravitational;
  out["total"] = energies.total();
  return out;
}

void SetState(core::World& world, int body, const Eigen::MatrixX3d& positions,
              const Eigen::MatrixX3d& velocities) {
  CheckBody(world, body);
  core::State state;
  state.positions = positions.transpose();
  state.velocities = velocities.transpose();
  world.SetState(body, state);
}

// Positions and velocities are copies, (nodes, 3) float64: the World's own arrays change with
// every step and move when it is reset, so a view could outlive what it shows.
void BindState(py::class_<core::World>& world) {
  world
      .def(
          "positions",
          [](const core::World& w, int body) -> Eigen::MatrixX3d {
            CheckBody(w, body);
            return w.state(body).positions.transpose();
          },
          py::arg("body"), "Node positions (m), a copy, shape (nodes, 3).")
      .def(
          "velocities",
          [](const core::World& w, int body) -> Eigen::MatrixX3d {
            CheckBody(w, body);
            return w.state(body).velocities.transpose();
          },
          py::arg("body"), "Node velocities (m/s), a copy, shape (nodes, 3).")
      .def("set_state", &SetState, py::arg("body"), py::arg("positions"), py::arg("velocities"))
      .def(
          "energies",
          [](const core::World& w, int body) {
            CheckBody(w, body);
            return EnergiesDict(w.ComputeEnergies(body));
          },
          py::arg("body"), "kinetic, elastic, gravitational and total energy (J).");
}

}  // namespace

void CheckBody(const core::World& world, int body) {
  if (body < 0 || body >= world.num_bodies()) {
    throw std::invalid_argument("no body " + std::to_string(body) + " (the world has " +
                                std::to_string(world.num_bodies()) + ")");
  }
}

void BindWorld(py::module_& module) {
  py::class_<core::World> world(module, "World", "Bodies and colliders stepped in time.");
  world
      .def(py::init([](const std::string& integrator, const Eigen::Vector3d& gravity, int threads,
                       const std::string& spring_precision, bool record_contact_points) {
             return core::World(
                 Options(integrator, gravity, threads, spring_precision, record_contact_points));
           }),
           py::kw_only(), py::arg("integrator") = "explicit",
           py::arg("gravity") = Eigen::Vector3d(0.0, 0.0, -9.81), py::arg("threads") = 1,
           py::arg("spring_precision") = "single", py::arg("record_contact_points") = false)
      .def(
          "add_body",
          // The body options by the scene YAML's names (docs/scenes.md, objects[]).
          [](core::World& w, const std::string& name, const PyModel& model, double damping,
             double friction, double restitution, double orientation_threshold) {
            core::BodyOptions options;
            options.damping_beta = damping;
            options.friction = friction;
            options.restitution = restitution;
            options.orientation_threshold = orientation_threshold;
            return w.AddBody(name, model.model, options);
          },
          py::arg("name"), py::arg("model"), py::kw_only(), py::arg("damping") = 0.0,
          py::arg("friction") = 0.5, py::arg("restitution") = 1.0,
          py::arg("orientation_threshold") = 0.0,
          "Adds a body at rest at the model's rest positions; returns its index. damping: s, "
          "spring dampers c = damping k.")
      .def(
          "step",
          [](core::World& w, double dt) {
            if (!(dt > 0.0) || !std::isfinite(dt)) throw std::invalid_argument("dt must be > 0");
            core::StepReport report;
            {
              py::gil_scoped_release release;
              report = w.Step(dt);
            }
            return Report(report);
          },
          py::arg("dt"), "Advances by dt seconds (GIL released); returns the step's report.")
      .def("reset", &core::World::Reset)
      .def_property_readonly("time", &core::World::time)
      .def_property_readonly("num_bodies", &core::World::num_bodies)
      .def_property_readonly("num_colliders", &core::World::num_colliders)
      .def_property_readonly("stable_time_step", &core::World::stable_time_step);
  BindState(world);
  BindColliders(world);
}

}  // namespace msm_sim::python
