/// \file
/// \brief The Allan family and the noise terms for Python: `_curve` (one statistic at the
/// averaging factors asked for, with or without confidence bounds) and `_noise` (the CLI's
/// `noise --json` object). The Python layer (gyroflip/__init__.py) turns these into the
/// allantools-compatible functions and `deviation()`.
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "common.hpp"
#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/cross.hpp"
#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/mapped_file.hpp"
#include "gyroflip/io/noise_report.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/report/figures.hpp"

#include <nlohmann/json.hpp>

namespace gyroflip::python {

namespace {

analysis::input_kind input_of(const std::string& input) {
  if (input == "rate" || input == "freq") return analysis::input_kind::rate;
  if (input == "angle" || input == "phase") return analysis::input_kind::angle;
  throw py::value_error("input must be 'rate' or 'angle' (got '" + input + "')");
}

double tau0_of(double rate_hz) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz))
    throw py::value_error("rate must be a positive, finite sample rate in Hz");
  return 1.0 / rate_hz;
}

// The samples as a sample_source: a NumPy memmap of a file (`file_backed`, checked by the
// Python layer) hands consumed pages back to the kernel, so a 1e9-sample file costs address
// space, not memory; anything else is read in place.
std::unique_ptr<analysis::sample_source> source_of(std::span<const double> y, bool file_backed) {
  if (file_backed) return std::make_unique<io::mapping_samples>(y.data(), y.size());
  return std::make_unique<analysis::span_samples>(y);
}

analysis::tau_spec spec_of(const std::string& taus,
                           const std::optional<std::vector<std::size_t>>& m) {
  if (m) return analysis::tau_spec{analysis::tau_spec::set::list, *m};
  return take(analysis::parse_tau_spec(taus));
}

py::dict curve(const std::string& kind, const f64_array& data, double rate_hz,
               const std::string& input, const std::string& taus,
               const std::optional<std::vector<std::size_t>>& factors, std::optional<double> ci,
               bool file_backed, bool guard, bool bias_correction, std::optional<int> alpha) {
  const auto k = analysis::parse_dev_kind(kind);
  if (!k) throw py::value_error("unknown statistic '" + kind + "'");
  const auto in = input_of(input);
  const double tau0 = tau0_of(rate_hz);
  if (ci) check(analysis::check_confidence_level(*ci));
  if (alpha) check(analysis::check_noise_alpha(*alpha));
  // PDEV, MTIE and TIE rms have no EDF: no interval, no noise type to read (the CLI's nulls).
  if (!analysis::has_edf(*k)) {
    if (guard)
      throw py::value_error("guard applies to the kinds with intervals (not " + kind + ")");
    ci.reset();
  }
  const auto spec = spec_of(taus, factors);
  const auto src = source_of(span_of(data, "data"), file_backed);
  auto pts = without_gil([&](const progress_fn& listen) {
    // Without intervals no phase is needed afterwards: the library picks the cheapest path
    // (ADEV/HDEV of rate samples at octave factors from block sums).
    if (!ci && !bias_correction) return analysis::deviation(*k, *src, in, tau0, spec, listen);
    auto phase = analysis::phase_source::make(*src, in, tau0, listen);
    if (!phase) return result<std::vector<analysis::deviation_point>>(phase.err());
    // A known noise type: the curve, then that type's EDF (no identification).
    auto p = alpha ? analysis::deviation(*k, *phase, spec, listen)
                   : analysis::deviation_with_confidence(
                         *k, *phase, spec, ci.value_or(0.683), listen,
                         guard ? analysis::edf_rule::guarded : analysis::edf_rule::stable32);
    if (p && alpha) analysis::add_confidence(*p, *k, phase->size(), ci.value_or(0.683), *alpha);
    if (p && bias_correction) analysis::correct_total_bias(*p, *k);
    return p;
  });
  const auto points = take(std::move(pts));
  const auto column = [&](auto field) {
    using T = decltype(field(points.front()));
    std::vector<T> v;
    v.reserve(points.size());
    for (const auto& p : points) v.push_back(field(p));
    return to_numpy(v);
  };
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  py::dict d;
  d["m"] = column([](const auto& p) { return static_cast<std::int64_t>(p.m); });
  d["tau_s"] = column([](const auto& p) { return p.tau_s; });
  d["dev"] = column([](const auto& p) { return p.dev; });
  d["n"] = column([](const auto& p) { return static_cast<std::int64_t>(p.n); });
  d["edf"] = column([&](const auto& p) { return ci ? p.edf : nan; });
  d["ci_lo"] = column([&](const auto& p) { return ci ? p.ci_lo : nan; });
  d["ci_hi"] = column([&](const auto& p) { return ci ? p.ci_hi : nan; });
  // The noise type where one was read or given (bounds or bias correction), else NaN (the CLI's
  // null; review E-L2).
  const bool typed = ci || bias_correction;
  d["alpha"] = column([&](const auto& p) { return typed ? static_cast<double>(p.alpha) : nan; });
  return d;
}

