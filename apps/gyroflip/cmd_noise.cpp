/// \file
/// \brief `gyroflip noise`: IEEE 952 noise terms (Q, N, B, K, R) with intervals and units.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cmd_adev.hpp"
#include "finite_output.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/noise_report.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/report/figures.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

using nlohmann::json;

std::string show(const analysis::noise_term& t, double to_unit) {
  if (!t.resolved) return fmt::format("not resolved (< {:.4g})", t.hi * to_unit);
  return fmt::format("{:.4g}  [{:.4g}, {:.4g}]", t.value * to_unit, t.lo * to_unit, t.hi * to_unit);
}

// A term's value, or for an unresolved term its upper limit.
double value_or_limit(const analysis::noise_term& t) {
  return t.resolved ? t.value : t.hi;
}

// The term in another unit, for the text's "= ..." (the value, or its upper limit).
std::string also(const analysis::noise_term& t, double to_unit) {
  return fmt::format("{}{:.4g}", t.resolved ? "" : "< ", value_or_limit(t) * to_unit);
}

// One column's OADEV, fitted terms and read-offs (in the samples' unit).
using column_noise = io::noise_report;

// `--fit-taus LO:HI` (s): the taus the model is fitted to (the library's rule).
result<analysis::tau_range> fit_range(const std::string& spec) {
  if (spec.empty()) return analysis::tau_range{};
  const auto v = text::to_doubles(spec, ':');
  if (!v || v->size() != 2)
    return usage_error("--fit-taus: LO:HI in seconds, 0 <= LO < HI; got " + spec);
  const analysis::tau_range r{(*v)[0], (*v)[1], false};  // a given range is fitted as given
  if (auto s = analysis::check_fit_range(r); !s) return s.err();
  return r;
}

// A quantity's name in messages.
const char* sensor_name(const std::string& quantity) {
  return quantity == "accel" ? "an accelerometer" : "a gyro";
}

// The sensor and unit of one column (docs/ANALYSIS.md, "Accelerometers"): --units when given,
// else the unit the column's name states, else --quantity's default unit (deg/s, m/s^2).
// Contradictions are usage errors naming the column.
result<io::column_unit> sensor_of(const noise_options& o, const series_input& in,
                                  const std::string& column) {
  const auto named = io::unit_of_column(column);
  io::column_unit u;
  if (in.units_given) {
    u = {units::is_accel_unit(in.units) ? "accel" : "gyro", in.units};
    if (named && named->quantity != u.quantity)
      return usage_error(
          fmt::format("{}: column {} is named in {} ({}), but --units {} is a unit of {}", in.file,
                      printable(column, 60), named->unit, sensor_name(named->quantity), in.units,
                      sensor_name(u.quantity)));
  } else if (named) {
    u = *named;
  } else {
    u = o.quantity == "accel" ? io::column_unit{"accel", "m/s^2"}
                              : io::column_unit{"gyro", in.units};
  }
  if (!o.quantity.empty() && o.quantity != u.quantity)
    return usage_error(fmt::format("{}: column {} is in {}, a unit of {}, not of --quantity {}",
                                   in.file, printable(column, 60), u.unit, sensor_name(u.quantity),
                                   o.quantity));
  if (u.quantity == "accel" && in.input == "angle")
    return usage_error(
        "an accelerometer record is read as specific force (--input rate); integrated velocity "
        "is not supported");
  return u;
}

