/// \file
/// \brief The method for Python: `_calibrate` and `_compensate` on a recording's columns,
/// `_calibrate_runs` on recordings (the workflow's multi-run calibration),
/// `_simulate` (the rig simulator, one row per dwell) and `_read_recording` (CSV or `.gfr`).
/// Results are the CLI's JSON objects (parsed) plus NumPy columns.
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include <nlohmann/json.hpp>

#include "common.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/compensation.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/method/runs.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/rigdata/recording_source.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/calibrate.hpp"
#include "gyroflip/workflow/compensate.hpp"
#include "gyroflip/workflow/recordings.hpp"
#include "gyroflip/workflow/simulate.hpp"

namespace gyroflip::python {

namespace {

constexpr const char* arrays_name = "<arrays>";  // the "file" of columns passed in memory

method::pairing pairing_of(const std::string& name) {
  const auto p = method::parse_pairing(name);
  if (!p)
    throw py::value_error("pairing must be '" + method::scheme_names_joined("' or '") + "' (got '" +
                          name + "')");
  return *p;
}

// The columns of a recording passed as arrays.
struct columns {
  f64_array time_s, angle_deg, rate_dps;
  std::optional<f64_array> temp_c, n_avg;
  std::optional<f64_array> positions_deg;  ///< the table (none: the paper's 0/180)
};

io::table_rows rows_of(const columns& c, double tol) {
  io::recording_columns rc{span_of(c.time_s, "time_s"),
                           span_of(c.angle_deg, "angle_deg"),
                           span_of(c.rate_dps, "rate_dps"),
                           {},
                           {}};
  if (c.temp_c) rc.temp_c = span_of(*c.temp_c, "temp_c");
  if (c.n_avg) rc.n_avg = span_of(*c.n_avg, "n_avg");
  if (c.positions_deg) rc.positions_deg = span_of(*c.positions_deg, "positions_deg");
  return take(io::rows_of_columns(rc, tol));
}

method::recording_cycles cycles_of(const columns& c, method::pairing p, double tol) {
  const auto rows = rows_of(c, tol);
  auto cycles = take(method::cycles_of_rows(arrays_name, rows.rows, p, {}, rows.positions));
  cycles.has_temp = c.temp_c.has_value();
  return cycles;
}

// One field of every element of `v` as a float64 NumPy array.
template <class T, class F>
py::array_t<double> column(const std::vector<T>& v, F T::*field) {
  std::vector<double> out;
  out.reserve(v.size());
  for (const auto& x : v) out.push_back(static_cast<double>(x.*field));
  return to_numpy(out);
}

py::dict cycle_columns(const std::vector<method::cycle>& cycles) {
  py::dict d;
  d["time_s"] = column(cycles, &method::cycle::time_s);
  d["rate_dps"] = column(cycles, &method::cycle::rate_dps);
  d["bias_dps"] = column(cycles, &method::cycle::bias_dps);
  d["temp_c"] = column(cycles, &method::cycle::temp_c);
  return d;
}

// The sensor whose specification the stationarity test checks (a preset name or TOML file).
std::optional<sensor::preset> preset_of(const std::optional<std::string>& sensor) {
  if (!sensor) return std::nullopt;
  return take(sensor::load_preset(*sensor));
}

py::dict calibrate(const columns& c, std::optional<double> lat_deg,
                   const std::optional<std::string>& axis, const std::string& pairing, double tol,
                   const std::optional<std::string>& sensor, bool strict,
                   const std::optional<std::string>& table_axis) {
  io::calibration_record rec;
  rec.pairing = pairing_of(pairing);
  rec.geometry = geometry_of(lat_deg, axis);
  const auto preset = preset_of(sensor);
  const auto rc = cycles_of(c, rec.pairing, tol);
  rec.sensor = io::sensor_of({});
  rec.pooled = take(method::calibrate(rc.cycles));
  // The stationarity test, as the CLI's (workflow::calibrate_runs).
  const auto st = method::check_stationarity(
      rc.cycles, rec.pooled,
      workflow::stationarity_inputs_of(rec.pairing, preset ? &*preset : nullptr, rec.geometry));
  std::vector<std::string> warnings;
  (void)take(workflow::judge_run(
      {arrays_name, {}, "calibration", "sensor= (a preset name or a TOML file)"}, st, strict,
      warnings));
  rec.files.push_back({arrays_name, rec.pooled, std::nullopt, st});
  rec.pooled.stderr_correlated_dps =
      method::pooled_correlated_stderr(workflow::calibrations_of(rec.files));  // as the CLI
  if (rec.pairing == method::pairing::harmonic) {
    // The named terms with their covariance and the separability report, as the CLI's
    // (workflow::add_harmonic_terms over method::fit_harmonics of the rows).
    const auto rows = rows_of(c, tol);
    method::harmonic_options o;
    o.separable = true;
    auto f = method::fit_harmonics(method::indexed_dwells(rows.rows), rows.positions, o);
    if (!f) raise(input_error({arrays_name}, f.err().message));
    workflow::add_harmonic_terms(std::span(&*f, 1), rows.positions, table_axis.value_or(""), rec);
  }
  py::dict d = json_loads(take(io::to_json(rec)));
  d["warnings"] = warnings;
  for (const auto& cy : rc.cycles)  // the temperature may be absent (NaN)
    check(io::check_finite(std::array{cy.time_s, cy.rate_dps, cy.bias_dps}, "calibrate"));
  d["cycle_values"] = cycle_columns(rc.cycles);
  return d;
}

// The same as `gyroflip calibrate FILE... --json` (workflow::calibrate_runs), with the warnings.
py::dict calibrate_runs(const std::vector<std::string>& files, std::optional<double> lat_deg,
                        const std::optional<std::string>& axis, const std::string& pairing,
                        std::optional<std::size_t> degree, double tol,
                        const std::optional<std::string>& sensor, bool strict) {
  workflow::calibrate_request req;
  req.sensor = preset_of(sensor);
  req.strict = strict;
  req.sensor_hint = "sensor= (a preset name or a TOML file)";
  req.files = files;
  req.pairing = pairing_of(pairing);
  req.geometry = geometry_of(lat_deg, axis);
  req.degree = degree;
  req.angle_tolerance_deg = tol;
  auto run =
      without_gil([&](const progress_fn& listen) { return workflow::calibrate_runs(req, listen); });
  const auto res = take(std::move(run));
  py::dict d = json_loads(take(io::to_json(res.record)));
  d["warnings"] = res.warnings;
  return d;
}

// The dN to subtract: a constant, or a calibration (JSON text) with its dN(T) model if it has one.
workflow::delta_n_source delta_n_of(std::optional<double> delta_n_dps,
                                    const std::optional<std::string>& calibration_json) {
  if (delta_n_dps.has_value() == calibration_json.has_value())
    throw py::value_error("give either delta_n_dps or calibration");
  if (delta_n_dps) {
    auto dn = take(workflow::delta_n_of_value(*delta_n_dps));  // the CLI's --delta-n rule
    dn.source = "delta_n_dps";
    return dn;
  }
  return take(workflow::delta_n_of_json(*calibration_json, "calibration"));
}

py::dict compensate(const columns& c, std::optional<double> delta_n_dps,
                    const std::optional<std::string>& calibration_json,
                    const std::optional<std::string>& pairing, double drift_window_s, double tol,
                    bool strict) {
  const auto dn = delta_n_of(delta_n_dps, calibration_json);
  auto runs = take(workflow::check_calibration_runs(dn, strict));
  // The CLI's reading of the calibration's uncertainty and its --strict (no recording header:
  // the file's stated repeatability, checked against its own parts).
  const auto budget = workflow::compensation_budget(dn, {}, arrays_name, runs.warnings);
  if (dn.record && strict) check(workflow::refuse_unvouched(dn, budget, runs.unchecked));
  auto p = pairing ? pairing_of(*pairing) : dn.pairing.value_or(method::pairing::abba);
  check(method::check_drift_window(drift_window_s));
  // A harmonic calibration (issue 33): its terms applied as the CLI applies them
  // (workflow::read_harmonic_cycles: at each position, or a 0/180 pair's c1 cos + s1 sin).
  const auto terms = dn.record ? workflow::harmonic_terms_of(*dn.record) : std::nullopt;
  std::optional<workflow::harmonic_application> applied;
  method::recording_cycles rc;
  if (terms) {
    const auto rows = rows_of(c, tol);
    method::rows_in_memory source(arrays_name, rows.rows, {}, {}, rows.positions);
    auto hc = take(workflow::read_harmonic_cycles(
        source, *terms, dn.model,
        pairing ? std::optional<method::pairing>(p) : std::optional<method::pairing>()));
    p = hc.pairing;
    applied = std::move(hc.applied);
    rc = std::move(hc.cycles);
    rc.has_temp = c.temp_c.has_value();
  } else {
    rc = cycles_of(c, p, tol);
  }
  const auto& model = applied ? applied->model : dn.model;
  if (model.degree() > 0 && !rc.has_temp)
    throw py::value_error("no temp_c given, but the calibration's dN(T) model needs temperatures");
  // The CLI's compensate loop and summary (every number checked finite, as the CLI).
  const auto comp =
      take(workflow::compensate_cycles(rc.cycles, model, drift_window_s, "compensate"));
  py::dict res;
  using cc = method::compensated_cycle;
  res["time_s"] = column(comp.cycles, &cc::time_s);
  res["rate_dps"] = column(comp.cycles, &cc::rate_dps);
  res["bias_dps"] = column(comp.cycles, &cc::bias_dps);
  res["temp_c"] = column(comp.cycles, &cc::temp_c);
  res["delta_n_dps"] = column(comp.cycles, &cc::delta_n_dps);
  // As the CLI: the dN stated is the one subtracted (a harmonic calibration's for this run).
  auto stated = dn;
  stated.model = model;
  res["summary"] = json_loads(take(io::finite_dump(
      workflow::compensation_json(
          comp, arrays_name, stated, p,
          workflow::applied_errors_of(dn, rc.cycles, budget, applied ? &*applied : nullptr)),
      "compensate")));
  res["warnings"] = runs.warnings;
  if (applied) res["applied"] = applied->how;
  return res;
}

// Rows as columns: their angles from `table` (NaN while the table turns), their position indices
// (-1 while it turns) and the table's angles.
py::dict rows_dict(const std::vector<method::row>& rows, const position_table& table) {
  py::dict d;
  std::vector<double> angle;
  angle.reserve(rows.size());
  for (const auto& r : rows)
    angle.push_back(table.holds(r.position) ? table.angle_deg(r.position) : method::no_value);
  std::vector<double> positions_deg;
  for (const auto& p : table.positions()) positions_deg.push_back(p.angle_deg);
  d["time_s"] = column(rows, &method::row::time_s);
  d["angle_deg"] = to_numpy(angle);
  d["position"] = column(rows, &method::row::position);
  d["positions_deg"] = to_numpy(positions_deg);
  d["rate_dps"] = column(rows, &method::row::rate_dps);
  d["temp_c"] = column(rows, &method::row::temp_c);
  d["n_avg"] = column(rows, &method::row::n_avg);
  return d;
}

py::dict metadata_dict(const std::vector<io::csv_metadata>& meta) {
  py::dict d;
  for (const auto& m : meta) d[py::str(m.key)] = m.value;
  return d;
}

py::dict read_recording(const std::string& path, double tol) {
  const auto r = take(rigdata::read_recording_rows(path, tol));
  py::dict d = rows_dict(r.rows, r.positions);
  d["metadata"] = metadata_dict(r.metadata);
  d["warnings"] = r.warnings;
  return d;
}

py::dict simulate(const std::string& sensor, double duration_s, std::uint64_t seed, double lat_deg,
                  const std::string& axis, int n_avg, double settle_s,
                  const std::optional<std::string>& temp, const std::string& rate,
                  double power_on_before_s, bool flip, const std::vector<double>& positions,
                  const std::string& order, std::optional<double> azimuth_deg,
                  const std::string& table_axis, double tilt_mrad, double tilt_azimuth_deg) {
  rig::simulation_config c;
  const auto preset = take(sensor::load_preset(sensor));
  c.sensor = preset.params;
  c.rate = take(rig::profile::parse_rate(rate));
  c.temperature = temp ? take(rig::profile::parse_temperature(*temp))
                       : rig::profile::constant(preset.params.temp_ref_c);
  c.lat_deg = lat_deg;
  c.axis = axis;
  c.table_axis = table_axis;
  if (azimuth_deg) {
    if (axis != "north")
      raise(usage_error("azimuth and axis both name the sensitive axis: give one"));
    c.mount.azimuth_deg = *azimuth_deg;
  }
  c.mount.tilt_mrad = tilt_mrad;
  c.mount.tilt_azimuth_deg = tilt_azimuth_deg;
  if (order != "auto" && order != "sweep" && order != "cycle")
    raise(parameter_error("order", "order is 'auto', 'sweep' or 'cycle'"));
  c.order = order == "sweep"   ? rig::visit_order::sweep
            : order == "cycle" ? rig::visit_order::cycle
                               : rig::visit_order::automatic;
  c.rig.positions_deg = positions;
  c.rig.n_avg = n_avg;
  c.rig.settle_s = settle_s;
  c.flip = flip;
  c.duration_s = duration_s;
  c.power_on_before_s = power_on_before_s;
  c.seed = seed;
  auto run = without_gil([&](const progress_fn& listen) {
    return workflow::simulate_rows(c, true, listen);  // `gyroflip simulate`'s simulation
  });
  const auto sim = take(std::move(run));
  const auto& rows = sim.rows;
  using dr = rig::dwell_row;
  py::dict d;
  d["time_s"] = column(rows, &dr::time_s);
  d["angle_deg"] = column(rows, &dr::angle_deg);
  d["rate_dps"] = column(rows, &dr::rate_dps);
  d["temp_c"] = column(rows, &dr::temp_c);
  d["n_avg"] = column(rows, &dr::n_avg);
  d["bias_dps"] = column(rows, &dr::bias_dps);
  d["g_term_dps"] = column(rows, &dr::g_term_dps);
  d["earth_dps"] = column(rows, &dr::earth_dps);
  d["input_dps"] = column(rows, &dr::input_dps);
  d["delta_n_truth_dps"] = sim.truth.delta_n_dps;
  d["sensor"] = preset.name;
  return d;
}

}  // namespace

void bind_method(py::module_& m) {
  py::class_<columns>(m, "_Columns")
      .def(py::init<f64_array, f64_array, f64_array, std::optional<f64_array>,
                    std::optional<f64_array>, std::optional<f64_array>>());
  m.def("_calibrate", &calibrate, py::arg("columns"), py::arg("latitude"), py::arg("axis"),
        py::arg("pairing"), py::arg("angle_tolerance_deg"), py::arg("sensor"), py::arg("strict"),
        py::arg("table_axis"));
  m.def("_calibrate_runs", &calibrate_runs, py::arg("files"), py::arg("latitude"), py::arg("axis"),
        py::arg("pairing"), py::arg("degree"), py::arg("angle_tolerance_deg"), py::arg("sensor"),
        py::arg("strict"));
  m.def("_compensate", &compensate, py::arg("columns"), py::arg("delta_n_dps"),
        py::arg("calibration_json"), py::arg("pairing"), py::arg("drift_window_s"),
        py::arg("angle_tolerance_deg"), py::arg("strict"));
  m.def("_read_recording", &read_recording, py::arg("path"), py::arg("angle_tolerance_deg"));
  m.def("_simulate", &simulate, py::arg("sensor"), py::arg("duration_s"), py::arg("seed"),
        py::arg("latitude"), py::arg("axis"), py::arg("n_avg"), py::arg("settle_s"),
        py::arg("temp"), py::arg("rate"), py::arg("power_on_before_s"), py::arg("flip"),
        py::arg("positions"), py::arg("order"), py::arg("azimuth"), py::arg("table_axis"),
        py::arg("tilt_mrad"), py::arg("tilt_azimuth"));
}

}  // namespace gyroflip::python