// One series' noise analysis (the CLI's per column): `unit` the samples' unit, `quantity` gyro or
// accel (docs/ANALYSIS.md, "Accelerometers").
io::noise_report noise_report_of(const f64_array& data, double rate_hz, const std::string& input,
                                 const std::string& unit, const std::string& quantity, double ci,
                                 double fit_lo_s, double fit_hi_s, bool abba_cycles,
                                 const std::string& name, const std::string& column,
                                 bool file_backed, bool long_taus = false) {
  const auto in = input_of(input);
  const double tau0 = tau0_of(rate_hz);
  check(analysis::check_confidence_level(ci));  // the CLI's rules, from the library
  check(analysis::check_fit_range({fit_lo_s, fit_hi_s}));
  if (quantity != "gyro" && quantity != "accel")
    throw py::value_error("quantity must be 'gyro' or 'accel' (got '" + quantity + "')");
  if ((quantity == "accel") != units::is_accel_unit(unit))
    throw py::value_error("units '" + unit + "' is not a unit of " +
                          (quantity == "accel" ? "an accelerometer (m/s^2, g, mg, ug)"
                                               : "a gyro (deg/s, rad/s, deg/h; deg, rad)"));
  if (quantity == "accel" && in == analysis::input_kind::angle)
    throw py::value_error("an accelerometer record is read as specific force (input='rate')");
  const auto y = span_of(data, "data");
  const auto src = source_of(y, file_backed);
  io::noise_report r;
  r.file = name;
  r.column = column;
  r.quantity = quantity;
  r.input = in == analysis::input_kind::angle ? "angle" : "rate";
  r.units = std::string(units::unit_name(in == analysis::input_kind::angle, unit));
  r.deg_per_unit = quantity == "accel" ? 1.0 : units::deg_per_unit(unit);
  r.mps2_per_unit = units::mps2_per_unit(unit);
  r.tau0_s = tau0;
  r.samples = y.size();
  if (abba_cycles) r.series = method::noise_series_of(method::pairing::abba, tau0);
  auto a = without_gil([&](const progress_fn& listen) {
    auto phase = analysis::phase_source::make(*src, in, tau0, listen);
    if (!phase) return result<analysis::noise_analysis>(phase.err());
    // The default range (fit_taus None) leaves the short taus a filter or line shaped out; a
    // given range is fitted as given (the CLI's --fit-taus).
    const bool given = fit_lo_s > 0.0 || std::isfinite(fit_hi_s);
    return analysis::analyse_noise(*phase, ci, {fit_lo_s, fit_hi_s, !given}, r.series, listen,
                                   long_taus);
  });
  r.result = take(std::move(a));
  return r;
}

