/// \file
/// \brief `gyroflip calibrate`: dN from stationary recordings (paper eqns 8-11), its Earth and
/// g terms, and a dN(T) model when recordings at several temperatures are given.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "command_line.hpp"
#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/digits.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/rigdata/recording_source.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/calibrate.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

void print_entry(std::string& out, const io::calibration_entry& e,
                 const std::optional<io::calibration_geometry>& g) {
  const auto& c = e.cal;
  fmt::format_to(std::back_inserter(out), "{}: {} cycles over {:.0f} s", e.file, c.cycles,
                 c.duration_s);
  if (!std::isnan(c.temp_c)) fmt::format_to(std::back_inserter(out), ", {:.2f} degC", c.temp_c);
  // A number with an error gets the digits its error supports, the error two significant digits;
  // one without (the std, the half-sum's mean, the Earth term from the latitude) a stated number
  // of significant digits (third review of issue 31, M4: "4.788442e-03 ... 1.983e-04"); full
  // digits in -o and --json.
  const double u = c.stderr_correlated_dps;
  fmt::format_to(std::back_inserter(out),
                 "\n  dN = {} deg/s   std {}   stderr {} (naive) {} (correlated)\n",
                 to_digits_of(c.delta_n_dps, u, 4), significant(c.std_dps, 3),
                 significant(c.stderr_dps, 2), significant(u, 2));
  fmt::format_to(std::back_inserter(out), "  bias (half-sum) mean {} deg/s\n",
                 significant(c.bias_mean_dps, 4));
  if (g) {
    const auto s = method::split_delta_n(c.delta_n_dps, g->lat_deg, g->axis);
    fmt::format_to(std::back_inserter(out), "  Earth term {} deg/s   g term {} deg/s\n",
                   significant(s.earth_rate_dps, 4), to_digits_of(s.g_term_dps, u, 4));
  }
  if (e.stationarity)
    fmt::format_to(std::back_inserter(out), "  stationarity: {}\n", e.stationarity->summary());
}

// The result a user quotes, with the digits its uncertainty supports, and which number is which.
void print_result(std::string& out, const io::calibration_record& rec,
                  const workflow::delta_n_budget& b) {
  const auto o = std::back_inserter(out);
  const auto two = [](double v) { return significant(v, 2); };
  std::string failed;
  for (const auto& f : rec.files)
    if (f.stationarity && f.stationarity->failed()) failed += (failed.empty() ? "" : ", ") + f.file;
  if (!failed.empty())
    fmt::format_to(o,
                   "NOT A CALIBRATION: {} failed the stationarity test; the numbers below are "
                   "the runs' mean r, not the sensor's dN\n",
                   failed);
  if (!rec.model) {
    const auto& c = rec.files.front().cal;
    fmt::format_to(o, "dN = {} deg/s (one run; its within-run error, correlated noise)\n",
                   workflow::value_pm(c.delta_n_dps, c.stderr_correlated_dps));
  } else if (rec.model->degree() == 0) {
    const auto& m = *rec.model;
    fmt::format_to(o, "dN over {} runs = {} deg/s (68.3 %{}; {})\n", rec.files.size(),
                   workflow::value_pm(m.coeffs_dps[0], b.calibration_dps),
                   b.coverage_factor > 1.0
                       ? fmt::format(", Student's t for {} degrees of freedom", b.run_to_run_dof)
                       : "",
                   m.random_effects ? "random effects: DerSimonian-Laird, modified Knapp-Hartung"
                                    : "weighted mean");
  } else {
    const auto& m = *rec.model;
    // Without degrees of freedom (fourth review of issue 31, F8) the fit's quality and error are
    // not determined: said so, as the report does, not "chi2/dof 0" beside an 8-digit dN.
    const bool determined = m.dof > 0 || !m.random_effects;
    const double u_centre = determined ? m.interval_at(m.t_ref_c) : b.calibration_dps;
    fmt::format_to(o,
                   "dN(T) = sum c_k (T - {:.2f})^k, c = [{:.3g}] (full digits: -o, --json), fitted "
                   "over {:.1f}..{:.1f} degC (random effects), {}\n"
                   "  at {:.2f} degC: dN = {} deg/s; {}\n",
                   m.t_ref_c, fmt::join(m.coeffs_dps, ", "), m.temp_min_c, m.temp_max_c,
                   determined ? fmt::format("chi2/dof {:.3g}", m.chi2_per_dof)
                              : std::string("chi2/dof not determined (0 degrees of freedom: the "
                                            "line passes through its runs)"),
                   m.t_ref_c,
                   std::isfinite(u_centre) && u_centre > 0.0
                       ? workflow::value_pm(m.coeffs_dps[0], u_centre)
                       : to_digits_of(m.coeffs_dps[0], b.within_run_dps, 3),
                   std::isfinite(b.calibration_dps)
                       ? fmt::format("anywhere in the range within ±{} deg/s (68.3 %){}",
                                     two(b.calibration_dps),
                                     determined ? "" : ", from the sensor preset's spread")
                       : std::string("its error is not determined (0 degrees of freedom)"));
  }
  if (rec.files.size() > 1) {
    std::string between;
    if (!std::isfinite(b.runs_std_dps))
      between = fmt::format(
          "not determined (0 degrees of freedom: the model passes through its {} runs){}",
          rec.files.size(),
          std::isfinite(b.run_to_run_dps)
              ? fmt::format("; the sensor preset's turn-on spread {} deg/s is assumed",
                            two(b.run_to_run_dps))
              : std::string());
    else
      between = fmt::format(
          "std {} deg/s of the runs' dN{}{}", two(b.runs_std_dps),
          !std::isfinite(b.between_run_dps) ? std::string()
          : b.between_run_dps > 0.0
              ? fmt::format(" ({} beyond their own noise, random effects' tau)",
                            two(b.between_run_dps))
              : std::string(" (none beyond their own noise: random effects' tau is 0)"),
          b.run_to_run_floored
              ? fmt::format("; below their own noise {} deg/s, so not resolved: {} deg/s taken "
                            "for a new power-up",
                            two(b.single_run_dps), two(b.run_to_run_dps))
              : std::string());
    fmt::format_to(o,
                   "  between runs: {}\n"
                   "  within runs: {} deg/s (the runs' correlated errors pooled: noise inside the "
                   "runs, not the error of dN)\n",
                   between, two(b.within_run_dps));
  }
  if (!failed.empty()) return;  // nothing to quote (review of issue 31)
  if (std::isfinite(b.new_power_up_dps))
    fmt::format_to(o,
                   "quote: ±{} deg/s for a new power-up (68.3 %): what a rate compensated with "
                   "this calibration carries in every cycle; ±{} deg/s is how well the "
                   "calibrated value itself is known\n",
                   two(b.new_power_up_dps), two(b.calibration_dps));
  else
    fmt::format_to(o,
                   "quote: ±{} deg/s is the calibrated value's own error; how far dN moves from "
                   "one power-up to the next is unknown (one run, no sensor preset)\n",
                   two(b.calibration_dps));
}