result<column_noise> noise_of(const noise_options& o, const series_input& opts,
                              const analysis::tau_range& range, const analysis_input& in,
                              const io::column_unit& sensor) {
  column_noise c;
  c.file = opts.file;
  c.column = in.column;
  c.input = opts.input;
  c.quantity = sensor.quantity;
  c.units = std::string(units::unit_name(opts.input == "angle", sensor.unit));
  c.deg_per_unit = sensor.quantity == "accel" ? 1.0 : units::deg_per_unit(sensor.unit);
  c.mps2_per_unit = units::mps2_per_unit(sensor.unit);
  c.tau0_s = in.phase.tau0_s();
  c.samples = in.series.samples().size();
  // The rate column of `gyroflip compensate`: a demodulator's estimates, whose white-noise shape
  // its scheme states (abba: correlated cycles).
  for (const auto& m : in.series.metadata())
    if (m.key == "pairing" && opts.input == "rate")
      if (const auto p = method::parse_pairing(m.value))
        c.series = method::noise_series_of(*p, c.tau0_s);
  result<analysis::noise_analysis> a = error{};
  if (in.parts.empty()) {
    progress bar("noise of " + opts.file, 1000);
    a = analysis::analyse_noise(in.phase, o.ci, range, c.series, per_mille(bar), o.long_taus);
    bar.finish();
  } else {
    // A .gfr with gaps under --gaps split: every gap-free stretch, pooled (no term spans a gap).
    std::vector<const analysis::phase_source*> parts;
    c.samples = 0;
    for (const auto& p : in.parts) {
      parts.push_back(&p.phase);
      c.samples += p.series.samples().size();
    }
    if (o.long_taus)
      note(fmt::format("{}: --long-taus is not drawn for stretches pooled across gaps", opts.file));
    a = analysis::analyse_noise(parts, o.ci, range, c.series);
  }
  // Too few points for the fit is a property of this input (too short a series): name it.
  if (!a)
    return input_error({opts.file}, a.err().message + (o.fit_taus.empty() ? "" : " in --fit-taus"));
  if (a->terms.chi2_per_dof > 4.0)
    warn(
        fmt::format("{}: column {}: the noise model fits the curve poorly (chi2/dof {:.3g}): "
                    "other noise (a sinusoid, a temperature swing) or a bad range; see the misfit "
                    "points, or fit a range with --fit-taus LO:HI",
                    opts.file, printable(c.column, 60), a->terms.chi2_per_dof));
  c.result = std::move(*a);
  return c;
}

// The fit's range and quality, one line of the text.
std::string fit_line(const noise_options& o, const analysis::noise_terms& f) {
  return fmt::format(
      "  fit over tau {:g} to {:g} s{}, chi2/dof {:.3g}; intervals include the spread over {} fit "
      "ranges\n",
      f.fit_tau_lo_s, f.fit_tau_hi_s, o.fit_taus.empty() ? "" : " (--fit-taus)", f.chi2_per_dof,
      f.fit_ranges);
}

// An accelerometer's terms (IEEE Std 1293-2018): VRW, bias instability, acceleration random
// walk, in m/s^2 units and g units (g_n = 9.80665 m/s^2).
void append_accel_text(std::string& text, const noise_options& o, const column_noise& c) {
  const auto& f = c.result.terms;
  const double k = c.mps2_per_unit;
  const double mg = k / units::standard_gravity_mps2 * 1e3;
  const double rth = units::deg_rth_per_deg_rts;
  const auto out = std::back_inserter(text);
  fmt::format_to(out,
                 "{}: column {} (accelerometer), {} samples at {:g} Hz in {}, IEEE 1293 terms "
                 "from OADEV ({:g} % intervals)\n",
                 c.file, printable(c.column, 60), c.samples, 1.0 / c.tau0_s, c.units,
                 100.0 * f.level);
  fmt::format_to(out,
                 "  velocity random walk N  {} m/s^2/sqrt(Hz) = {} m/s/sqrt(h) = {} ug/sqrt(Hz) "
                 "(two-sided density)\n",
                 show(f.arw, k), also(f.arw, k * rth), also(f.arw, mg * 1e3));
  if (std::isfinite(c.result.adev_1s))
    fmt::format_to(out,
                   "                          ADEV(1 s) {:.4g} m/s^2/sqrt(Hz) (ADEV at tau {:g} s "
                   "x sqrt(tau)), {:.4g} less the other fitted terms there\n",
                   c.result.adev_1s * std::sqrt(c.result.adev_1s_tau_s) * k, c.result.adev_1s_tau_s,
                   c.result.adev_1s_arw * k);
  fmt::format_to(out,
                 "  bias instability  B     {} mg (IEEE 952 fit)   = {} m/s^2;  floor/0.664 {:.4g} "
                 "mg;  raw floor {:.4g} mg at tau {:g} s{}\n",
                 show(f.bias_instability, mg), also(f.bias_instability, k),
                 f.bias_floor_dev * mg / 0.6643, f.bias_floor_dev * mg, f.bias_floor_tau_s,
                 f.bias_floor_reached ? "" : " (no floor: OADEV still falls)");
  fmt::format_to(out, "  acceleration random walk K  {} m/s^3/sqrt(Hz) = {} mg/sqrt(h)\n",
                 show(f.rrw, k), also(f.rrw, mg * rth));
  fmt::format_to(out, "  quantization      Q     {} m/s\n", show(f.quantization, k));
  fmt::format_to(out, "  ramp              R     {} mg/h\n",
                 show(f.rate_ramp, mg * units::s_per_h));
  fmt::format_to(out, "{}", fit_line(o, f));
  for (const auto& n : f.notes)
    if (n.find("not resolved by the data") == std::string::npos)
      fmt::format_to(out, "  note: {}\n", n);
}

