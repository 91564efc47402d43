/// \file
/// \brief Errors, arrays and Ctrl-C for the bindings (common.hpp).
#include "common.hpp"

#include <Python.h>

#include <chrono>

#include "gyroflip/earth/earth.hpp"

namespace gyroflip::python {

namespace {

// Library parameters and the Python arguments that set them (the library never names either).
constexpr std::pair<const char*, const char*> argument_of_parameter[] = {
    {"sample_rate_hz", "rate"},
    {"duration_s", "duration_s"},
    {"n_avg", "n_avg"},
    {"seed", "seed"},
    {"lat_deg", "latitude"},
    {"window_s", "drift_window_s"},
    {"delta_n_dps", "delta_n_dps"},
    {"fit_taus", "fit_taus"},
    {"level", "ci"},
    {"taus", "taus"},
    {"settle_s", "settle_s"},
    {"angle_tolerance_deg", "angle_tolerance_deg"},
    {"sensors", "sensors"},
    {"campaigns", "campaigns"},
};

}  // namespace

void raise(const error& e) {
  std::string message = e.message;
  for (const auto& [param, arg] : argument_of_parameter)
    if (e.parameter == param) message += std::string(" (argument ") + arg + ")";
  if (e.code == errc::io) {
    PyErr_SetString(PyExc_OSError, message.c_str());
    throw py::error_already_set();
  }
  throw py::value_error(message);
}

progress_fn interrupt_check() {
  using clock = std::chrono::steady_clock;
  return [last = clock::now()](std::size_t, std::size_t) mutable {
    const auto now = clock::now();
    if (now - last < std::chrono::milliseconds(50)) return;
    last = now;
    const py::gil_scoped_acquire held;
    if (PyErr_CheckSignals() != 0) throw interrupted{};
  };
}

std::span<const double> span_of(const f64_array& a, const char* name) {
  if (a.ndim() != 1)
    throw py::value_error(std::string(name) + " must be 1-D (got " + std::to_string(a.ndim()) +
                          " dimensions)");
  return {a.data(), static_cast<std::size_t>(a.shape(0))};
}

py::object json_loads(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

std::optional<io::calibration_geometry> geometry_of(std::optional<double> lat_deg,
                                                    const std::optional<std::string>& axis) {
  if (lat_deg.has_value() != axis.has_value())
    throw py::value_error("give latitude and axis together (or neither)");
  if (!lat_deg) return std::nullopt;
  check(earth::check_latitude(*lat_deg));
  return io::calibration_geometry{*lat_deg, take(earth::parse_axis(*axis))};
}

}  // namespace gyroflip::python