py::object noise(const f64_array& data, double rate_hz, const std::string& input,
                 const std::string& unit, const std::string& quantity, double ci, double fit_lo_s,
                 double fit_hi_s, bool abba_cycles, const std::string& name,
                 const std::string& column, bool file_backed) {
  const auto r = noise_report_of(data, rate_hz, input, unit, quantity, ci, fit_lo_s, fit_hi_s,
                                 abba_cycles, name, column, file_backed);
  return json_loads(take(io::finite_dump(io::noise_json(r), "noise")));
}

// The noise figure of several columns (`gyroflip noise --plot`): one figure per sensor, the
// accelerometer's at STEM_accel.EXT beside a gyro's. Returns each column's noise() dict.
py::list noise_plot(const std::vector<f64_array>& data, const std::vector<std::string>& columns,
                    const std::vector<std::string>& unit, const std::vector<std::string>& quantity,
                    double rate_hz, const std::string& input, double ci, double fit_lo_s,
                    double fit_hi_s, bool long_taus, const std::string& path,
                    const std::string& plot_units, const std::string& title) {
  const std::filesystem::path p(path);
  const auto ext = p.extension().string();
  const auto format =
      ext == ".png"   ? report::image_format::png
      : ext == ".svg" ? report::image_format::svg
      : ext == ".pdf"
          ? report::image_format::pdf
          : throw py::value_error("path must end in .png, .svg or .pdf (got '" + path + "')");
  const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
  const std::string stem = p.stem().string();
  std::vector<io::noise_report> all;
  bool gyro = false, accel = false;
  for (std::size_t i = 0; i < data.size(); ++i) {
    all.push_back(noise_report_of(data[i], rate_hz, input, unit[i], quantity[i], ci, fit_lo_s,
                                  fit_hi_s, false, "<array>", columns[i], false, long_taus));
    (quantity[i] == "accel" ? accel : gyro) = true;
  }
  if (!plot_units.empty() &&
      ((units::is_accel_unit(plot_units) && gyro) || (!units::is_accel_unit(plot_units) && accel)))
    throw py::value_error("plot_units '" + plot_units + "' is not a unit of every column's sensor");
  const std::array formats{format};
  for (const std::string q : {"gyro", "accel"}) {
    if (!(q == "accel" ? accel : gyro)) continue;
    std::vector<report::allan_curve> curves;
    for (const auto& r : all)
      if (r.quantity == q) curves.push_back(report::noise_curve(r));
    const std::string u = !plot_units.empty() ? plot_units : q == "accel" ? "mg" : "deg/h";
    auto fig = take(report::noise_figure(curves, u, title.empty() ? "Allan deviation" : title));
    check(report::render(fig, dir, q == "accel" && gyro ? stem + "_accel" : stem, formats));
  }
  py::list out;
  for (const auto& r : all)
    out.append(json_loads(take(io::finite_dump(io::noise_json(r), "noise"))));
  return out;
}

// Kalibr's IMU file from the axes' terms (each (column, N, N resolved, K, K resolved), an
// unresolved term as its upper limit, in Kalibr's units), written atomically; returns its text.
using kalibr_axis_tuple = std::tuple<std::string, double, bool, double, bool>;
std::string write_kalibr(const std::string& path, const std::string& rostopic, double rate_hz,
                         const std::vector<kalibr_axis_tuple>& gyro,
                         const std::vector<kalibr_axis_tuple>& accel,
                         const std::string& gyro_source, const std::string& accel_source) {
  io::kalibr_imu imu;
  imu.rostopic = rostopic;
  imu.update_rate_hz = rate_hz;
  imu.gyro_source = gyro_source;
  imu.accel_source = accel_source;
  const auto term = [](double v, bool resolved) {
    analysis::noise_term t;
    t.resolved = resolved;
    t.value = t.lo = t.hi = t.range_lo = t.range_hi = v;
    return t;
  };
  for (const auto& [c, n, nr, k, kr] : gyro) imu.gyro.push_back({c, term(n, nr), term(k, kr)});
  for (const auto& [c, n, nr, k, kr] : accel) imu.accel.push_back({c, term(n, nr), term(k, kr)});
  auto text = take(io::kalibr_yaml(imu));
  check(io::write_file_atomically(path, text));
  return text;
}

