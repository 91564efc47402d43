/// \file
/// \brief The compiled half of the Python module `gyroflip` (`gyroflip._gyroflip`): plain
/// functions over NumPy arrays; gyroflip/__init__.py gives them their public, documented form.
#include <string>

#include "common.hpp"

namespace gyroflip::python {
void bind_analysis(py::module_& m);
void bind_method(py::module_& m);
void bind_workflow(py::module_& m);
}  // namespace gyroflip::python

PYBIND11_MODULE(_gyroflip, m) {
  m.doc() = "gyroflip's C++ core (use the functions of the package gyroflip)";
  m.attr("__version__") = GYROFLIP_VERSION;
  gyroflip::python::bind_analysis(m);
  gyroflip::python::bind_method(m);
  gyroflip::python::bind_workflow(m);
}