// What to do next with a calibration saved as `cal_path` (empty: not saved).
std::string next_step(const std::string& cal_path) {
  if (cal_path.empty())
    return "Next: save it (gyroflip calibrate ... -o cal.json) and compensate a run with it: "
           "gyroflip compensate RUN.csv --calibration cal.json";
  return fmt::format("Next: gyroflip compensate RUN.csv --calibration {}", cal_path);
}

// An N-position calibration's terms with their 1 sigma and correlations, and its separability.
void print_terms(std::string& out, const io::calibration_record& rec) {
  if (rec.terms_covariance.empty()) return;
  const auto o = std::back_inserter(out);
  const std::size_t n = rec.terms.size();
  fmt::format_to(o, "terms (deg/s, 1 sigma; covariance in --json and -o):\n");
  for (std::size_t i = 0; i < n; ++i) {
    std::string corr;
    for (std::size_t j = 0; j < i; ++j) {
      const double d = rec.terms[i].stderr_correlated_dps * rec.terms[j].stderr_correlated_dps;
      if (d > 0.0)
        corr += fmt::format(" r({},{})={:+.2f}", rec.terms[i].name, rec.terms[j].name,
                            rec.terms_covariance[i * n + j] / d);
    }
    // The value to its error's digits, the error to two (core/digits, as every per-run line).
    const double u = rec.terms[i].stderr_correlated_dps;
    fmt::format_to(o, "  {:<3} {} ± {}{}\n", rec.terms[i].name,
                   to_digits_of(rec.terms[i].value_dps, u, 4), significant(u, 2), corr);
  }
  if (rec.separability)
    for (const auto& l : rec.separability->lines()) fmt::format_to(o, "{}\n", l);
}

