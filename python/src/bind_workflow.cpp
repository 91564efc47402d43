/// \file
/// \brief The experiments for Python, the CLI's workflow calls (workflow/*.hpp): `_report` (the
/// report folder) and `_reproduce` (the paper's experiment). Results are the CLI's JSON objects
/// (its summary.json), parsed.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/heading.hpp"
#include "gyroflip/workflow/plan.hpp"
#include "gyroflip/workflow/report.hpp"
#include "gyroflip/workflow/reproduce.hpp"

namespace gyroflip::python {

namespace {

py::dict report(const std::vector<std::string>& files, const std::string& output,
                std::optional<double> lat_deg, const std::optional<std::string>& axis,
                const std::string& calibration, const std::string& title,
                const std::string& pairing, std::optional<double> expected_rate_dps,
                const std::string& command, const std::string& next_step,
                const std::optional<std::string>& sensor) {
  workflow::report_request req;
  // The specification the runs' g-term is checked against, as `report --sensor` (fourth review
  // of issue 31, F5).
  if (sensor) req.sensor = take(sensor::load_preset(*sensor));
  req.next_step = next_step;
  req.files = files;
  req.output = output;
  req.geometry = geometry_of(lat_deg, axis);
  req.calibration = calibration;
  req.title = title;
  const auto p = method::parse_pairing(pairing);
  if (!p) throw py::value_error("pairing must be 'abba' or 'simple' (got '" + pairing + "')");
  req.pairing = *p;
  req.expected_rate_dps = expected_rate_dps;
  req.command = command;
  req.made_by = "gyroflip.report (Python)";
  req.sensor_hint = "sensor= (a preset name or a TOML file)";
  auto run =
      without_gil([&](const progress_fn& listen) { return workflow::make_report(req, listen); });
  const auto res = take(std::move(run));
  return json_loads(res.summary_json);  // its "warnings" are the result's
}

py::dict reproduce(bool quick, std::uint64_t seed, std::optional<std::size_t> campaigns,
                   const std::string& output,
                   const std::vector<std::pair<std::string, std::string>>& sensors,
                   const std::string& command) {
  workflow::reproduce_request req;
  req.quick = quick;
  req.seed = seed;
  req.campaigns = campaigns;
  req.output = output;
  for (const auto& [name, path] : sensors) req.sensor_files.push_back({name, path});
  req.command = command;
  req.made_by = "gyroflip.reproduce (Python)";
  auto run =
      without_gil([&](const progress_fn& listen) { return workflow::reproduce(req, listen); });
  const auto res = take(std::move(run));
  py::dict d = json_loads(res.summary_json);
  d["text"] = res.text;
  return d;
}

// gyroflip.plan: the CLI's `plan` (workflow::plan): a preset's noise, or a static record's fit.
py::object plan(const std::optional<std::string>& sensor, const std::optional<f64_array>& data,
                std::optional<double> rate_hz, const std::string& unit, double dead_s,
                double duration_s, double min_dwell_s, double max_dwell_s,
                const std::vector<double>& positions, std::optional<double> heading_lat_deg,
                const std::string& order) {
  if (sensor.has_value() == data.has_value())
    raise(usage_error("plan: give either sensor (a preset name or TOML file) or static (samples)"));
  workflow::plan_request req;
  req.dead_s = dead_s;
  req.duration_s = duration_s;
  req.limits.min_dwell_s = min_dwell_s;
  req.limits.max_dwell_s = max_dwell_s;
  req.conversion_s = rig::conversion_time_s(rig::ad7739_config{});
  req.positions_deg = positions;
  req.heading_lat_deg = heading_lat_deg;
  req.order = order;
  if (sensor) {
    const auto p = take(sensor::load_preset(*sensor));
    req.noise = workflow::plan_noise_of(p.params);
    req.noise_source = "sensor " + p.name;
  } else {
    if (!rate_hz || !(*rate_hz > 0.0) || !std::isfinite(*rate_hz))
      raise(parameter_error("rate", "a static record needs its sample rate in Hz (> 0)"));
    const auto y = span_of(*data, "static");
    const analysis::span_samples src(y);
    const double tau0 = 1.0 / *rate_hz;
    const double k = units::deg_per_unit(unit);
    auto noise = without_gil([&](const progress_fn& listen) -> result<method::plan_noise> {
      auto phase = analysis::phase_source::make(src, analysis::input_kind::rate, tau0, listen);
      if (!phase) return phase.err();
      return workflow::plan_noise_of_record(*phase, k, min_dwell_s, req.notes);
    });
    req.noise = take(std::move(noise));
    req.noise_source = "the noise fit of the static record";
    req.static_samples = y;
    req.static_tau0_s = tau0;
    req.static_dps_per_unit = k;
  }
  auto r = take(workflow::plan(req));
  return json_loads(take(io::finite_dump(workflow::plan_json(r), "plan")));
}

// gyroflip.heading: the CLI's `heading` (workflow::find_heading).
py::object heading(const std::vector<std::string>& runs, double lat_deg,
                   const std::optional<std::string>& table_axis,
                   std::optional<double> base_turn_deg, const std::optional<std::string>& sensor,
                   int harmonics) {
  workflow::heading_request q;
  q.runs = runs;
  q.lat_deg = lat_deg;
  if (table_axis) {
    if (*table_axis != "up" && *table_axis != "down")
      raise(parameter_error("table_axis", "table_axis is 'up' or 'down'"));
    q.table_axis_up = *table_axis == "up";
  }
  q.base_turn_deg = base_turn_deg;
  if (sensor) q.sensor = *sensor;
  q.harmonics = harmonics;
  auto h = take(workflow::find_heading(q));
  return json_loads(take(io::finite_dump(workflow::heading_json(h), "heading")));
}

// `gyroflip sensors --json` (workflow::sensors_json), the CLI's checks of its options.
py::object sensors(double dead_s, double lat_deg) {
  if (!(dead_s >= 0.0) || !std::isfinite(dead_s))
    raise(parameter_error("dead_time", "dead_time is a number of s >= 0"));
  if (!(lat_deg >= -85.0 && lat_deg <= 85.0))
    raise(parameter_error("latitude", "latitude is within [-85, 85] deg"));
  return json_loads(take(io::finite_dump(workflow::sensors_json(dead_s, lat_deg), "sensors")));
}

// `gyroflip calibrate --explain --positions A,B,... [--table-axis AXIS] --json`: what a table
// separates, before a run (method::separability_of).
py::object separability(const std::vector<double>& positions_deg, const std::string& table_axis) {
  auto table = position_table::of_angles(positions_deg);
  if (!table) raise(parameter_error("positions", "positions: " + table.err().message));
  const auto sep = method::separability_of(*table, method::table_axis_kind_of(table_axis));
  return json_loads(io::separability_to_json(sep, ""));
}

}  // namespace

void bind_workflow(py::module_& m) {
  m.def("_sensors", &sensors, py::arg("dead_time"), py::arg("latitude"));
  m.def("_separability", &separability, py::arg("positions"), py::arg("table_axis"));
  m.def("_heading", &heading, py::arg("runs"), py::arg("latitude"), py::arg("table_axis"),
        py::arg("base_turn"), py::arg("sensor"), py::arg("harmonics"));
  m.def("_plan", &plan, py::arg("sensor"), py::arg("static"), py::arg("rate"), py::arg("units"),
        py::arg("dead_time"), py::arg("duration"), py::arg("min_dwell"), py::arg("max_dwell"),
        py::arg("positions"), py::arg("heading_latitude"), py::arg("order"));
  m.def("_report", &report, py::arg("files"), py::arg("output"), py::arg("latitude"),
        py::arg("axis"), py::arg("calibration"), py::arg("title"), py::arg("pairing"),
        py::arg("expected_rate"), py::arg("command"), py::arg("next_step"), py::arg("sensor"));
  m.def("_reproduce", &reproduce, py::arg("quick"), py::arg("seed"), py::arg("campaigns"),
        py::arg("output"), py::arg("sensors"), py::arg("command"));
}

}  // namespace gyroflip::python
