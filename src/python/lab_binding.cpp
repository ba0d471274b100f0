#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.h"
#include "lab_main.h"

namespace msm_sim::python {

namespace py = pybind11;

void BindLab(py::module_& module) {
  module.def(
      "run_lab",
      [](const std::vector<std::string>& args) {
        std::ostringstream out;
        std::ostringstream err;
        int code = 0;
        {
          // The command runs on C++ data only: other Python threads go on meanwhile.
          py::gil_scoped_release release;
          std::vector<std::string> argv{"msm_lab"};
          argv.insert(argv.end(), args.begin(), args.end());
          code = lab::RunLabMain(argv, out, err);
        }
        return std::make_tuple(code, out.str(), err.str());
      },
      py::arg("args"),
      "Runs `msm_lab ARGS...` in this process (the same function the executable runs); "
      "returns (exit code, what it wrote to stdout, what it wrote to stderr).");
}

}  // namespace msm_sim::python