std::optional<std::pair<std::string, std::string>> unit_of_column(const std::string& name) {
  const auto u = io::unit_of_column(name);
  if (!u) return std::nullopt;
  return std::pair{u->quantity, u->unit};
}

// A curve's columns as a dict of NumPy arrays (m, tau_s, dev, n).
py::dict columns_of(const std::vector<analysis::deviation_point>& points) {
  std::vector<std::int64_t> m, n;
  std::vector<double> tau, dev;
  for (const auto& p : points) {
    m.push_back(static_cast<std::int64_t>(p.m));
    n.push_back(static_cast<std::int64_t>(p.n));
    tau.push_back(p.tau_s);
    dev.push_back(p.dev);
  }
  py::dict d;
  d["m"] = to_numpy(m);
  d["tau_s"] = to_numpy(tau);
  d["dev"] = to_numpy(dev);
  d["n"] = to_numpy(n);
  return d;
}

// GRADEV on data with NaN gaps (the array is read as it is; NaN allowed).
py::dict gradev(const f64_array& data, double rate_hz, const std::string& input,
                const std::vector<std::size_t>& factors) {
  const auto y = span_of(data, "data");
  const analysis::tau_spec spec{analysis::tau_spec::set::list, factors};
  auto r = without_gil([&](const progress_fn&) {
    return analysis::gradev(y, input_of(input), tau0_of(rate_hz), spec);
  });
  return columns_of(take(std::move(r)));
}

py::dict gcodev(const f64_array& a, const f64_array& b, double rate_hz, const std::string& input,
                const std::vector<std::size_t>& factors) {
  const analysis::tau_spec spec{analysis::tau_spec::set::list, factors};
  auto r = without_gil([&](const progress_fn&) {
    return analysis::gcodev(span_of(a, "data_1"), span_of(b, "data_2"), input_of(input),
                            tau0_of(rate_hz), spec);
  });
  return columns_of(take(std::move(r)));
}

py::list dynamic(const std::string& kind, const f64_array& data, double rate_hz,
                 const std::string& input, double window_s, std::optional<double> step_s,
                 const std::string& taus, std::optional<double> ci) {
  const auto k = analysis::parse_dev_kind(kind);
  if (!k) throw py::value_error("unknown statistic '" + kind + "'");
  if (ci) check(analysis::check_confidence_level(*ci));
  const auto spec = take(analysis::parse_tau_spec(taus));
  // Kinds without an EDF get no interval columns' values (NaN), as deviation() gives them.
  const auto level = ci && analysis::has_edf(*k) ? ci : std::nullopt;
  const auto y = span_of(data, "data");
  const double tau0 = tau0_of(rate_hz);
  const auto [window, step] = take(analysis::dynamic_samples(window_s, step_s, tau0, y.size()));
  auto r = without_gil([&](const progress_fn& listen) {
    return analysis::dynamic_deviation(*k, y, input_of(input), tau0, window, step, spec, listen,
                                       level);
  });
  const auto windows = take(std::move(r));
  py::list out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& w : windows) {
    auto d = columns_of(w.curve);
    std::vector<double> lo, hi, edf, alpha;
    for (const auto& p : w.curve) {
      lo.push_back(level ? p.ci_lo : nan);
      hi.push_back(level ? p.ci_hi : nan);
      edf.push_back(level ? p.edf : nan);
      alpha.push_back(level ? static_cast<double>(p.alpha) : nan);
    }
    d["ci_lo"] = to_numpy(lo);
    d["ci_hi"] = to_numpy(hi);
    d["edf"] = to_numpy(edf);
    d["alpha"] = to_numpy(alpha);
    d["start_s"] = w.start_s;
    out.append(d);
  }
  return out;
}

