// msm_sim._core: the compiled half of the Python package msm_sim (docs/python.md). Bad
// arguments raise ValueError (pybind11 translates std::invalid_argument), other failures
// RuntimeError; the GIL is released while a lab command runs and while a World steps.
#include "bindings.h"

PYBIND11_MODULE(_core, module) {
  module.doc() = "msm_sim's C++ core: the lab commands, materials, models and the World";
  msm_sim::python::BindLab(module);
  msm_sim::python::BindModel(module);
  msm_sim::python::BindWorld(module);
}
