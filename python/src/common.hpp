/// \file
/// \brief What every binding of the Python module shares: library errors as Python exceptions,
/// NumPy arrays in and out, and long work that lets go of the GIL but still hears Ctrl-C.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/calibration_file.hpp"

namespace gyroflip::python {

namespace py = pybind11;

/// A float64 array, C-contiguous: NumPy passes a float64 contiguous array (a memmap too)
/// without a copy and converts anything else once.
using f64_array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// Raises the error as Python does for such a fault: `OSError` for files, `ValueError` for bad
/// data or arguments and for data the computation cannot use. `argument` names the Python
/// argument a library parameter stands for, when there is one.
[[noreturn]] void raise(const error& e);

/// The value of `r`, or raise(r.err()).
template <class T>
T take(result<T>&& r) {
  if (!r) raise(r.err());
  return std::move(*r);
}
inline void check(const status& s) {
  if (!s) raise(s.err());
}

/// Thrown by interrupt_check when Python has a signal pending (the error indicator is set).
struct interrupted {};

/// A progress callback for work that runs with the GIL released: every 50 ms it takes the GIL
/// and runs Python's signal handlers; Ctrl-C (or any handler that raises) cancels the work by
/// throwing `interrupted` through the library (core/progress.hpp).
[[nodiscard]] progress_fn interrupt_check();

/// Runs `f()` without the GIL, listening for Ctrl-C through `interrupt_check()` (passed to f);
/// a cancelled run raises the pending Python exception (KeyboardInterrupt).
template <class F>
auto without_gil(F&& f) {
  try {
    py::gil_scoped_release released;
    return f(interrupt_check());
  } catch (const interrupted&) {
    throw py::error_already_set();
  }
}

/// The samples of a 1-D array as a span (the array must stay alive).
[[nodiscard]] std::span<const double> span_of(const f64_array& a, const char* name);

/// A new 1-D float64 (or other) NumPy array holding `v`.
template <class T>
py::array_t<T> to_numpy(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

/// The geometry of `latitude` and `axis` (both or neither), checked as the CLI checks them.
[[nodiscard]] std::optional<io::calibration_geometry> geometry_of(
    std::optional<double> lat_deg, const std::optional<std::string>& axis);

/// Python's json.loads of `text`.
[[nodiscard]] py::object json_loads(const std::string& text);

}  // namespace gyroflip::python
