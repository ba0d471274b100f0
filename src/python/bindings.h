#pragma once
// The parts of the Python module msm_sim._core (module.cpp), each defined in its own file.

#include <pybind11/pybind11.h>

namespace msm_sim::python {

/// run_lab(args) -> (exit code, stdout, stderr): msm_lab's command line (lab_binding.cpp).
void BindLab(pybind11::module_& module);

/// Material, Model, build_model, load_model (model_binding.cpp).
void BindModel(pybind11::module_& module);

/// World (world_binding.cpp), its colliders' constructors (world_colliders.cpp).
void BindWorld(pybind11::module_& module);

}  // namespace msm_sim::python