void append_text(std::string& text, const noise_options& o, const column_noise& c) {
  if (c.quantity == "accel") return append_accel_text(text, o, c);
  const auto& f = c.result.terms;
  const double k = c.deg_per_unit;
  const double k_rad = k * units::rad_per_deg;
  const auto out = std::back_inserter(text);
  fmt::format_to(out,
                 "{}: column {}, {} samples at {:g} Hz in {}, IEEE 952 terms from OADEV ({:g} % "
                 "intervals)\n",
                 c.file, printable(c.column, 60), c.samples, 1.0 / c.tau0_s, c.units,
                 100.0 * f.level);
  fmt::format_to(out,
                 "  angle random walk N    {} deg/sqrt(h)   = {} deg/s/sqrt(Hz) = {} rad/s/sqrt(Hz)"
                 " (two-sided density; one-sided sqrt(2) N = {} deg/s/sqrt(Hz))\n",
                 show(f.arw, k * units::deg_rth_per_deg_rts), also(f.arw, k), also(f.arw, k_rad),
                 also(analysis::noise_term{f.arw.resolved, std::numbers::sqrt2 * f.arw.value, 0.0,
                                           std::numbers::sqrt2 * f.arw.hi},
                      k));
  if (std::isfinite(c.result.adev_1s))
    fmt::format_to(
        out,
        "                         ADEV(1 s) {:.4g} deg/sqrt(h) (ADEV at tau {:g} s x "
        "sqrt(tau): the datasheet reading), {:.4g} less the other fitted terms there\n",
        c.result.adev_1s * std::sqrt(c.result.adev_1s_tau_s) * k * units::deg_rth_per_deg_rts,
        c.result.adev_1s_tau_s, c.result.adev_1s_arw * k * units::deg_rth_per_deg_rts);
  const double floor_dph = f.bias_floor_dev * k * units::dph_per_dps;
  fmt::format_to(out,
                 "  bias instability  B    {} deg/h (IEEE 952 fit)   = {} rad/s;  floor/0.664 "
                 "{:.4g} deg/h;  datasheet \"bias stability\" (raw floor) {:.4g} deg/h at tau {:g} "
                 "s{}\n",
                 show(f.bias_instability, k * units::dph_per_dps), also(f.bias_instability, k_rad),
                 floor_dph / 0.6643, floor_dph, f.bias_floor_tau_s,
                 f.bias_floor_reached ? "" : " (no floor: OADEV still falls)");
  fmt::format_to(out, "  rate random walk  K    {} deg/h/sqrt(h)   = {} rad/s^2/sqrt(Hz)\n",
                 show(f.rrw, k * units::dph_rth_per_dps_rts), also(f.rrw, k_rad));
  fmt::format_to(out, "  quantization      Q    {} deg\n", show(f.quantization, k));
  fmt::format_to(out, "  rate ramp         R    {} deg/h^2\n",
                 show(f.rate_ramp, k * units::dph2_per_dps2));
  fmt::format_to(out, "{}", fit_line(o, f));
  const auto& r = c.result.readoffs;
  const auto line = [](const std::optional<double>& v, double to, double tau, const char* slope) {
    return v ? fmt::format("{:.4g} (slope {} at tau {:.3g} s)", *v * to, slope, tau)
             : fmt::format("- (no slope {} on the curve)", slope);
  };
  fmt::format_to(out,
                 "  read off the curve: N {} deg/sqrt(h), K {} deg/h/sqrt(h), B = floor/0.664 "
                 "{:.4g} deg/h (floor {:.4g} deg/h at tau {:.3g} s, {})\n",
                 line(r.arw, k * units::deg_rth_per_deg_rts, r.arw_from_tau_s, "-1/2"),
                 line(r.rrw, k * units::dph_rth_per_dps_rts, r.rrw_from_tau_s, "+1/2"),
                 r.bias_instability * k * units::dph_per_dps, r.floor_dev * k * units::dph_per_dps,
                 r.floor_tau_s, r.floor_is_minimum ? "a minimum" : "the curve still falls there");
  for (const auto& n : f.notes)
    if (n.find("not resolved by the data") == std::string::npos)
      fmt::format_to(out, "  note: {}\n", n);
}