std::string summary_text(const io::calibration_record& rec, const workflow::delta_n_budget& b,
                         const std::string& cal_path) {
  std::string out;
  fmt::format_to(std::back_inserter(out), "pairing: {}\n", method::to_string(rec.pairing));
  for (const auto& f : rec.files) print_entry(out, f, rec.geometry);
  print_result(out, rec, b);
  print_terms(out, rec);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& f : rec.files)
    if (std::isfinite(f.cal.temp_c)) {
      lo = std::min(lo, f.cal.temp_c);
      hi = std::max(hi, f.cal.temp_c);
    }
  const std::string temps = !(lo <= hi)      ? ""
                            : hi - lo < 0.05 ? fmt::format("{:.1f} degC", lo)
                                             : fmt::format("{:.1f}-{:.1f} degC", lo, hi);
  const bool failed = std::any_of(rec.files.begin(), rec.files.end(), [](const auto& f) {
    return f.stationarity && f.stationarity->failed();
  });
  if (!failed) {
    // What the test cannot see (review of issue 31: 0.01 deg/s on an HZ1 passed as its dN): a
    // constant input below the g-term limit (plus the Earth rate without the geometry: the g-term
    // is then only bounded below by |dN| - W_E), and inputs that enter r as a constant.
    double g_limit = 0.0, g_margin = 0.0;
    bool exact = true, unchecked = false;
    std::string short_runs;
    for (const auto& f : rec.files) {
      if (f.stationarity && !f.stationarity->checked)
        short_runs += (short_runs.empty() ? "" : ", ") + f.file;
      if (f.stationarity && f.stationarity->g_checked) {
        g_limit = std::max(g_limit, f.stationarity->g_limit_dps);
        g_margin = std::max(g_margin, f.stationarity->g_margin_dps);
        exact = exact && f.stationarity->g_exact;
      } else if (f.stationarity) {
        unchecked = true;
      }
    }
    // Too short for the scatter and drift tests: not vouched for (fifth review of issue 31, F16).
    if (!short_runs.empty())
      fmt::format_to(std::back_inserter(out),
                     "NOT VOUCHED FOR: {} too short for the scatter and drift tests (at least {} "
                     "cycles): an input rate that changes during the run passes unseen\n",
                     short_runs, method::min_stationarity_cycles);
    const char* constant_like =
        "; nor does it see a zero-mean vibration at an even harmonic of the flip frequency "
        "(2/cycle, 4/cycle ...) or a repeatable motion after each turn (--one-way): they enter r "
        "as a constant";
    if (unchecked)
      fmt::format_to(std::back_inserter(out),
                     "NOT VOUCHED FOR: the g-term was not checked (no sensor specification): a "
                     "constant input of any size reads as dN; give --sensor NAME|FILE.toml{}\n",
                     constant_like);
    else if (g_limit > 0.0)
      fmt::format_to(std::back_inserter(out),
                     "The stationarity test cannot see a constant input below {:#.2g} deg/s (the "
                     "sensor's g-term limit {:#.2g}{}, plus this run's margin of 3 correlated "
                     "errors, {:#.2g}): it reads as dN; make sure the table was at rest{}\n",
                     g_limit + g_margin + (exact ? 0.0 : earth::earth_rate_wgs84_dps), g_limit,
                     exact ? "" : " plus the Earth rate, without --latitude/--axis", g_margin,
                     constant_like);
    // The smallest step and drift of r the drift and step statistics catch half of the time
    // (fifth review of issue 31, F1/F2): smaller ones pass and stay in dN.
    double step_mid = 0.0, step_end = 0.0, ramp = 0.0;
    for (const auto& f : rec.files)
      if (f.stationarity && f.stationarity->checked) {
        step_mid = std::max(step_mid, f.stationarity->step_hidden_dps);
        step_end = std::max(step_end, f.stationarity->step_hidden_end_dps);
        ramp = std::max(ramp, f.stationarity->ramp_hidden_dps);
      }
    if (step_mid > 0.0 && ramp > 0.0)
      fmt::format_to(std::back_inserter(out),
                     "Nor can it see a step of r below {:#.2g} deg/s at mid-run ({:#.2g} deg/s in "
                     "the first or last 3 % of a run) or a drift below {:#.2g} deg/s over a run "
                     "(each caught half of the time at that size{}): they stay in dN\n",
                     step_mid, step_end, ramp,
                     rec.files.size() > 1 ? ", the least sensitive run" : "");
    // Not vouched for: the next step is the check, not compensating with it (third review of
    // issue 31, M6).
    std::string files;
    for (const auto& f : rec.files) files += " " + f.file;
    const std::string next =
        !short_runs.empty()
            ? fmt::format(
                  "Next: record a run of {} cycles or more with the table at rest and "
                  "calibrate it",
                  method::min_stationarity_cycles)
        : unchecked ? fmt::format(
                          "Next: check its g-term first: gyroflip calibrate{} --sensor "
                          "NAME|FILE.toml{}",
                          files, cal_path.empty() ? "" : " -o " + cal_path)
                    : next_step(cal_path);
    fmt::format_to(std::back_inserter(out), "{}\n{}\n{}\n", workflow::delta_n_meaning(), next,
                   workflow::when_to_recalibrate(b, temps));
    return out;
  }
  // The runs that passed still calibrate: the exact command without the failed ones.
  std::string good;
  for (const auto& f : rec.files)
    if (!(f.stationarity && f.stationarity->failed())) good += " " + f.file;
  fmt::format_to(std::back_inserter(out),
                 "{}\nNext: calibrate again with the table at rest (nothing turning it, level, no "
                 "rate input) and check each run's stationarity line{}\n",
                 workflow::delta_n_meaning(),
                 good.empty()
                     ? std::string()
                     : fmt::format("; or leave the failed runs out: gyroflip calibrate{}{}", good,
                                   cal_path.empty() ? "" : " -o " + cal_path));
  return out;
}

}  // namespace