// Greenhall & Riley's EDF for (d, overlapping, modified) as SP1065 names the variances.
double edf_of(int alpha, int d, std::size_t m, std::size_t n, bool overlapping, bool modified) {
  const auto e = analysis::edf_greenhall(alpha, d, m, n, overlapping, modified);
  if (!e) throw py::value_error("no EDF for this (alpha, d, overlapping, modified)");
  return *e;
}

}  // namespace

void bind_analysis(py::module_& m) {
  m.def("_gradev", &gradev, py::arg("data"), py::arg("rate"), py::arg("input"), py::arg("factors"));
  m.def("_gcodev", &gcodev, py::arg("a"), py::arg("b"), py::arg("rate"), py::arg("input"),
        py::arg("factors"));
  m.def("_dynamic", &dynamic, py::arg("kind"), py::arg("data"), py::arg("rate"), py::arg("input"),
        py::arg("window_s"), py::arg("step_s"), py::arg("taus"), py::arg("ci") = std::nullopt);
  // The one table of per-statistic facts (analysis::dev_table): Python's kind lists are read
  // from it, as the command line's are.
  m.def("_dev_facts", [] {
    py::list out;
    for (const auto& f : analysis::dev_table) {
      py::dict d;
      d["name"] = std::string(f.name);
      d["reference"] = std::string(f.reference);
      d["extended"] = f.extended;
      d["angle_unit"] = f.angle_unit;
      d["edf"] = f.edf;
      d["bias_correction"] = f.bias_correction;
      d["span_divisor"] = f.span_divisor;
      d["even_m_only"] = f.even_m_only;
      d["tau_factor"] = f.tau_factor;
      out.append(d);
    }
    return out;
  });
  m.def("_chi2_quantile", &analysis::chi2_quantile, py::arg("p"), py::arg("dof"));
  m.def("_edf", &edf_of, py::arg("alpha"), py::arg("d"), py::arg("m"), py::arg("n"),
        py::arg("overlapping"), py::arg("modified"));
  m.def("_edf_kind", [](const std::string& kind, int alpha, std::size_t mm, std::size_t n) {
    const auto k = analysis::parse_dev_kind(kind);
    if (!k) throw py::value_error("unknown statistic '" + kind + "'");
    return analysis::edf(*k, alpha, mm, n);
  });
  m.def("_curve", &curve, py::arg("kind"), py::arg("data"), py::arg("rate"), py::arg("input"),
        py::arg("taus"), py::arg("factors"), py::arg("ci"), py::arg("file_backed"),
        py::arg("guard") = false, py::arg("bias_correction") = false,
        py::arg("alpha") = std::nullopt);
  m.def("_noise", &noise, py::arg("data"), py::arg("rate"), py::arg("input"), py::arg("units"),
        py::arg("quantity"), py::arg("ci"), py::arg("fit_lo_s"), py::arg("fit_hi_s"),
        py::arg("abba_cycles"), py::arg("name"), py::arg("column"), py::arg("file_backed"));
  m.def("_noise_plot", &noise_plot, py::arg("data"), py::arg("columns"), py::arg("units"),
        py::arg("quantity"), py::arg("rate"), py::arg("input"), py::arg("ci"), py::arg("fit_lo_s"),
        py::arg("fit_hi_s"), py::arg("long_taus"), py::arg("path"), py::arg("plot_units"),
        py::arg("title"));
  m.def("_write_kalibr", &write_kalibr, py::arg("path"), py::arg("rostopic"), py::arg("rate"),
        py::arg("gyro"), py::arg("accel"), py::arg("gyro_source"), py::arg("accel_source"));
  m.def("_unit_of_column", &unit_of_column, py::arg("name"));
}

}  // namespace gyroflip::python
