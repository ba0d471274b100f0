#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/lattice/body_recipe.h"
#include "msm_sim/lattice/body_shape.h"
#include "msm_sim/material/material.h"
#include "msm_sim/material/shore_hardness.h"
#include "msm_sim/material/spring_law.h"
#include "msm_sim/model/model_file.h"
#include "msm_sim/model/model_transform.h"
#include "py_model.h"

namespace msm_sim::python {
namespace py = pybind11;
namespace {

core::BodyShape Shape(const std::string& shape, const std::vector<double>& size, double radius,
                      double length, const std::string& mesh, double scale) {
  core::BodyShape body;
  if (shape == "box") {
    if (size.size() != 3) throw std::invalid_argument("shape box needs size [x, y, z]");
    body.kind = core::BodyShape::Kind::kBox;
    body.size = Eigen::Vector3d(size[0], size[1], size[2]);
  } else if (shape == "sphere") {
    body.kind = core::BodyShape::Kind::kSphere;
    body.radius = radius;
  } else if (shape == "cylinder") {
    body.kind = core::BodyShape::Kind::kCylinder;
    body.radius = radius;
    body.length = length;
  } else if (shape == "mesh") {
    body.kind = core::BodyShape::Kind::kMesh;
    body.mesh_path = mesh;
    body.mesh_scale = scale;
  } else {
    throw std::invalid_argument("shape must be box, sphere, cylinder or mesh, not '" + shape + "'");
  }
  return body;
}

// The lattice options by the scene YAML's names (docs/scenes.md, objects[]); the region is the
// shape's solid, centred on the origin, as the node builds its objects.
PyModel BuildModel(const core::Material& material, const core::BodyShape& shape,
                   const py::dict& lattice) {
  core::BodyRecipe recipe(material);
  const std::string model = py::cast<std::string>(lattice["model"]);
  if (!core::ParseLatticeKind(model, &recipe.lattice_kind)) {
    throw std::invalid_argument("model must be cubic, random or baudet, not '" + model + "'");
  }
  const auto solid = std::make_shared<const core::SolidMesh>(core::MakeBodySolid(shape));
  if (recipe.lattice_kind == core::LatticeKind::kBaudet) {
    if (shape.kind != core::BodyShape::Kind::kBox) {
      throw std::invalid_argument("model baudet fills boxes only");
    }
    recipe.box_size = shape.size;
    recipe.centre_box = true;
    recipe.target_volume = solid->volume();
  } else {
    recipe.solid = solid;
  }
  recipe.lattice.spacing = py::cast<double>(lattice["spacing"]);
  recipe.target_nodes = py::cast<int>(lattice["target_nodes"]);
  if (!(recipe.lattice.spacing > 0.0) && recipe.target_nodes <= 0) {
    throw std::invalid_argument("give spacing > 0 or target_nodes > 0");
  }
  const std::string spring = py::cast<std::string>(lattice["spring"]);
  if (!core::ParseSpringLaw(spring, &recipe.lattice.spring_law)) {
    throw std::invalid_argument("spring must be linear, nonlinear or power, not '" + spring + "'");
  }
  recipe.lattice.power_law.alpha = py::cast<double>(lattice["alpha"]);
  recipe.lattice.power_law.beta = py::cast<double>(lattice["beta"]);
  recipe.antialias = py::cast<bool>(lattice["antialias"]);
  recipe.seed = py::cast<std::uint64_t>(lattice["seed"]);
  recipe.random_self_calibrate = py::cast<bool>(lattice["self_calibrate"]);
  recipe.surface.free_face_bending = py::cast<bool>(lattice["free_face_bending"]);
  recipe.surface.surface_dispersion = py::cast<double>(lattice["surface_dispersion"]);
  recipe.surface.mass_scaling = py::cast<double>(lattice["mass_scaling"]);
  py::gil_scoped_release release;
  return PyModel{std::make_shared<const core::Model>(core::BuildModel(recipe))};
}

void BindMaterial(py::module_& module) {
  py::class_<core::Material>(module, "Material",
                             "Isotropic linear-elastic material: E (Pa), nu, rho (kg/m^3).")
      .def(py::init(&core::Material::FromYoungsPoisson), py::kw_only(), py::arg("youngs"),
           py::arg("poisson"), py::arg("density"))
      .def_static(
          "from_shore",
          [](double hardness, double poisson, double density, const std::string& scale) {
            if (scale != "A" && scale != "00") throw std::invalid_argument("scale must be A or 00");
            const core::ShoreConversion conversion =
                scale == "A" ? core::YoungsFromShoreA(hardness) : core::YoungsFromShore00(hardness);
            return core::Material::FromYoungsPoisson(conversion.youngs, poisson, density);
          },
          py::arg("hardness"), py::kw_only(), py::arg("poisson"), py::arg("density"),
          py::arg("scale") = "A", "E from a Shore hardness (docs/materials.md).")
      .def_property_readonly("youngs", &core::Material::youngs_modulus)
      .def_property_readonly("poisson", &core::Material::poisson_ratio)
      .def_property_readonly("density", &core::Material::density)
      .def_property_readonly("shear_modulus", &core::Material::shear_modulus)
      .def_property_readonly("bulk_modulus", &core::Material::bulk_modulus)
      .def("__repr__", &core::Material::Describe);
}

// Copies: a Model is immutable, and a copy outlives it without keeping it alive.
void BindModelClass(py::module_& module) {
  py::class_<PyModel>(module, "Model", "An immutable calibrated mass-spring model.")
      .def_property_readonly("num_nodes", [](const PyModel& m) { return m.model->num_nodes(); })
      .def_property_readonly("num_springs", [](const PyModel& m) { return m.model->num_springs(); })
      .def_property_readonly("rest_positions",
                             [](const PyModel& m) -> Eigen::MatrixX3d {
                               return m.model->rest_positions().transpose();
                             })
      .def_property_readonly("masses",
                             [](const PyModel& m) -> Eigen::VectorXd { return m.model->masses(); })
      .def_property_readonly(
          "added_mass", [](const PyModel& m) { return m.model->added_mass(); },
          "kg added to cut cells by mass scaling (docs/physics.md 7), part of masses")
      .def_property_readonly("springs",
                             [](const PyModel& m) {
                               const int n = m.model->num_springs();
                               py::array_t<std::int32_t> pairs({n, 2});
                               auto view = pairs.mutable_unchecked<2>();
                               for (int s = 0; s < n; ++s) {
                                 view(s, 0) = m.model->spring_node_a()[s];
                                 view(s, 1) = m.model->spring_node_b()[s];
                               }
                               return pairs;
                             })
      .def_property_readonly(
          "spring_rest_lengths",
          [](const PyModel& m) { return py::array(py::cast(m.model->spring_rest_length())); })
      .def_property_readonly(
          "spring_stiffness",
          [](const PyModel& m) { return py::array(py::cast(m.model->spring_stiffness())); })
      .def("save", [](const PyModel& m, const std::string& path) { SaveModel(*m.model, path); })
      .def(
          "transformed",
          [](const PyModel& m, const Eigen::Vector3d& position, const Eigen::Vector3d& rpy) {
            return PyModel{std::make_shared<const core::Model>(
                core::TransformedModel(*m.model, Pose(position, rpy)))};
          },
          py::arg("position"), py::arg("rpy") = Eigen::Vector3d::Zero(),
          "The model rigidly moved: rotated by rpy (R = Rz Ry Rx), then moved by position.");
  module.def(
      "load_model",
      [](const std::string& path) {
        return PyModel{std::make_shared<const core::Model>(core::LoadModel(path))};
      },
      py::arg("path"));
}

}  // namespace

void BindModel(py::module_& module) {
  BindMaterial(module);
  BindModelClass(module);
  module.def(
      "build_model",
      [](const core::Material& material, const std::string& shape, const std::vector<double>& size,
         double radius, double length, const std::string& mesh, double scale,
         const py::dict& lattice) {
        return BuildModel(material, Shape(shape, size, radius, length, mesh, scale), lattice);
      },
      py::arg("material"), py::arg("shape"), py::arg("size"), py::arg("radius"), py::arg("length"),
      py::arg("mesh"), py::arg("scale"), py::arg("lattice"),
      "The model of a shape centred on the origin (msm_sim.build_model wraps this).");
}

}  // namespace msm_sim::python