namespace {

// calibrate --explain: the separability report of --positions (before a run) or of each
// recording's table, as text or one JSON object per table.
int run_explain(const calibrate_options& o) {
  std::vector<std::pair<std::string, method::separability>> reports;
  if (!o.positions.empty()) {
    if (!o.files.empty())
      return report(usage_error("--explain takes --positions or recordings, not both"));
    const auto angles = text::to_doubles(o.positions, ',');
    if (!angles)
      return report(usage_error(fmt::format("--positions '{}': expected angles in degrees, A,B,...",
                                            printable(o.positions, 60))));
    auto table = position_table::of_angles(*angles);
    if (!table) return report(usage_error("--positions: " + table.err().message));
    reports.emplace_back("",
                         method::separability_of(*table, method::table_axis_kind_of(o.table_axis)));
  } else {
    if (o.files.empty())
      return report(usage_error("--explain needs --positions A,B,... or recordings"));
    for (const auto& f : o.files) {
      auto rows = rigdata::read_recording_rows(f, o.angle_tolerance_deg);
      if (!rows) return report(rows.err());
      std::string axis = o.table_axis;
      if (axis.empty())
        for (const auto& m : rows->metadata)
          if (m.key == "table_axis") axis = m.value;
      reports.emplace_back(
          f, method::separability_of(rows->positions, method::table_axis_kind_of(axis)));
      reports.back().second.axis_recorded = !axis.empty();
    }
  }
  std::string out;
  for (const auto& [file, sep] : reports) {
    if (o.json) {
      out += io::separability_to_json(sep, file) + "\n";
      continue;
    }
    if (!file.empty()) out += file + ": ";
    for (const auto& l : sep.lines()) out += l + "\n";
  }
  fmt::print("{}", out);
  return 0;
}

}  // namespace

int run_calibrate(const calibrate_options& o) {
  if (o.explain) return run_explain(o);
  if (o.files.empty())
    return report(
        usage_error("calibrate: the recordings are required (or --explain --positions "
                    "A,B,... for the separability of a table before a run)"));
  if (!o.positions.empty() || !o.table_axis.empty())
    return report(
        usage_error("--positions and --table-axis go with --explain (a recording "
                    "carries its own table and axis)"));
  const auto pairing = method::parse_pairing(o.pairing);
  if (!pairing)
    return report(usage_error("--pairing must be " + method::scheme_names_joined(" or ")));
  auto geometry = geometry_option(o.lat_deg, o.axis);
  if (!geometry) return report(geometry.err());
  std::vector<std::string> inputs = o.files;
  if (!o.sensor.empty()) inputs.push_back(o.sensor);  // a TOML preset is an input too
  if (auto s = io::check_outputs(inputs, std::array{o.output}); !s) return report(s.err());
  workflow::calibrate_request req;
  req.files = o.files;
  req.pairing = *pairing;
  req.angle_tolerance_deg = o.angle_tolerance_deg;
  req.geometry = *geometry;
  if (o.degree_given) req.degree = o.degree;
  req.strict = o.strict;
  req.sensor_hint = "`calibrate --sensor NAME|FILE.toml`";
  if (!o.sensor.empty()) {
    auto p = sensor::load_preset(o.sensor);
    if (!p) return report(p.err());
    req.sensor = std::move(*p);
  }
  progress bar("calibrate", 1000);
  auto res = workflow::calibrate_runs(req, per_mille(bar));
  bar.finish();
  if (!res) return report(res.err());
  for (const auto& w : res->warnings) warn(w);
  const auto& rec = res->record;
  // Formatted and checked (every number finite) before anything is written.
  const auto text = io::to_json(rec);
  if (!text) return report(text.err());
  const std::string summary = o.json ? *text + "\n" : summary_text(rec, res->budget, o.output);
  if (auto s = check_finite(summary, "<stdout>"); !s) return report(s.err());
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, *text + "\n"); !s) return report(s.err());
  fmt::print("{}", summary);
  return 0;
}

}  // namespace gyroflip::app