// `noise -o FILE.csv`: one row per column and term, in the field's units, with the interval (or
// the upper limit of an unresolved term) and the read-off beside the fit.
std::string terms_csv(const std::vector<column_noise>& all) {
  std::string t = "column,term,unit,value,lo,hi,resolved,read_off\n";
  for (const auto& c : all) {
    const double k = c.deg_per_unit;
    const auto& f = c.result.terms;
    const auto& r = c.result.readoffs;
    const auto row = [&](const char* term, const char* unit, const analysis::noise_term& x,
                         double to, std::optional<double> read_off) {
      const std::string ro = read_off ? fmt::format("{}", *read_off * to) : "";
      if (x.resolved)
        t += fmt::format("{},{},{},{},{},{},1,{}\n", c.column, term, unit, x.value * to, x.lo * to,
                         x.hi * to, ro);
      else
        t += fmt::format("{},{},{},,,{},0,{}\n", c.column, term, unit, x.hi * to, ro);
    };
    if (c.quantity == "accel") {
      const double a = c.mps2_per_unit;
      const double mg = a / units::standard_gravity_mps2 * 1e3;
      row("vrw", "m/s^2/sqrt(Hz)", f.arw, a, r.arw);
      row("bias_instability", "mg", f.bias_instability, mg, r.bias_instability);
      row("acceleration_rw", "m/s^3/sqrt(Hz)", f.rrw, a, r.rrw);
      row("quantization", "m/s", f.quantization, a, std::nullopt);
      row("rate_ramp", "mg/h", f.rate_ramp, mg * units::s_per_h, std::nullopt);
      continue;
    }
    row("arw", "deg/sqrt(h)", f.arw, k * units::deg_rth_per_deg_rts, r.arw);
    row("bias_instability", "deg/h", f.bias_instability, k * units::dph_per_dps,
        r.bias_instability);
    row("rrw", "deg/h/sqrt(h)", f.rrw, k * units::dph_rth_per_dps_rts, r.rrw);
    row("quantization", "deg", f.quantization, k, std::nullopt);
    row("rate_ramp", "deg/h^2", f.rate_ramp, k * units::dph2_per_dps2, std::nullopt);
  }
  return t;
}

// Kalibr's IMU file (io::kalibr_yaml): the gyro and accelerometer columns, the largest axis of each
// term; every column at one rate (Kalibr has one update_rate).
result<std::string> kalibr_text(const noise_options& o, const std::vector<column_noise>& all,
                                const std::string& bag_topic) {
  io::kalibr_imu imu;
  // The topic read from a bag is the IMU's topic in Kalibr's bags too.
  imu.rostopic = !o.in.topic.empty() ? o.in.topic : !bag_topic.empty() ? bag_topic : "/imu0";
  imu.update_rate_hz = 1.0 / all.front().tau0_s;
  for (const auto& c : all) {
    if (std::abs(c.tau0_s / all.front().tau0_s - 1.0) > 1e-6)
      return usage_error(fmt::format(
          "--kalibr: {} column {} is sampled at {:g} Hz, {} column {} at {:g} Hz: Kalibr has one "
          "update_rate",
          all.front().file, printable(all.front().column, 60), 1.0 / all.front().tau0_s, c.file,
          printable(c.column, 60), 1.0 / c.tau0_s));
    auto& source = c.quantity == "accel" ? imu.accel_source : imu.gyro_source;
    (c.quantity == "accel" ? imu.accel : imu.gyro).push_back(io::kalibr_axis_of(c));
    if (source.find(c.file) == std::string::npos) source += (source.empty() ? "" : ", ") + c.file;
    if (!c.result.terms.arw.resolved || !c.result.terms.rrw.resolved)
      warn(
          fmt::format("{}: column {}: {} not resolved: the Kalibr file takes its upper limit if "
                      "it is the largest axis",
                      o.kalibr, printable(c.column, 60), !c.result.terms.arw.resolved ? "N" : "K"));
  }
  if (imu.accel.empty() || imu.gyro.empty())
    return usage_error(fmt::format(
        "--kalibr needs gyro and accelerometer columns (Kalibr requires both sensors' terms): "
        "{} has no {} column; name it with --kalibr-other FILE, or a column whose name states "
        "its unit (ax_mps2, gx_rad_s)",
        o.in.file, imu.accel.empty() ? "accelerometer" : "gyro"));
  auto y = io::kalibr_yaml(imu);
  if (!y) return y.err();
  return *y;
}

}  // namespace

namespace {

// The record of --kalibr-other: every numeric column, read as FILE is, each column's unit from
// its name (else the sensor FILE lacks).
series_input other_input(const noise_options& o) {
  series_input other = o.in;
  other.file = o.kalibr_other;
  other.column.clear();
  other.columns = "all-numeric";
  other.units_given = false;
  other.units = "deg/s";
  other.input = "rate";
  return other;
}

// The curves of one sensor (gyro or accel) in the figure's base unit (deg/s; m/s^2).
std::vector<report::allan_curve> curves_of(const std::vector<column_noise>& all,
                                           const std::string& quantity) {
  std::vector<report::allan_curve> curves;
  for (const auto& c : all)
    if (c.quantity == quantity) curves.push_back(report::noise_curve(c));
  return curves;
}

// The plot's stem for a sensor: FILE's own, or STEM_accel beside a gyro figure.
std::string stem_of(const plot_file& p, const std::string& quantity, bool both) {
  return quantity == "accel" && both ? p.stem + "_accel" : p.stem;
}

}  // namespace

int run_noise(const noise_options& o) {
  if (o.json)
    if (auto s = check_name_for_json(o.in.file); !s) return report(s.err());
  if (!o.kalibr_other.empty() && o.kalibr.empty())
    return report(usage_error("--kalibr-other is the other sensor's record for --kalibr"));
  std::vector<std::string> inputs_named{o.in.file};
  if (!o.kalibr_other.empty()) inputs_named.push_back(o.kalibr_other);
  if (auto s = io::check_outputs(inputs_named, std::array{o.kalibr, o.output}); !s)
    return report(s.err());
  // Checked before the files are read.
  const auto range = fit_range(o.fit_taus);
  if (!range) return report(range.err());
  const auto plot = plot_target(o.plot);
  if (!plot) return report(plot.err());
  const std::array plot_unit_names{"deg/h", "deg/s", "rad/s", "m/s^2", "mg", "ug"};
  if (*plot && !o.plot_units.empty() &&
      std::find(plot_unit_names.begin(), plot_unit_names.end(), o.plot_units) ==
          plot_unit_names.end())
    return report(
        usage_error("--plot-units must be deg/h, deg/s or rad/s (gyro), mg, ug or "
                    "m/s^2 (accelerometer); got " +
                    printable(o.plot_units, 40)));
  std::vector<series_input> sources{o.in};
  if (!o.kalibr_other.empty()) sources.push_back(other_input(o));
  if (*plot) {
    // The script and one data file per series (curve, its lines, its long taus) beside each
    // image (the gyro's, and STEM_accel's): none may be an input, nor a file the user changed.
    std::size_t columns = 0;
    for (const auto& src : sources) {
      auto names = column_names(src);
      if (!names) return report(names.err());
      columns += names->size();
    }
    const std::size_t series = 7 * columns;
    const std::array format{(*plot)->format};
    for (const bool accel : {false, true}) {
      const std::string stem = accel ? (*plot)->stem + "_accel" : (*plot)->stem;
      if (auto s = io::check_outputs(inputs_named,
                                     report::rendered_files((*plot)->dir, stem, series, format));
          !s)
        return report(s.err());
      if (auto s = report::check_rendered_files((*plot)->dir, stem, series); !s)
        return report(s.err());
    }
  }
  std::vector<column_noise> all;
  std::string bag_topic;  // the topic a ROS bag was read from (the Kalibr file's rostopic)
  for (std::size_t i = 0; i < sources.size(); ++i) {
    noise_options oi = o;
    if (i == 1) {
      // The other record holds the sensor the first lacks.
      bool gyro = false, accel = false;
      for (const auto& c : all) (c.quantity == "accel" ? accel : gyro) = true;
      if (gyro && accel)
        return report(usage_error(fmt::format(
            "--kalibr-other: {} already has gyro and accelerometer columns", o.in.file)));
      oi.quantity = gyro ? "accel" : "gyro";
    }
    auto inputs = load_series(sources[i], true);
    if (!inputs) return report(inputs.err());
    for (const auto& in : *inputs) {
      if (bag_topic.empty()) bag_topic = in.series.topic();
      const auto sensor = sensor_of(oi, sources[i], in.column);
      if (!sensor) return report(sensor.err());
      auto c = noise_of(o, sources[i], *range, in, *sensor);
      if (!c) return report(c.err());
      all.push_back(std::move(*c));
    }
  }
  bool has_gyro = false, has_accel = false;
  for (const auto& c : all) (c.quantity == "accel" ? has_accel : has_gyro) = true;
  if (*plot && !o.plot_units.empty()) {
    const bool accel_unit = units::is_accel_unit(o.plot_units);
    if ((accel_unit && has_gyro) || (!accel_unit && has_accel))
      return report(usage_error(fmt::format(
          "--plot-units {} is a unit of {}, and the record has {} columns", o.plot_units,
          sensor_name(accel_unit ? "accel" : "gyro"), accel_unit ? "gyro" : "accelerometer")));
  }
  json j;
  if (all.size() == 1) {
    j = io::noise_json(all.front());
  } else {
    j = with_schema("noise_columns", 1, {{"file", o.in.file}, {"columns", json::array()}});
    for (const auto& c : all) j["columns"].push_back(io::noise_json(c));
  }
  // Every output is formatted and checked before the first is written.
  std::string file_text;
  if (!o.output.empty()) {
    auto t = o.output.ends_with(".json") ? finite_dump(j, o.output)
                                         : result<std::string>(terms_csv(all));
    if (!t) return report(t.err());
    if (auto s = check_finite(*t, o.output); !s) return report(s.err());
    file_text = o.output.ends_with(".json") ? *t + "\n" : *t;
  }
  std::string kalibr_file;
  if (!o.kalibr.empty()) {
    auto y = kalibr_text(o, all, bag_topic);
    if (!y) return report(y.err());
    if (auto s = check_finite(*y, o.kalibr); !s) return report(s.err());
    kalibr_file = std::move(*y);
  }
  if (!o.kalibr.empty())
    if (auto s = io::write_file_atomically(o.kalibr, kalibr_file); !s) return report(s.err());
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, file_text); !s) return report(s.err());
  if (*plot) {
    // One figure per sensor: the gyro's in FILE, the accelerometer's in FILE (or STEM_accel
    // beside a gyro figure); one curve per column.
    for (const std::string quantity : {"gyro", "accel"}) {
      if (!(quantity == "accel" ? has_accel : has_gyro)) continue;
      const auto curves = curves_of(all, quantity);
      const std::string unit = !o.plot_units.empty() ? o.plot_units
                               : quantity == "accel" ? "mg"
                                                     : "deg/h";
      const auto title =
          !o.title.empty()
              ? o.title
              : fmt::format("Allan deviation of {}{}", printable(o.in.file, 120),
                            has_gyro && has_accel
                                ? (quantity == "accel" ? " (accelerometer)" : " (gyro)")
                                : "");
      auto fig = report::noise_figure(curves, unit, title);
      if (!fig) return report(fig.err());
      const std::array formats{(*plot)->format};
      if (auto s = report::render(*fig, (*plot)->dir, stem_of(**plot, quantity, has_gyro), formats);
          !s)
        return report(s.err());
    }
  }
  if (o.json) {
    if (auto s = print_json(j); !s) return report(s.err());
    return 0;
  }
  std::string text;
  for (const auto& c : all) append_text(text, o, c);
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
