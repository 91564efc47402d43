/// \file
/// \brief The report a lab sends (report.hpp; docs/REPORT.md): the runs read and analysed, then
/// one page built from their numbers: what the sensor and rig were, a conclusion written from the
/// numbers, dN and its budget (or the compensated rates), the noise, the pairing comparison, the
/// figures per run and the provenance; summary.json holds the same numbers.
#include "gyroflip/workflow/report.hpp"

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/core/digits.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <utility>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/core/version.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/schema.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/method/runs.hpp"
#include "gyroflip/report/figures.hpp"
#include "gyroflip/report/folder.hpp"
#include "gyroflip/report/page.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/rigdata/recording_source.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/analyse.hpp"
#include "gyroflip/workflow/budget.hpp"
#include "gyroflip/workflow/calibrate.hpp"
#include "gyroflip/workflow/compensate.hpp"
#include "gyroflip/workflow/heading.hpp"

namespace gyroflip::workflow {

namespace {

using nlohmann::json;

constexpr std::array formats{report::image_format::png, report::image_format::svg,
                             report::image_format::pdf};

// The summary.json layout (schema gyroflip.report/N): 2 since issue 22 (calibration runs carry a
// residual instead of a compensated mean, the budget, identity, provenance, warnings).
constexpr int summary_schema = 3;

// A dN that calls a calibration run not stationary: its g-term beyond this many times the
// sensor's specified g-sensitivity (at 1 g).
constexpr double g_term_beyond_spec = 3.0;
// Fewer cycles than this give no usable correlated standard error (review R11): the std of n
// cycles has a relative error of 1/sqrt(2 (n - 1)) (13 % at 30) before the correlation of
// neighbouring cycles is estimated from blocks of them; the paper's runs have 3000-6700 cycles.
constexpr std::size_t min_cycles = 30;
// A scale-factor error beyond this many times the sensor's tolerance is warned about (review
// R12): 3 x the tolerance is already outside any unit's specification.
constexpr double sf_beyond_spec = 3.0;

// A number without an error beside it, to `digits` significant digits, in the page's one
// notation (fixed: issue 31, "8.6e-06" beside "0.000010" in a column).
std::string g(double v, int digits = 4) {
  return std::isfinite(v) ? fixed_significant(v, digits) : std::string("–");
}

// A number the user gave (the commanded rate) as given: its shortest digits, in the same fixed
// notation ("-0.5", not "-0.500000").
std::string as_given(double v) {
  if (!std::isfinite(v)) return "–";
  std::string s = fixed_significant(v, 15);
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

// An error (or a number compared with one) to two significant digits, trailing zeros kept
// ("0.0010", not "0.001" as {:.2g} prints: third review of issue 31, H4), as calibrate prints them.
std::string u2(double u) {
  return std::isfinite(u) ? fixed_significant(u, 2) : std::string("–");
}

json num(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

// What the recordings say about the sensor, the rig and where the data came from.
struct identity {
  std::string preset;  // the sensor's name (a built-in preset's name when it is one)
  const sensor::preset* builtin = nullptr;
  std::set<std::string> serials;
  std::vector<io::csv_metadata> rig;  // the first run's rig settings
  std::vector<std::string> origin;    // per run
  std::size_t simulated = 0;          // runs from gyroflip's simulator or an emulated rig
  std::size_t emulated = 0;           // of them, rig recordings of an emulator
  std::size_t on_rig = 0;             // rig recordings of a board
};

// What a calibration's runs were, from what `calibrate` recorded of them (schema 2): "3
// simulated (gyroflip simulate)", ...; `simulated` counts those from the simulator or emulator,
// `unknown` those it recorded nothing of (a file of schema 1, or runs given as arrays).
struct calibration_origin {
  std::size_t runs = 0, simulated = 0, unknown = 0;
  std::string words;
};

// The runs a calibration was made of, with what `calibrate` recorded of each (the SHA-256 lets
// a reader check that they are the files at hand).
report::table calibration_runs_table(const io::calibration_record& rec) {
  report::table t{"The calibration's runs (as recorded in the calibration)",
                  {"run", "file", "T (°C)", "ΔN (°/s)", "origin", "bytes", "SHA-256"},
                  {},
                  ""};
  for (std::size_t k = 0; k < rec.files.size(); ++k) {
    const auto& e = rec.files[k];
    t.rows.push_back({std::to_string(k + 1), e.file, g(e.cal.temp_c, 3),
                      to_digits_of(e.cal.delta_n_dps, e.cal.stderr_correlated_dps, 6),
                      e.source ? origin_words(*e.source) : std::string("not recorded"),
                      e.source ? std::to_string(e.source->size_bytes) : std::string("–"),
                      e.source ? e.source->sha256 : std::string("–")});
  }
  return t;
}

json calibration_runs_json(const io::calibration_record& rec) {
  json out = json::array();
  for (const auto& e : rec.files) {
    json j = {{"file", e.file}, {"delta_n_dps", e.cal.delta_n_dps}, {"temp_c", num(e.cal.temp_c)}};
    // As calibrate tested it (null: not checked, a file before the test; F7).
    j["stationarity"] = e.stationarity ? io::stationarity_to_json(*e.stationarity) : json(nullptr);
    if (e.source)
      j.update(json{{"sha256", e.source->sha256},
                    {"bytes", e.source->size_bytes},
                    {"origin", e.source->origin},
                    {"origin_detail", e.source->origin_detail}});
    out.push_back(std::move(j));
  }
  return out;
}

calibration_origin calibration_origin_of(const io::calibration_record& rec) {
  calibration_origin c;
  c.runs = rec.files.size();
  if (c.runs == 0) {
    c.words = "none listed (its ΔN was not made by gyroflip calibrate, or its runs were removed)";
    return c;
  }
  std::map<std::string, std::size_t> by;
  for (const auto& e : rec.files) {
    if (!e.source) {
      ++c.unknown;
      continue;
    }
    ++by[e.source->origin];
    c.simulated += e.source->simulated() ? 1U : 0U;
  }
  const std::pair<const char*, const char*> kinds[] = {
      {"simulated", "simulated (gyroflip simulate)"},
      {"emulated", "emulated (gyroflip emulate: no real board)"},
      {"rig", "recorded on a rig (.gfr)"},
      {"unknown", "CSV recordings whose metadata names no maker"}};
  for (const auto& [k, w] : kinds)
    if (by[k] > 0) c.words += fmt::format("{}{} {}", c.words.empty() ? "" : ", ", by[k], w);
  if (c.unknown > 0)
    c.words += fmt::format(
        "{}{} of unrecorded origin (the calibration names no source: made "
        "before gyroflip recorded it, or from arrays)",
        c.words.empty() ? "" : ", ", c.unknown);
  return c;
}

identity identify(const std::vector<run_analysis>& runs) {
  identity id;
  for (const auto& a : runs) {
    const auto& m = a.run.metadata;
    if (id.preset.empty()) {
      id.preset = metadata_value(m, "sensor_name");
      if (id.preset.empty()) id.preset = metadata_value(m, "sensor");
      id.rig = io::sensor_of(m).rig;
    }
    if (const auto s = metadata_value(m, "serial"); !s.empty()) id.serials.insert(s);
    const auto src = origin_of(a.run.file, m);
    id.origin.push_back(origin_words(src));
    id.simulated += src.simulated() ? 1U : 0U;
    id.emulated += src.origin == "emulated" ? 1U : 0U;
    id.on_rig += src.origin == "rig" ? 1U : 0U;
  }
  id.builtin = id.preset.empty() ? nullptr : sensor::find_builtin(id.preset);
  return id;
}

std::string sensor_words(const identity& id) {
  if (id.builtin != nullptr) return id.builtin->description;
  return id.preset.empty() ? std::string("a sensor the recordings do not name") : id.preset;
}

// The sensor's short name for titles ("HZ1-90-100A").
std::string part_of(const identity& id) {
  if (id.preset.empty()) return "Gyro";
  std::string p = id.preset;
  if (id.builtin != nullptr)
    std::transform(p.begin(), p.end(), p.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return p;
}

struct temp_span {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  [[nodiscard]] bool known() const { return lo <= hi; }
  [[nodiscard]] std::string text() const {
    if (!known()) return "not recorded";
    return hi - lo < 0.05 ? fmt::format("{:.1f} °C", lo) : fmt::format("{:.1f}–{:.1f} °C", lo, hi);
  }
};

temp_span cycle_temps(const std::vector<method::cycle>& cycles) {
  temp_span t;
  for (const auto& c : cycles)
    if (std::isfinite(c.temp_c)) {
      t.lo = std::min(t.lo, c.temp_c);
      t.hi = std::max(t.hi, c.temp_c);
    }
  return t;
}

// The temperatures of all the runs' cycles.
temp_span runs_temps(const std::vector<run_analysis>& runs) {
  temp_span all;
  for (const auto& a : runs) {
    const auto t = cycle_temps(a.run.cycles(a.pairing));
    if (t.known()) {
      all.lo = std::min(all.lo, t.lo);
      all.hi = std::max(all.hi, t.hi);
    }
  }
  return all;
}

std::string minutes(double s) {
  return s >= 120.0 ? fmt::format("{:.0f} min", s / 60.0) : fmt::format("{:.0f} s", s);
}

// The run's mean cycle period (s).
double cycle_period_s(const run_analysis& a) {
  const auto& c = a.run.cycles(a.pairing);
  return c.size() > 1 ? (c.back().time_s - c.front().time_s) / static_cast<double>(c.size() - 1)
                      : 0.0;
}

std::string term(const analysis::noise_term& t, double to) {
  if (!t.resolved) return "< " + g(t.hi * to, 3);
  return fmt::format("{} [{}, {}]", g(t.value * to, 3), g(t.lo * to, 3), g(t.hi * to, 3));
}

// The per-run stationarity test on the page (fifth review of issue 31, F7: the page showed none of
// its statistics, nor the steps and ramps a run cannot see, which calibrate prints): one row per
// statistic, each against its limit, from the library's one result (method::check_stationarity,
// as calibrate made it or recorded it).
void stationarity_rows(report::table& t, const std::string& run, const method::stationarity& st) {
  const auto row = [&](std::string what, std::string value, std::string limit, bool failed,
                       bool judged = true) {
    t.rows.push_back({run, std::move(what), std::move(value), std::move(limit),
                      !judged  ? "not judged"
                      : failed ? "FAILED"
                               : "within"});
  };
  if (st.checked) {
    row("scatter: std(r) over the dwells' white noise", g(st.scatter_ratio, 3),
        fmt::format("{}–{}", g(st.scatter_low_limit, 3), g(st.scatter_limit, 3)),
        st.scatter_failed);
    if (st.noise_checked)
      row("noise: std(r) over the specification's", g(st.noise_ratio, 3), g(st.noise_limit, 3),
          st.noise_failed);
    else
      row("noise: std(r) over the specification's", "not checked", "–", false, false);
    // The three drift statistics fail together (drift_failed) when one is beyond its limit and
    // the level change beyond 3 correlated errors; each is shown against its own limit.
    const bool level = std::abs(st.step_dps) > st.step_limit_dps;
    const bool has_step = st.step_statistic_limit_value > 0.0;
    row("step: sup-t", g(st.step_statistic, 3),
        has_step ? g(st.step_statistic_limit_value, 3) : "–",
        st.drift_failed && level && st.step_statistic > st.step_statistic_limit_value, has_step);
    row("ramp: slope t", g(st.slope_statistic, 3), has_step ? "±" + g(st.slope_limit, 3) : "–",
        st.drift_failed && std::abs(st.slope_statistic) > st.slope_limit, has_step);
    row("drift: CUSUM", g(st.drift_statistic, 3), g(st.drift_limit_value, 3),
        st.drift_failed && st.drift_statistic > st.drift_limit_value);
    row("level change at the split (°/s)", u2(st.step_dps), u2(st.step_limit_dps), st.drift_failed);
    row(fmt::format("outlier: |r − median| / MAD σ (cycle {})", st.outlier_cycle),
        g(st.outlier_z, 3), g(st.outlier_limit, 3), st.outlier_failed);
  } else {
    row("scatter, noise, step, ramp, drift, outlier", "not tested: " + st.why_not, "–", false,
        false);
  }
  if (st.g_checked)
    row(fmt::format("g-term{} (°/s)", st.g_exact ? "" : ", at least"), u2(st.g_term_dps),
        fmt::format("{} + {}", u2(st.g_limit_dps), u2(st.g_margin_dps)), st.g_failed);
  else
    row("g-term (°/s)", "not checked (no specification)", "–", false, false);
  if (st.has_temp)
    row("temperature span (°C)", g(st.temp_span_c, 2), g(method::isothermal_span_c, 2),
        st.temp_failed);
  // What the run cannot see (each caught half of the time at that size; smaller ones stay in dN).
  if (st.checked && st.step_hidden_dps > 0.0)
    t.rows.push_back({run, "cannot see: a step of r at mid-run / in its first or last 3 % (°/s)",
                      fmt::format("{} / {}", u2(st.step_hidden_dps), u2(st.step_hidden_end_dps)),
                      "–", "below this"});
  if (st.checked && st.ramp_hidden_dps > 0.0)
    t.rows.push_back({run, "cannot see: a drift of r over the run (°/s)", u2(st.ramp_hidden_dps),
                      "–", "below this"});
}

report::table stationarity_table(std::span<const io::calibration_entry> runs, bool recorded) {
  report::table t{recorded ? "Stationarity of the calibration's runs (as calibrate tested them)"
                           : "Stationarity of each run",
                  {"run", "statistic", "value", "limit", "result"},
                  {},
                  "Each statistic against its limit (docs/METHOD-NOTES.md, \"Stationarity\"): the "
                  "step, ramp and drift statistics fail a run only with a level change beyond 3 "
                  "correlated errors; the g-term's limit is the specification's plus that margin. "
                  "\"cannot see\": the smallest step or drift the test catches half of the time "
                  "in that run; smaller ones pass and stay in ΔN."};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string run = std::to_string(k + 1);
    if (runs[k].stationarity)
      stationarity_rows(t, run, *runs[k].stationarity);
    else
      t.rows.push_back(
          {run, "all", "not checked (a calibration written before the test)", "–", "not judged"});
  }
  return t;
}

// A run's dwell rates in order, its content print's input (method/cycle_print.hpp).
std::vector<double> dwell_rates_of(const recording_run& run) {
  std::vector<double> out;
  out.reserve(run.dwells.size());
  for (const auto& d : run.dwells) out.push_back(d.rate_dps);
  return out;
}

// The noise of each run's raw sensor and compensated rate: the IEEE 952 terms of the fit the
// Allan plot draws, in the plot's units (°/√h, °/h, °/h/√h), and the taus the data cover.
report::table noise_table(const std::vector<run_analysis>& runs) {
  report::table t{
      "IEEE 952 noise terms (68.3 % intervals; < : an upper limit, not resolved)",
      {"run", "series", "τ of the data (s)", "N (°/√h)", "B (°/h)", "K (°/h/√h)",
       "lowest OADEV (°/h) at τ (s)", "sensor's N, dead time removed (°/√h)"},
      {},
      "N, B and K are fitted to the OADEV over the τ of the data; the Allan plot draws the "
      "resolved ones with these numbers and marks where each is read (N at τ = 1 h on its −½ "
      "line, K at 3 h on its +½ line, B on its floor 0.664 B where the fitted curve is lowest), "
      "“extrapolated” when that τ lies beyond the data; upper limits (<) are not drawn. The "
      "lowest OADEV is the lowest measured point of the plotted curve. The raw series' dwell "
      "means average only a share d of their spacing (the rest is turning and settling), so its "
      "white noise looks √(1/d) times larger than the sensor's: the last column is the raw N "
      "times √d, the sensor's own angle random walk. The compensated rate's N is that of the "
      "flipped output as delivered (its dead time included)."};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& a = runs[k];
    for (const auto& [what, n] :
         {std::pair{"raw (0° dwells)", &a.raw_noise}, std::pair{"compensated", &a.comp_noise}}) {
      const std::string run = fmt::format("{}: {}", k + 1, a.run.file);
      if (!*n || (*n)->oadev.empty()) {
        t.rows.push_back({run, what, "–", "–", "–", "–", "series too short", "–"});
        continue;
      }
      const auto& pts = (*n)->oadev;
      const std::string taus =
          fmt::format("{}–{}", g(pts.front().tau_s, 3), g(pts.back().tau_s, 3));
      if (!noise_fitted(**n)) {
        t.rows.push_back({run, what, taus, "–", "–", "–", "too few points to fit", "–"});
        continue;
      }
      const auto& f = (*n)->terms;
      const auto lowest = std::min_element(
          pts.begin(), pts.end(), [](const auto& x, const auto& y) { return x.dev < y.dev; });
      const bool raw = n == &a.raw_noise;
      std::string sensor_n = raw ? "dead time unknown" : "–";
      if (raw && a.raw_duty > 0.0)
        sensor_n = fmt::format("{} (d = {})",
                               term(f.arw, units::deg_rth_per_deg_rts * std::sqrt(a.raw_duty)),
                               g(a.raw_duty, 3));
      t.rows.push_back(
          {run, what, taus, term(f.arw, units::deg_rth_per_deg_rts),
           term(f.bias_instability, units::dph_per_dps), term(f.rrw, units::dph_rth_per_dps_rts),
           fmt::format("{} at {}", g(lowest->dev * units::dph_per_dps, 3), g(lowest->tau_s, 3)),
           sensor_n});
    }
  }
  return t;
}

// The paper's own metric, raw beside compensated: the range of the moving mean at each stated
// window that fits twice into the run (issue 31).
report::table drift_table(const std::vector<run_analysis>& runs) {
  report::table t{
      "Drift: range (max − min) of the moving mean, raw 0° dwell means against the "
      "compensated rate (°/h)",
      {"run", "window (s)", "raw (°/h)", "compensated (°/h)"},
      {},
      "The paper's metric for its \"bias drift\" (its window is not stated). Unlike B, "
      "these are measured, not fitted: they compare even where B is only an upper "
      "limit."};
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (const auto& d : runs[k].drifts)
      t.rows.push_back({fmt::format("{}: {}", k + 1, runs[k].run.file),
                        fmt::format("{:.0f}", d.window_s), g(d.raw_dps * units::dph_per_dps, 3),
                        g(d.comp_dps * units::dph_per_dps, 3)});
  return t;
}

// The pairing comparison the reader would otherwise misread (docs/METHOD-NOTES.md).
report::section pairing_section(const std::vector<run_analysis>& runs) {
  report::section s;
  s.heading = "Simple and abba pairing";
  s.paragraphs.push_back(
      "The paper pairs each 0° dwell with the next 180° dwell (simple pairing). gyroflip's "
      "default, abba, averages each dwell with both neighbours, which cancels a linear drift "
      "of the bias exactly (the warm-up leak of simple pairing). Abba cycles share dwells, so "
      "neighbouring cycle values are correlated: their per-cycle std is lower than simple "
      "pairing's although the white-noise level at long averaging times is the same. Compare "
      "the paper's per-cycle std with the simple pairing's row; compare long-term stability "
      "with the OADEV at long τ, which is the same for both.");
  report::table t{"Per-cycle statistics of r = (y₀ − y₁₈₀)/2 by pairing",
                  {"run", "pairing", "cycles", "mean r (°/s)", "per-cycle std (°/s)",
                   "correlated stderr (°/s)", "OADEV at the longest common τ (°/s)"},
                  {},
                  ""};
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (const auto& p : runs[k].pairings) {
      const auto& c = p.cal;
      const auto& at = p.oadev_at_common_tau;
      t.rows.push_back({fmt::format("{}: {}", k + 1, runs[k].run.file),
                        std::string(method::scheme_of(p.pairing).label), std::to_string(c.cycles),
                        value_pm(c.delta_n_dps, c.stderr_correlated_dps), g(c.std_dps, 3),
                        g(c.stderr_correlated_dps, 3),
                        at ? fmt::format("{} at {} s", g(at->dev, 3), g(at->tau_s, 3)) : "–"});
    }
  s.tables.push_back(std::move(t));
  return s;
}

// Renders `f` as figures/STEM.{png,svg,pdf} in `dir` and returns its reference.
result<report::figure_ref> draw(const report::figure& f, const std::string& dir,
                                const std::string& stem, const std::string& caption) {
  if (auto s = report::render(f, dir + "/figures", stem, formats); !s) return s.err();
  return report::figure_ref{f.title, "figures/" + stem + ".png", "figures/" + stem + ".pdf",
                            caption};
}

std::string stem_of(std::size_t k, const char* what) {
  return fmt::format("run{}_{}", k + 1, what);
}

// A compensated run's numbers against a commanded rate.
struct rate_check {
  double error_dps = 0.0;
  double error_u_dps = 0.0;  // the run's correlated error and the ΔN's, combined
  /// NaN at a commanded rate of 0 (no scale factor to measure).
  double scale_factor_ppm = std::numeric_limits<double>::quiet_NaN();
  double scale_factor_u_ppm = std::numeric_limits<double>::quiet_NaN();
};

rate_check check_rate(const method::compensation_summary& s, double expected_dps,
                      double systematic_dps) {
  rate_check c;
  c.error_dps = s.mean_dps - expected_dps;
  c.error_u_dps = std::hypot(s.stderr_correlated_dps, systematic_dps);
  // At rest (a stationary run, a rate table at 0) there is no scale factor to measure: the error
  // alone (fifth review of issue 31, F13).
  if (expected_dps == 0.0) return c;
  c.scale_factor_ppm = 1e6 * (s.mean_dps / expected_dps - 1.0);
  c.scale_factor_u_ppm = 1e6 * c.error_u_dps / std::abs(expected_dps);
  return c;
}

// The dN actually subtracted from a run (a constant, or dN(T) at its cycles' temperatures).
std::pair<double, double> applied_range(const compensation& c) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& x : c.cycles) {
    lo = std::min(lo, x.delta_n_dps);
    hi = std::max(hi, x.delta_n_dps);
  }
  return {lo, hi};
}

// The ΔN applied to a run, with the digits the ΔN's uncertainty `u_dps` supports (issue 31:
// "0.00326975" at a temperature where no run was taken).
std::string applied_text(const compensation& c, double u_dps) {
  const auto [lo, hi] = applied_range(c);
  return hi - lo <= 1e-12 * std::max(1.0, std::abs(hi))
             ? to_digits_of(lo, u_dps, 6)
             : fmt::format("{}…{}", to_digits_of(lo, u_dps, 6), to_digits_of(hi, u_dps, 6));
}

// Everything the page and summary.json say, computed once.
struct findings {
  identity id;
  bool compensating = false;
  std::optional<delta_n_source> given;
  std::optional<method::delta_n_model> model;       // the calibration's, or the runs' dN(T)
  std::optional<method::delta_n_model> runs_model;  // the runs' model (calibration mode)
  delta_n_budget budget;
  std::optional<std::pair<double, double>> pooled;  // one temperature: weighted mean and error
  std::vector<std::string> warnings;
  std::vector<std::optional<rate_check>> rates;
  /// Runs that failed the stationarity test: the report's own calibration runs, or the runs a
  /// given calibration names (what calibrate recorded of them).
  std::vector<std::string> not_stationary;
  /// Runs that passed with their g-term not checked (no sensor specification): a constant input
  /// of any size passes the test, so their ΔN is not vouched for (third review of issue 31, H1).
  std::vector<std::string> not_vouched;
  /// Runs too short for the scatter and drift tests (fifth review of issue 31, F16): not vouched
  /// for either, and no ΔN is headlined from them.
  std::vector<std::string> not_tested;
  /// A given calibration written before the test (its runs not checked).
  bool calibration_unchecked = false;
};

// The runs' names, "a, b and c".
std::string names_of(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k == 0 ? "" : k + 1 == names.size() ? " and " : ", ") + names[k];
  return out;
}

// The calibration runs' warnings: a run that was not stationary or not isothermal (the library's
// one test, as calibrate makes it: method::check_stationarity).
void check_stationary(const report_request& r, const sensor::preset* spec,
                      const std::vector<run_analysis>& runs, findings& f,
                      std::vector<io::calibration_entry>& entries) {
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& a = runs[k];
    // The geometry given against the run's header (fifth review of issue 31, F18), as calibrate.
    (void)check_geometry_header(r.geometry, a.run.metadata, a.run.file, false, f.warnings);
    const auto st = method::check_stationarity(a.run.cycles(a.pairing), a.cal,
                                               stationarity_inputs_of(a.pairing, spec, r.geometry));
    entries[k].stationarity = st;
    // The one verdict calibrate and compensate give (judge_run); a report is never strict.
    const auto standing =
        judge_run({a.run.file, {}, "report", r.sensor_hint}, st, false, f.warnings);
    if (standing && *standing == run_standing::failed) f.not_stationary.push_back(a.run.file);
    if (standing && *standing == run_standing::g_unchecked) f.not_vouched.push_back(a.run.file);
    if (standing && *standing == run_standing::untested) f.not_tested.push_back(a.run.file);
  }
}

// Runs that scatter far beyond their own errors were not made under the same conditions.
void check_runs_agree(findings& f) {
  if (auto w = runs_disagree_warning(f.runs_model)) f.warnings.push_back(std::move(*w));
  if (auto w = runs_too_alike_warning(f.runs_model)) f.warnings.push_back(std::move(*w));
}

// The runs a given calibration was made of, as calibrate tested them (schema 3): a failed run
// makes its ΔN not the sensor's; a file written before the test says its runs are not checked.
void check_calibration_runs_stationary(const delta_n_source& given, findings& f) {
  auto runs = check_calibration_runs(given, false);  // never an error without strict
  if (!runs) return;
  f.calibration_unchecked = runs->unchecked;
  for (auto& n : runs->failed) f.not_stationary.push_back(std::move(n));
  for (auto& n : runs->g_unchecked) f.not_vouched.push_back(std::move(n));
  for (auto& n : runs->untested) f.not_tested.push_back(std::move(n));
  for (auto& w : runs->warnings) f.warnings.push_back(std::move(w));
}

// A calibration applied to runs away from its runs' temperatures. A constant dN (review R3): the
// budget gets the sensor preset's temperature term, or is marked not valid when no coefficient
// is known. A dN(T) line (re-review): its error is taken at the runs' own temperatures, where it
// is extrapolated, not at the calibration runs' (at 36 degC from runs at 4-20 degC it is 2.6
// times the largest of those).
void check_calibration_temperature(const std::vector<run_analysis>& runs, findings& f,
                                   const sensor::preset* spec) {
  const auto& rec = *f.given->record;
  temp_span cal;
  for (const auto& e : rec.files)
    if (std::isfinite(e.cal.temp_c)) {
      cal.lo = std::min(cal.lo, e.cal.temp_c);
      cal.hi = std::max(cal.hi, e.cal.temp_c);
    }
  if (!cal.known()) return;
  double outside_c = 0.0, at_c = 0.0;
  for (const auto& a : runs) {
    const double t = a.cal.temp_c;  // the mean of its cycles' temperatures (NaN: none)
    if (!std::isfinite(t)) continue;
    if (const double out = std::max(cal.lo - t, t - cal.hi); out > outside_c) {
      outside_c = out;
      at_c = t;
    }
  }
  if (!(outside_c > outside_calibration_c)) return;
  auto& b = f.budget;
  if (rec.model && rec.model->degree() > 0) {
    const double se = rec.model->interval_at(at_c);
    if (!(std::isfinite(se) && se > b.model_dps)) return;
    b.model_dps = b.calibration_dps = se;
    b.model_note = fmt::format(
        "the dN(T) line's error at the run's {:.1f} °C, extrapolated {:.1f} °C beyond its runs' "
        "{}",
        at_c, outside_c, cal.text());
    b.new_power_up_dps = std::hypot(b.calibration_dps, b.coverage_factor * b.run_to_run_dps);
    return;
  }
  add_temperature_term(b, outside_c, cal.text(), spec != nullptr ? &spec->params : nullptr,
                       spec != nullptr ? spec->name : f.id.preset);
}

// The per-run table's ΔN applied: with the tau^2(T) band, its ± at the run's temperature (the
// one the conclusion quotes for the run; the budget table gives the widest).
std::string applied_with_band(const compensation& c, const delta_n_budget& b, double u_dps) {
  return applied_text(c, u_dps) +
         (b.band_model && std::isfinite(u_dps) ? " ± " + u2(u_dps) : std::string());
}

// "±u °/s" of a new power-up's ΔN, or why there is none.
std::string power_up_text(const delta_n_budget& b) {
  if (!b.valid) return b.invalid_why;
  if (!std::isfinite(b.new_power_up_dps))
    return "no ± known (its run-to-run repeatability is " + b.run_to_run_source + ")";
  return fmt::format("±{} °/s{}", u2(b.new_power_up_dps),
                     b.outside_c > 0.0 ? ", its temperature term included" : "");
}

// The same for the runs compensated: where the budget's runs give a between-run variance that
// changes with temperature (tau^2(T)), each run's at its temperature, the ± `compensate` quotes
// for it (new_power_up_at; fifth review of issue 31: the page quoted the widest for every run).
std::string power_up_text(const delta_n_budget& b, const std::vector<run_analysis>& runs) {
  if (!b.valid || !std::isfinite(b.new_power_up_dps) || !b.band_model || runs.empty())
    return power_up_text(b);
  std::string out;
  for (std::size_t k = 0; k < runs.size(); ++k)
    out +=
        fmt::format("{}±{} °/s{}", k == 0 ? "" : ", ", u2(new_power_up_at(b, runs[k].cal.temp_c)),
                    runs.size() == 1 ? std::string() : " for " + runs[k].run.file);
  return out + (b.outside_c > 0.0 ? ", its temperature term included" : "");
}

// A compensated run against its commanded rate (review R12): a reading of the opposite sign, or a
// scale-factor error far beyond the sensor's tolerance, says the comparison is wrong (the
// commanded rate's sign, the table's speed, the sensor's mounting or preset), not the sensor.
void check_commanded_rate(const run_analysis& a, double expected_dps, const rate_check& c,
                          findings& f) {
  if (expected_dps == 0.0) return;  // at rest: no sign, no scale factor to judge
  const double mean = a.comp.summary.mean_dps;
  // The scale-factor error's own standard uncertainty (the dN error and the run's noise, as a
  // fraction): a warning only where the error lies beyond it (review of issue 22: a run at
  // exactly its commanded 0.002 deg/s was told its table was wrong, at 0.9 sigma).
  const double u = c.scale_factor_u_ppm / 1e6;
  const double u_dps = u * std::abs(expected_dps);
  const auto spec = scale_factor_tolerance(f.id.preset);
  if (mean * expected_dps < 0.0 && std::abs(mean) > 2.0 * u_dps) {
    f.warnings.push_back(fmt::format(
        "{}: the compensated rate {} °/s has the opposite sign of the commanded {} °/s (a "
        "scale-factor error of {:.0f} %, beyond twice its uncertainty): the commanded rate's "
        "sign or the sensor's mounting is wrong, not the sensor's scale factor",
        a.run.file, g(mean, 6), as_given(expected_dps), c.scale_factor_ppm / 1e4));
    return;
  }
  if (spec && std::abs(c.scale_factor_ppm) / 1e6 - 2.0 * u > sf_beyond_spec * spec->fraction) {
    f.warnings.push_back(fmt::format(
        "{}: a scale-factor error of {:.1f} ± {:.1f} % against the commanded {} °/s is {:.0f} "
        "times the {}: the commanded rate, the table's speed or the sensor (preset) is not what "
        "was assumed",
        a.run.file, c.scale_factor_ppm / 1e4, 100.0 * u, as_given(expected_dps),
        std::abs(c.scale_factor_ppm) / (1e6 * spec->fraction), spec->source));
    return;
  }
  // Too slow to say anything about the scale factor: its uncertainty exceeds the tolerance.
  if (spec && 2.0 * u > spec->fraction)
    f.warnings.push_back(fmt::format(
        "{}: the commanded {} °/s is too slow to measure a scale factor: twice the ΔN and "
        "noise uncertainty (2 × ±{} °/s, 2 σ) is {:.1f} % of it, more than the {} (a rate "
        "above {} °/s would resolve it)",
        a.run.file, as_given(expected_dps), u2(u_dps), 200.0 * u, spec->source,
        u2(2.0 * u_dps / spec->fraction)));
}

// B of the compensated rate beside the raw's when both are resolved; otherwise say that upper
// limits are no comparison and compare what was resolved: the lowest OADEV and the drift at the
// stated windows (issue 31: "B < 1.45 °/h against < 11.2 °/h" read as an improvement).
std::string noise_sentence(const run_analysis& a) {
  if (!a.comp_noise || !noise_fitted(*a.comp_noise)) return "";
  const auto& bc = a.comp_noise->terms.bias_instability;
  const bool raw = a.raw_noise && noise_fitted(*a.raw_noise);
  if (raw && bc.resolved && a.raw_noise->terms.bias_instability.resolved)
    return fmt::format(
        " The compensated rate's bias instability B is {} °/h against {} °/h for the raw 0° "
        "dwell means (without flipping) ({}, noise table).",
        term(bc, units::dph_per_dps), term(a.raw_noise->terms.bias_instability, units::dph_per_dps),
        a.run.file);
  std::string out = fmt::format(" The compensated rate's bias instability B is {} °/h",
                                term(bc, units::dph_per_dps));
  const auto* br = raw ? &a.raw_noise->terms.bias_instability : nullptr;
  if (br != nullptr)
    out += fmt::format(" against the raw 0° dwell means' {} °/h", term(*br, units::dph_per_dps));
  // An upper limit below the other's resolved interval is still a comparison: a lower bound of
  // the improvement. Two upper limits, or a resolved B against a bound, are none.
  if (br != nullptr && !bc.resolved && br->resolved && br->lo > bc.hi)
    out += fmt::format(
        " (noise table): its upper limit lies below the raw's lower bound {} °/h, an "
        "improvement, though B itself is not resolved.",
        g(br->lo * units::dph_per_dps, 3));
  else
    out +=
        " (noise table): an upper limit is not a resolved B, so these are no measure of the "
        "improvement.";
  const auto lowest = [](const analysis::noise_analysis& n) {
    return *std::min_element(n.oadev.begin(), n.oadev.end(),
                             [](const auto& x, const auto& y) { return x.dev < y.dev; });
  };
  if (raw && !a.comp_noise->oadev.empty() && !a.raw_noise->oadev.empty()) {
    const auto c = lowest(*a.comp_noise), w = lowest(*a.raw_noise);
    out += fmt::format(
        " What was resolved: the lowest OADEV is {} °/h at τ = {} s compensated against {} °/h "
        "at τ = {} s raw",
        g(c.dev * units::dph_per_dps, 3), g(c.tau_s, 3), g(w.dev * units::dph_per_dps, 3),
        g(w.tau_s, 3));
    for (const auto& d : a.drifts)
      out +=
          fmt::format("; the range of the {:.0f}-s moving mean {} °/h against {} °/h", d.window_s,
                      g(d.comp_dps * units::dph_per_dps, 3), g(d.raw_dps * units::dph_per_dps, 3));
    out += fmt::format(" ({}, noise and drift tables).", a.run.file);
  }
  return out;
}

// The ΔN error in B's unit, where both appear (issue 31: B < 1.7 °/h quoted beside a systematic
// ΔN error of ±3.5 °/h).
std::string delta_n_in_dph(const delta_n_budget& b, const run_analysis& a) {
  if (!std::isfinite(b.new_power_up_dps) || !a.comp_noise || !noise_fitted(*a.comp_noise))
    return "";
  const auto& bc = a.comp_noise->terms.bias_instability;
  const double u_dph = b.new_power_up_dps * units::dph_per_dps;
  const double b_dph = (bc.resolved ? bc.value : bc.hi) * units::dph_per_dps;
  return fmt::format(
      " In B's unit the ΔN error is ±{} °/h, a constant in every cycle that no averaging "
      "removes{}.",
      u2(u_dph),
      u_dph > b_dph ? "; it is larger than B: the calibration, not the sensor's noise, limits "
                      "the compensated mean"
                    : "");
}

// A dN(T) coefficient as the ΔN(T) table and the conclusion print it: with the digits its
// 68.3 % interval supports (issue 31: "0.00326975 ± 0.000812"); c0 without degrees of freedom
// takes the budget's error (the preset's spread).
struct coefficient_text {
  std::string value;
  double se = 0.0, interval = 0.0;
};
coefficient_text coefficient_of(const method::delta_n_model& m, std::size_t k,
                                const delta_n_budget& b) {
  const std::size_t n = m.coeffs_dps.size();
  const double se = std::sqrt(m.cov[k * n + k]);
  const double t = m.random_effects ? analysis::t_one_sigma(static_cast<double>(m.dof)) : 1.0;
  const double u = k == 0 && !(se > 0.0) ? b.calibration_dps : t * se;
  const auto both = value_pm(m.coeffs_dps[k], u);
  return {both.substr(0, both.find(" ±")), se, u};
}

// The conclusion, written from the numbers the tables show.
std::string conclusion(const report_request& r, const std::vector<run_analysis>& runs,
                       const findings& f) {
  const auto& b = f.budget;
  std::string out;
  const std::string sensor = part_of(f.id);
  const auto worst_std = [&] {
    double s = 0.0;
    for (const auto& a : runs) s = std::max(s, a.comp.summary.std_dps);
    return s;
  }();
  std::string failed;
  for (const auto& n : f.not_stationary) failed += (failed.empty() ? "" : ", ") + n;
  if (!f.compensating) {
    std::string value;
    if (f.pooled) {
      value = fmt::format("{} °/s (the mean of {} runs at {}; random effects, 68.3 %)",
                          value_pm(f.pooled->first, f.pooled->second), runs.size(),
                          runs_temps(runs).text());
    } else if (f.runs_model && f.runs_model->degree() > 0) {
      // The numbers as the ΔN(T) and budget tables print them. A slope is stated only when it
      // is resolved: degrees of freedom left and at least 2 standard errors from zero.
      const auto& m = *f.runs_model;
      const std::size_t n = m.coeffs_dps.size();
      const std::size_t dof = runs.size() > n ? runs.size() - n : 0;
      const double slope = m.coeffs_dps[1], u = std::sqrt(m.cov[n + 1]);
      const auto c0 = coefficient_of(m, 0, b), c1 = coefficient_of(m, 1, b);
      // With degrees of freedom: the error at the temperature named (the table's c_0) and the
      // largest over the runs' temperatures (the budget's), review R4.
      const bool c0_error = std::isfinite(c0.interval) && c0.interval > 0.0;
      value = dof == 0
                  ? fmt::format("{}{} °/s at {:.2f} °C (ΔN(T) of {} runs over {:.1f}–{:.1f} °C{})",
                                c0.value, c0_error ? " ± " + u2(c0.interval) : std::string(),
                                m.t_ref_c, runs.size(), m.temp_min_c, m.temp_max_c,
                                c0_error ? "" : "; its error is not determined")
                  : fmt::format(
                        "{} ± {} °/s at {:.2f} °C, ± {} °/s anywhere in {:.1f}–{:.1f} °C (ΔN(T) "
                        "of {} runs)",
                        c0.value, u2(c0.interval), m.t_ref_c, u2(b.calibration_dps), m.temp_min_c,
                        m.temp_max_c, runs.size());
      if (dof == 0)
        value += fmt::format(
            "; how it changes with temperature is not resolved: {} runs for {} coefficients "
            "leave no degrees of freedom",
            runs.size(), n);
      else if (std::abs(slope) < 2.0 * u)
        value += fmt::format(
            "; how it changes with temperature is not resolved: the slope {} ± {} °/s per °C "
            "(standard error) is below 2 standard errors",
            c1.value, u2(u));
      else
        value +=
            fmt::format(", changing by {} ± {} °/s per °C (68.3 %)", c1.value, u2(c1.interval));
    } else {
      const auto& c = runs.front().cal;
      value = fmt::format("{} °/s (one run of {}, within-run error)",
                          value_pm(c.delta_n_dps, c.stderr_correlated_dps), minutes(c.duration_s));
    }
    // A run that was not stationary gives no ΔN of the sensor (issue 31): the numbers are said
    // as what they are, never headlined.
    out = !failed.empty() ? fmt::format(
                                "These runs give no ΔN of this {}: {} failed the stationarity test "
                                "(warnings below), so their mean r, {}, is not the sensor's ΔN. "
                                "Calibrate again with the table at rest.",
                                sensor, failed, value)
          : !f.not_tested.empty()
              ? fmt::format(
                    "These runs give no ΔN of this {}: {} {} too short for the stationarity "
                    "test's scatter and drift statistics (16 cycles at least), so an input rate "
                    "that changed during the run passes unseen: not vouched for. Their mean r is "
                    "{}. Record a longer run with the table at rest.",
                    sensor, names_of(f.not_tested), f.not_tested.size() == 1 ? "is" : "are", value)
          : !f.not_vouched.empty()
              ? fmt::format(
                    "Not vouched for: g-term not checked. {} passed the stationarity test with "
                    "{} g-term not checked (no sensor specification): a constant input rate of "
                    "any size (a turning or tilted table) passes it and enters ΔN whole, so {} "
                    "mean r, {}, is this {}'s ΔN only if the table was at rest.",
                    names_of(f.not_vouched), f.not_vouched.size() == 1 ? "its" : "their",
                    runs.size() == 1 ? "its" : "their", value, sensor)
          : failed.empty()
              ? fmt::format("ΔN of this {} is {}.", sensor, value)
              : fmt::format(
                    "These runs give no ΔN of this {}: {} failed the stationarity test "
                    "(warnings below), so their mean r, {}, is not the sensor's ΔN. Calibrate "
                    "again with the table at rest.",
                    sensor, failed, value);
    out += " " + delta_n_meaning();
    if (r.geometry) {
      const auto s = method::split_delta_n(runs.front().cal.delta_n_dps, r.geometry->lat_deg,
                                           r.geometry->axis);
      out += fmt::format(
          " Of the first run's ΔN, {} °/s is the Earth's rate at {}° latitude and {} °/s the "
          "g-term.",
          g(s.earth_rate_dps, 6), r.geometry->lat_deg,
          to_digits_of(s.g_term_dps, runs.front().cal.stderr_correlated_dps, 4));  // the table's
    }
    if (failed.empty()) {
      const auto t = runs_temps(runs);
      out += " " + when_to_recalibrate(b, t.known() ? t.text() : std::string());
      // Not vouched for: the next step is the check (as calibrate's, review M6).
      if (!f.not_vouched.empty() && !r.sensor_hint.empty())
        out += " Next: check the g-term: " + r.sensor_hint + ".";
      else if (!r.next_step.empty())
        out += " " + r.next_step;
    }
    out += fmt::format(
        " With ΔN removed, the rate's per-cycle standard deviation is up to {} °/s (a std, not "
        "a bound).",
        g(worst_std, 3));
  } else {
    // The ΔN applied, per run (a ΔN(T) applies another value at each temperature).
    std::string applied;
    for (std::size_t k = 0; k < runs.size(); ++k)
      applied += fmt::format("{}{} {}", k == 0 ? "" : ", ", runs[k].run.file,
                             applied_text(runs[k].comp, new_power_up_at(b, runs[k].cal.temp_c)));
    if (!failed.empty())
      out = fmt::format(
          "The calibration {} is not the sensor's: its run{} {} failed the stationarity test "
          "(warnings below), so the ΔN applied, and every rate below, is off by an amount no "
          "± here covers. ",
          f.given->source, f.not_stationary.size() == 1 ? "" : "s", failed);
    else if (!f.not_tested.empty())
      out = fmt::format(
          "Not vouched for: the calibration {}'s run{} {} {} too short for the stationarity "
          "test's scatter and drift statistics, so an input rate that changed during {} passes "
          "unseen, and the ΔN applied, and every rate below, is right only if its table was at "
          "rest. ",
          f.given->source, f.not_tested.size() == 1 ? "" : "s", names_of(f.not_tested),
          f.not_tested.size() == 1 ? "was" : "were", f.not_tested.size() == 1 ? "it" : "them");
    else if (!f.not_vouched.empty())
      out = fmt::format(
          "Not vouched for: g-term not checked. The calibration {}'s run{} {} passed the "
          "stationarity test with {} g-term not checked (no sensor specification): a constant "
          "input rate of any size (a turning or tilted table) passes it and enters ΔN whole, so "
          "the ΔN applied, and every rate below, is right only if its table was at rest. ",
          f.given->source, f.not_vouched.size() == 1 ? "" : "s", names_of(f.not_vouched),
          f.not_vouched.size() == 1 ? "its" : "their");
    else if (f.calibration_unchecked)
      out = fmt::format(
          "{}: that its ΔN is the sensor's is not checked. ",
          f.given->record && f.given->record->files.empty()
              ? fmt::format("The calibration {} lists no runs", f.given->source)
              : fmt::format("The calibration {} was written before gyroflip tested its runs for "
                            "stationarity",
                            f.given->source));
    out += fmt::format("Compensated with {} (ΔN applied, °/s: {}; for this power-up {}).",
                       f.given->source, applied, power_up_text(b, runs));
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const auto& s = runs[k].comp.summary;
      out += fmt::format(" {} reads {} °/s over {}", runs[k].run.file,
                         value_pm(s.mean_dps, s.stderr_correlated_dps), minutes(s.duration_s));
      if (f.rates[k] && *r.expected_rate_dps == 0.0)
        out += fmt::format(
            " against the commanded 0 °/s (at rest: no scale factor to measure): an error of {} "
            "°/s{}",
            b.valid ? value_pm(f.rates[k]->error_dps, f.rates[k]->error_u_dps)
                    : g(f.rates[k]->error_dps, 3),
            b.valid ? ""
                    : fmt::format(" (its uncertainty is not known: the ΔN applied's ± is {})",
                                  b.invalid_why));
      else if (f.rates[k])
        out += fmt::format(
            " against the commanded {} °/s: a scale-factor error of {}{}",
            as_given(*r.expected_rate_dps),
            b.valid
                ? value_pm(f.rates[k]->scale_factor_ppm, f.rates[k]->scale_factor_u_ppm) + " ppm"
                : fmt::format("about {:.1f} %", f.rates[k]->scale_factor_ppm / 1e4),
            b.valid ? ""
                    : fmt::format(" (its uncertainty is not known: the ΔN applied's ± is {})",
                                  b.invalid_why));
      out += ".";
    }
    out += b.valid && !std::isfinite(b.new_power_up_dps)
               ? std::string(
                     " The ΔN applied has no ± here (its run-to-run repeatability is not "
                     "known); its error is common to every cycle: averaging longer does "
                     "not reduce it.")
           : b.valid ? fmt::format(
                           " The ΔN error ±{} °/s is common to every cycle: averaging longer does "
                           "not reduce it.",
                           u2(b.new_power_up_dps))
                     : fmt::format(
                           " The ΔN applied has no ± here ({}); its error is common to "
                           "every cycle: averaging longer does not reduce it.",
                           b.invalid_why);
  }
  // The noise, as the noise table prints it: the same term (B) of both series of the first run.
  out += noise_sentence(runs.front());
  // A ΔN that is not the sensor's has no error to compare with B (review of issue 31: "±3.5 °/h"
  // beside a ΔN 1800 °/h off).
  if (f.not_stationary.empty()) out += delta_n_in_dph(b, runs.front());
  out += f.warnings.empty() ? " Nothing in the runs looks wrong."
                            : fmt::format(" Watch: {} warning{} below.", f.warnings.size(),
                                          f.warnings.size() == 1 ? "" : "s");
  return out;
}

json budget_json(const delta_n_budget& b) {
  return {{"runs", b.runs},
          {"within_run_dps", num(b.within_run_dps)},
          {"run_to_run_dps", num(b.run_to_run_dps)},
          {"run_to_run_measured", b.run_to_run_measured},
          {"run_to_run_source", b.run_to_run_source},
          {"model_dps", b.model_dps ? num(*b.model_dps) : json(nullptr)},
          {"model_note", b.model_note},
          {"calibration_dps", num(b.calibration_dps)},
          {"outside_calibration_c", num(b.outside_c)},
          {"temperature_dps", num(b.temperature_dps)},
          {"temperature_note", b.temperature_note},
          {"valid", b.valid},
          {"new_power_up_dps", num(b.new_power_up_dps)}};
}

report::table budget_table(const delta_n_budget& b, bool compensating) {
  const auto v = [](double x) { return std::isfinite(x) ? u2(x) : std::string("unknown"); };
  // The same in B's unit, so that a reader compares the ΔN error with the noise terms (issue 31).
  const auto h = [](double x) {
    return std::isfinite(x) ? u2(x * units::dph_per_dps) : std::string("–");
  };
  const std::string level =
      b.coverage_factor > 1.0
          ? fmt::format(
                "68.3 % intervals: 1 σ, × Student's t {:.3g} for the runs' {} degree{} "
                "of freedom",
                b.coverage_factor, b.run_to_run_dof, b.run_to_run_dof == 1 ? "" : "s")
          : "one standard uncertainty: 1 σ";
  report::table t{
      compensating ? fmt::format("Uncertainty of the ΔN applied (from the calibration; {})", level)
                   : fmt::format("Uncertainty budget of ΔN ({})", level),
      {"component", "value (°/s)", "value (°/h)", "what it is"},
      {{"within-run (correlated)", v(b.within_run_dps), h(b.within_run_dps),
        !b.within_run_note.empty() ? b.within_run_note
        : b.runs == 1
            ? std::string("the run's own error (correlated noise included)")
            : fmt::format("the {} runs' own errors, pooled (correlated noise included)", b.runs)},
       {"run-to-run repeatability", v(b.run_to_run_dps), h(b.run_to_run_dps), b.run_to_run_source},
       {"dN(T) model", b.model_dps ? v(*b.model_dps) : std::string("–"),
        b.model_dps ? h(*b.model_dps) : std::string("–"), b.model_note},
       {"calibrated ΔN", v(b.calibration_dps), h(b.calibration_dps),
        "the error of the calibrated value"},
       {"ΔN of a new power-up", b.valid ? v(b.new_power_up_dps) : std::string("not valid"),
        b.valid ? h(b.new_power_up_dps) : std::string("–"),
        b.valid ? fmt::format("{}{}: what a compensated rate "
                              "carries as a systematic error (w = r − ΔN, paper eqn 12), the "
                              "same in every cycle; the number to quote",
                              b.new_power_up_from_band
                                  ? "the ΔN(T) figure's band for a new run, widest at the runs' "
                                    "temperatures (a between-run variance that changes with "
                                    "temperature, τ²(T)"
                                  : fmt::format("√(calibrated² + {}²", b.coverage_factor > 1.0
                                                                           ? "(t × repeatability)"
                                                                           : "repeatability"),
                              b.outside_c > 0.0 ? " + temperature²)" : ")")
                : b.invalid_why + ": no ± covers the run"}},
      "The components are not added linearly: the within-run error is part of the runs' "
      "scatter, so the calibrated value's error is the model's (which the scatter scales)."};
  // What one run gives on its own (the pooled error above is k runs together, review of issue 31).
  if (b.runs > 1)
    t.rows.insert(t.rows.begin() + 1,
                  {"one run's own error", v(b.single_run_dps), h(b.single_run_dps),
                   fmt::format("the median of the {} runs' own errors: what one run like these "
                               "gives, e.g. a recalibration after each power-up",
                               b.runs)});
  if (std::isfinite(b.between_run_dps))
    t.rows.insert(t.rows.begin() + (b.runs > 1 ? 3 : 2),
                  {"between-run (random effects)", v(b.between_run_dps), h(b.between_run_dps),
                   "the runs' scatter beyond their own noise (√τ², DerSimonian–Laird): a change "
                   "of ΔN at each power-up"});
  if (b.outside_c > 0.0)
    t.rows.insert(t.rows.end() - 1,
                  {"temperature (outside the calibration's)",
                   b.valid ? v(b.temperature_dps) : std::string("not known"),
                   b.valid ? h(b.temperature_dps) : std::string("–"), b.temperature_note});
  return t;
}

}  // namespace

namespace {

// The dwells at every position of a run of more than two (recording_run keeps the pair's), for
// its dwell figure's one series per position; the pair's when the file cannot be read again.
std::vector<method::dwell> all_dwells(const recording_run& run) {
  auto rec = rigdata::read_recording_rows(run.file);
  if (!rec) return run.dwells;
  std::vector<method::dwell> out;
  for (const auto& d : method::indexed_dwells(rec->rows))
    out.push_back(
        {d.position, d.time_s, d.rate_dps, method::no_value, static_cast<std::uint64_t>(d.weight)});
  return out;
}

// North finding (issue 33, docs/NORTH.md): a run whose recording says its table turns about
// the vertical (`# table_axis: up|down`), indexed at three or more positions or 0/180, with the
// latitude known, gets a section with its heading (workflow::find_heading, the numbers
// `gyroflip heading` prints). Other runs, or a run the heading refuses, get none.
std::optional<std::pair<report::section, json>> heading_section(
    const recording_run& run, std::size_t k, const std::optional<io::calibration_geometry>& geo) {
  const std::string axis = metadata_value(run.metadata, "table_axis");
  if (!geo || (axis != "up" && axis != "down") || run.positions.size() < 2) return std::nullopt;
  heading_request q;
  q.runs = {run.file};
  q.lat_deg = geo->lat_deg;
  auto h = find_heading(q);
  if (!h) return std::nullopt;
  report::section s;
  s.heading = fmt::format("Run {}: north finding", k + 1);
  s.paragraphs.push_back(fmt::format(
      "The azimuth of the sensitive axis at the table's 0°, from north, clockwise, from the "
      "first harmonic of the dwell means about the vertical table axis at {:g}° latitude "
      "(docs/NORTH.md): {:.2f}° ± {:.2f}° (1σ from the data's own noise){}.",
      geo->lat_deg, h->heading_deg, h->sigma_deg,
      h->ambiguous
          ? fmt::format(", or its mirror {:.2f}° (0/180 gives it up to its sign)", h->mirror_deg)
          : std::string()));
  report::table t;
  t.caption = "Heading";
  t.header = {"scheme",    "heading (°)",
              "1σ (°)",    "white-noise limit (°)",
              "σ / limit", "first harmonic / Ω_E cos φ"};
  t.rows.push_back({h->scheme, fmt::format("{:.2f}", h->heading_deg),
                    fmt::format("{:.2f}", h->sigma_deg),
                    h->limit_deg > 0.0 ? fmt::format("{:.2f}", h->limit_deg) : "–",
                    h->limit_deg > 0.0 ? fmt::format("{:.2f}", h->ratio_to_limit) : "–",
                    fmt::format("{:.3f}", h->amplitude_dps / h->earth_horizontal_dps)});
  s.tables.push_back(std::move(t));
  for (const auto& c : h->caveats) s.warnings.push_back(c);
  json j = heading_json(*h);
  j["file"] = run.file;
  return std::pair{std::move(s), std::move(j)};
}

}  // namespace

result<report_result> make_report(const report_request& r, const progress_fn& on_progress) {
  if (r.files.empty()) return usage_error("no recording to report on");
  if (r.expected_rate_dps) {
    if (r.calibration.empty())
      return parameter_error("expected_rate_dps",
                             "a commanded rate is checked on compensated runs: give a calibration");
    // 0 is a run at rest (a stationary run, a rate table stopped): compared with 0, with no
    // scale factor (fifth review of issue 31, F13: it was refused).
    if (!(std::isfinite(*r.expected_rate_dps) &&
          std::abs(*r.expected_rate_dps) <= rig::max_rate_dps))
      return parameter_error("expected_rate_dps",
                             fmt::format("must be a rate within ±{:g} °/s", rig::max_rate_dps));
  }
  if (auto s = io::check_distinct_inputs(r.files); !s) return s.err();
  std::vector<std::string> inputs = r.files;
  if (!r.calibration.empty()) inputs.push_back(r.calibration);
  // The folder is checked (and its staging folder made) before any work.
  auto folder = report::report_folder::make(r.output, inputs);
  if (!folder) return folder.err();
  const std::string& staging = folder->path();  // removed with `folder` unless published
  const std::size_t steps = 2 * r.files.size() + 1;
  report_result out;
  findings f;
  if (!r.calibration.empty()) {
    auto dn = delta_n_of_file(r.calibration);
    if (!dn) return dn.err();
    f.given = std::move(*dn);
    f.compensating = true;
  }

  std::vector<run_analysis> runs;
  // The runs of one report are of one sensor, checked as calibrate checks them.
  one_sensor sensors("report on");
  for (std::size_t k = 0; k < r.files.size(); ++k) {
    auto run = read_run(r.files[k]);
    if (!run) return run.err();
    for (const auto& w : run->warnings) f.warnings.push_back(w);
    if (auto s = sensors.add(run->file, run->metadata, f.warnings); !s) return s.err();
    if (f.given) {
      std::vector<std::string> ws;
      if (auto s = check_calibration_fits(run->file, *f.given, run->metadata,
                                          run->cycles(r.pairing), ws);
          !s)
        return s.err();
      f.warnings.insert(f.warnings.end(), ws.begin(), ws.end());
      if (f.given->model.degree() > 0 && !run->has_temp)
        return input_error(
            {run->file}, "no temp_c column, but the calibration's dN(T) model needs temperatures");
    }
    auto a = analyse_run(std::move(*run), r.pairing);
    if (!a) return a.err();
    runs.push_back(std::move(*a));
    if (on_progress) on_progress(k + 1, steps);
  }
  f.id = identify(runs);
  // The specification the runs' g-term is checked against, and whose spread the budget takes:
  // the one resolver calibrate uses (the sensor given, else a simulated run's `# sensor.*`
  // header, else the built-in preset by name; fourth review of issue 31, F4).
  std::optional<sensor::preset> spec;
  if (!runs.empty()) {
    auto resolved = resolve_sensor_spec(r.sensor, runs.front().run.metadata, runs.front().run.file,
                                        false, f.warnings);
    if (!resolved) return resolved.err();
    spec = std::move(*resolved);
  }
  const sensor::preset* g_preset = spec ? &*spec : nullptr;

  // The dN: each calibration run compensated with its own dN (residuals about zero; their mean
  // says nothing); the runs' model (a weighted mean at one temperature, dN(T) over a span). With
  // a calibration: its dN or dN(T) for every run.
  std::vector<io::calibration_entry> entries;
  for (const auto& a : runs) entries.push_back({a.run.file, a.cal, std::nullopt, std::nullopt});
  if (f.given) {
    f.model = f.given->model;
    f.budget = calibration_budget(*f.given, g_preset, f.id.preset, f.warnings);
    check_calibration_temperature(runs, f, g_preset);
    check_calibration_runs_stationary(*f.given, f);
  } else {
    check_stationary(r, g_preset, runs, f, entries);
    auto m = method::fit_runs_model(calibrations_of(entries));
    if (!m) return m.err();
    f.runs_model = *m;
    if (f.runs_model && f.runs_model->degree() > 0) f.model = f.runs_model;
    if (f.runs_model && f.runs_model->degree() == 0)
      f.pooled = std::pair{f.runs_model->coeffs_dps[0], f.runs_model->interval_at(0.0)};
    f.budget = budget_of(entries, f.runs_model, g_preset ? &g_preset->params : nullptr,
                         g_preset ? g_preset->name : f.id.preset);
    check_runs_agree(f);
  }
  // Runs that failed the stationarity test give no ΔN of the sensor, so no ± covers what it is
  // used for: the budget is not valid and nothing is "the number to quote" (review of issue 31).
  if (!f.not_stationary.empty()) {
    f.budget.valid = false;
    f.budget.invalid_why = f.given
                               ? "not known: the calibration's runs failed the stationarity test"
                               : "not known: the runs failed the stationarity test";
  }
  for (auto& a : runs) {
    const auto model = f.given ? f.given->model : method::constant_model(a.cal.delta_n_dps);
    if (auto s = compensate_run(a, model); !s) return s.err();
    if (a.comp.outside_model > 0)
      f.warnings.push_back(outside_model_warning(a.run.file, a.comp, *f.model));
    f.rates.push_back(r.expected_rate_dps
                          ? std::optional(check_rate(a.comp.summary, *r.expected_rate_dps,
                                                     new_power_up_at(f.budget, a.cal.temp_c)))
                          : std::nullopt);
    if (f.rates.back()) check_commanded_rate(a, *r.expected_rate_dps, *f.rates.back(), f);
  }
  if (!f.compensating && f.runs_model && !f.budget.model_dps)
    f.warnings.push_back(fmt::format(
        "the dN(T) line passes exactly through its {} runs (0 degrees of freedom): its error is "
        "not determined, and the run-to-run repeatability is not measured; calibrate more runs "
        "than the line has coefficients",
        runs.size()));
  for (const auto& a : runs)
    if (a.cal.cycles < min_cycles)
      f.warnings.push_back(fmt::format(
          "{}: {} cycles: too few for a standard error that accounts for correlated noise (at "
          "least {}: the scatter of n cycles is itself uncertain by 1/√(2(n−1)), and the "
          "correlation is estimated from blocks of cycles); its ± understates the truth",
          a.run.file, a.cal.cycles, min_cycles));
  if (!f.compensating && f.budget.run_to_run_dof == 1)
    f.warnings.push_back(fmt::format(
        "the run-to-run repeatability {} °/s is {} with 1 degree of freedom ({} runs for "
        "{} coefficient{}): a std of one degree of freedom is itself uncertain by about 70 %; "
        "calibrate more runs",
        u2(f.budget.run_to_run_dps),
        f.budget.run_to_run_floored ? "not resolved (the runs scatter less than their own noise)"
                                    : "measured",
        runs.size(), runs.size() - 1, runs.size() == 2 ? "" : "s"));
  if (runs.size() == 1 && !f.compensating)
    f.warnings.push_back(
        "one run: its dN says nothing about the next power-up's (the run-to-run repeatability "
        "below is the sensor preset's or unknown); calibrate several runs");

  // Provenance first: a title, banners and the inputs' identities.
  const auto cal_origin =
      f.compensating ? calibration_origin_of(*f.given->record) : calibration_origin{};
  report::page page;
  page.made.command = r.command;
  page.made.made_utc = report::utc_now();
  page.made.version = std::string(version());
  page.made.commit = std::string(build_commit());
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    auto in = report::identify_file(inputs[k]);
    if (!in) return in.err();
    in->origin = k < runs.size() ? f.id.origin[k]
                                 : fmt::format("calibration (gyroflip.calibration) of {} run{}: {}",
                                               cal_origin.runs, cal_origin.runs == 1 ? "" : "s",
                                               cal_origin.words);
    // A run compensated with a calibration made of it is not an independent test of it.
    if (k < runs.size() && f.compensating) {
      auto same = same_run_warnings(runs[k].run.file, in->sha256, *f.given);
      // Or its cycles in other bytes (a copy, an export; fourth review of issue 31, F6).
      if (same.empty())
        same = same_cycles_warnings(runs[k].run.file, runs[k].run.cycles(r.pairing),
                                    dwell_rates_of(runs[k].run), *f.given);
      for (auto& w : same) f.warnings.push_back(std::move(w));
    }
    if (k < runs.size()) entries[k].source = source_of(runs[k].run.file, runs[k].run.metadata, *in);
    page.made.inputs.push_back(std::move(*in));
  }
  if (auto s = check_distinct_runs(entries); !s) return s.err();
  const temp_span all_t = runs_temps(runs);
  const std::string serials = [&] {
    std::string s;
    for (const auto& x : f.id.serials) s += (s.empty() ? "" : ", ") + x;
    return s;
  }();
  page.title =
      !r.title.empty()
          ? r.title
          : fmt::format(
                "{}{}: {} {} {}, {}", part_of(f.id),
                serials.empty() ? std::string() : " serial " + serials,
                f.compensating                                     ? "compensated"
                : f.not_stationary.empty() && f.not_tested.empty() ? "ΔN calibration from"
                                                                   : "no ΔN calibration:",
                runs.size(),
                f.compensating || (f.not_stationary.empty() && f.not_tested.empty())
                    ? (runs.size() == 1 ? "run" : "runs")
                : !f.not_stationary.empty()
                    ? (runs.size() == 1 ? "run, not stationary" : "runs, not all stationary")
                    : (runs.size() == 1 ? "run, too short to test"
                                        : "runs, not all long enough to test"),
                all_t.text());
  if (f.id.simulated > 0)
    page.banners.push_back(fmt::format(
        "Simulated data: {} of the {} recordings came from gyroflip's {} (see Inputs); "
        "no sensor was measured for them.",
        f.id.simulated, runs.size(),
        f.id.emulated == 0                ? "simulator"
        : f.id.emulated == f.id.simulated ? "emulator (a rig recording of no real board)"
                                          : "simulator or emulator"));
  if (cal_origin.simulated > 0)
    page.banners.push_back(fmt::format(
        "Simulated calibration: the ΔN applied comes from a calibration of which {} of the {} "
        "runs came from gyroflip's simulator or emulator (see Inputs and the calibration's "
        "runs); no sensor was measured for them.",
        cal_origin.simulated, cal_origin.runs));

  // Summary: the conclusion and the warnings.
  report::section top;
  top.heading = "Conclusion";
  top.paragraphs.push_back(conclusion(r, runs, f));
  top.warnings = f.warnings;
  page.sections.push_back(std::move(top));

  // Identity.
  report::section who;
  who.heading = "Sensor and rig";
  report::table idt{"What was measured, with what", {}, {}, ""};
  idt.rows.push_back({"sensor", sensor_words(f.id)});
  idt.rows.push_back({"serial", serials.empty() ? "not recorded" : serials});
  idt.rows.push_back(
      {"data", f.id.simulated == runs.size()
                   ? (f.id.emulated == 0             ? "simulated (gyroflip simulate)"
                      : f.id.emulated == runs.size() ? "emulated (gyroflip emulate: no real board)"
                                                     : "simulated (gyroflip simulate and emulate)")
                   : (f.id.simulated > 0
                          ? fmt::format("{} of {} runs simulated", f.id.simulated, runs.size())
                      : f.id.on_rig == runs.size() ? "recorded on a rig (.gfr)"
                      : f.id.on_rig > 0
                          ? fmt::format("{} of {} runs recorded on a rig (.gfr); the others CSV "
                                        "recordings whose metadata names no maker",
                                        f.id.on_rig, runs.size())
                          : "CSV recordings whose metadata names no maker (origin not known)")});
  if (f.compensating) idt.rows.push_back({"calibration's runs", cal_origin.words});
  for (const auto& m : f.id.rig) idt.rows.push_back({"rig: " + m.key, m.value});
  idt.rows.push_back({"cycle (measured)", fmt::format("{} s", g(cycle_period_s(runs.front()), 4))});
  idt.rows.push_back({"pairing", std::string(method::to_string(r.pairing))});
  if (r.geometry)
    idt.rows.push_back(
        {"geometry", fmt::format("latitude {}°, sensitive axis at 0° (N, E, D) = ({}, {}, {})",
                                 r.geometry->lat_deg, g(r.geometry->axis.north, 3),
                                 g(r.geometry->axis.east, 3), g(r.geometry->axis.down, 3))});
  idt.rows.push_back({"temperatures", all_t.text()});
  who.tables.push_back(std::move(idt));
  // The time the sensor was on before each run (a warm-up transient moves dN), when the
  // recordings carry it (gyroflip simulate writes power_on_before_s).
  const bool power_on = std::any_of(runs.begin(), runs.end(), [](const run_analysis& a) {
    return !metadata_value(a.run.metadata, "power_on_before_s").empty();
  });
  report::table durations{"Runs", {"run", "file", "duration", "cycles", "temperature"}, {}, ""};
  if (power_on) durations.header.emplace_back("sensor on before the run");
  for (std::size_t k = 0; k < runs.size(); ++k) {
    durations.rows.push_back({std::to_string(k + 1), runs[k].run.file,
                              minutes(runs[k].cal.duration_s), std::to_string(runs[k].cal.cycles),
                              cycle_temps(runs[k].run.cycles(r.pairing)).text()});
    if (power_on) {
      const auto s = metadata_value(runs[k].run.metadata, "power_on_before_s");
      durations.rows.back().push_back(s.empty() ? "not recorded" : s + " s");
    }
  }
  who.tables.push_back(std::move(durations));
  if (f.compensating && !f.given->record->files.empty())
    who.tables.push_back(calibration_runs_table(*f.given->record));
  page.sections.push_back(std::move(who));

  // dN and its budget, or the compensated rates.
  report::section main;
  if (!f.compensating) {
    main.heading = "ΔN and its uncertainty";
    main.paragraphs.push_back(fmt::format(
        "ΔN = mean of r = (y₀ − y₁₈₀)/2 over the cycles of each stationary run (paper eqns "
        "8–11), pairing {}. The correlated standard error accounts for the cycles' correlation "
        "(the naive std/√n understates it when the noise is not white).",
        method::to_string(r.pairing)));
    report::table per{"ΔN per run",
                      {"run", "T (°C)", "ΔN ± within-run error (°/s)", "per-cycle std (°/s)",
                       "residual drift (°/s)"},
                      {},
                      "Each run compensated with its own ΔN has a mean of zero by construction: "
                      "its residual's std and drift (max − min of the 100-s moving mean) are "
                      "shown instead."};
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const auto& a = runs[k];
      const auto& s = a.comp.summary;
      per.rows.push_back({fmt::format("{}: {}", k + 1, a.run.file), g(a.cal.temp_c, 3),
                          value_pm(a.cal.delta_n_dps, a.cal.stderr_correlated_dps), g(s.std_dps, 3),
                          s.drift_dps ? g(*s.drift_dps, 3) : "run too short"});
    }
    if (f.pooled) {
      const bool re = f.runs_model && f.runs_model->random_effects;
      per.rows.push_back({re ? "all runs (random-effects mean)" : "all runs (weighted mean)",
                          all_t.text(), value_pm(f.pooled->first, f.pooled->second), "", ""});
      // How the runs are weighted, on the page (review R5, issue 31): each by its within-run
      // error and the runs' scatter beyond it, so the plain mean is shown beside it.
      // The plain mean with the digits its own error (the runs' std / sqrt(n)) supports (third
      // review of issue 31, M4: "0.00288489").
      const double n_runs = static_cast<double>(runs.size());
      double plain = 0.0, ss = 0.0;
      for (const auto& a : runs) plain += a.cal.delta_n_dps / n_runs;
      for (const auto& a : runs) ss += std::pow(a.cal.delta_n_dps - plain, 2);
      const double plain_u = std::sqrt(ss / (n_runs - 1.0) / n_runs);
      per.note += fmt::format(
          " The runs' mean weights each run by 1/(its within-run error² + τ²), τ = {} °/s their "
          "scatter beyond their own errors (random effects, DerSimonian–Laird): when τ dwarfs "
          "the within-run errors, as every power-up's own g-term makes it, this is the plain "
          "mean. Its ± is a 68.3 % interval (modified Knapp–Hartung, Student's t). The plain mean "
          "of the "
          "{} runs is {} °/s; the run-to-run repeatability below is their plain std.",
          g(std::sqrt(std::max(0.0, f.runs_model->between_run_var_dps2)), 2), runs.size(),
          to_digits_of(plain, plain_u, 6));
    } else if (f.runs_model)
      per.note += fmt::format(
          " The runs span {}: they are not pooled into one mean; ΔN(T) "
          "below.",
          all_t.text());
    main.tables.push_back(std::move(per));
    if (r.geometry) {
      const auto g_spec = g_preset != nullptr ? g_term_spec_of(*g_preset) : std::nullopt;
      report::table split{
          fmt::format("ΔN split at {}° latitude (paper eqns 9–11)", r.geometry->lat_deg),
          {"run", "ΔN (°/s)", "Earth term (°/s)", "g-term (°/s)"},
          {},
          g_spec ? fmt::format("The sensor's specification: {}.", g_spec->source) : ""};
      for (std::size_t k = 0; k < runs.size(); ++k) {
        const auto& a = runs[k];
        const auto s =
            method::split_delta_n(a.cal.delta_n_dps, r.geometry->lat_deg, r.geometry->axis);
        const double u = a.cal.stderr_correlated_dps;
        split.rows.push_back({fmt::format("{}: {}", k + 1, a.run.file),
                              to_digits_of(a.cal.delta_n_dps, u, 6), g(s.earth_rate_dps, 6),
                              to_digits_of(s.g_term_dps, u, 4)});
      }
      main.tables.push_back(std::move(split));
    }
  } else {
    main.heading = "Compensated runs";
    const auto& m = *f.model;
    main.paragraphs.push_back(fmt::format(
        "w = r − ΔN per cycle (paper eqn 12), pairing {}, with {}: {}.",
        method::to_string(r.pairing), f.given->source,
        m.degree() == 0
            ? fmt::format("ΔN = {} °/s", to_digits_of(m.coeffs_dps[0], m.interval_at(m.t_ref_c), 6))
            : fmt::format("ΔN(T) of degree {} fitted over {:.1f}–{:.1f} °C", m.degree(),
                          m.temp_min_c, m.temp_max_c)));
    std::vector<std::string> head{"run",
                                  "T (°C)",
                                  "ΔN applied (°/s)",
                                  "mean ± its correlated error (°/s)",
                                  "per-cycle std (°/s)",
                                  "drift (°/s)"};
    if (r.expected_rate_dps) {
      head.emplace_back("commanded (°/s)");
      head.emplace_back("error (°/s)");
      head.emplace_back("scale-factor error (ppm)");
    }
    report::table per{
        "Per run",
        head,
        {},
        f.budget.valid
            ? fmt::format(
                  "The mean's error is its own (random, 1 σ); the ΔN applied adds {} (1 σ) to "
                  "every cycle alike (budget below){}.",
                  power_up_text(f.budget),
                  r.expected_rate_dps ? "; the scale-factor error's uncertainty includes both" : "")
            : fmt::format("The mean's error is its own (random, 1 σ); the ΔN applied has no known "
                          "uncertainty here: {} (budget below){}.",
                          power_up_text(f.budget),
                          r.expected_rate_dps
                              ? "; the scale-factor error's uncertainty is not known either"
                              : "")};
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const auto& a = runs[k];
      const auto& s = a.comp.summary;
      const double power_up = new_power_up_at(f.budget, a.cal.temp_c);
      std::vector<std::string> row{fmt::format("{}: {}", k + 1, a.run.file),
                                   g(a.cal.temp_c, 3),
                                   applied_with_band(a.comp, f.budget, power_up),
                                   value_pm(s.mean_dps, s.stderr_correlated_dps),
                                   g(s.std_dps, 3),
                                   s.drift_dps ? g(*s.drift_dps, 3) : "–"};
      if (f.rates[k]) {
        row.push_back(as_given(*r.expected_rate_dps));
        row.push_back(
            value_pm(f.rates[k]->error_dps, std::hypot(s.stderr_correlated_dps, power_up)));
        row.push_back(value_pm(f.rates[k]->scale_factor_ppm, f.rates[k]->scale_factor_u_ppm));
      }
      per.rows.push_back(std::move(row));
    }
    main.tables.push_back(std::move(per));
  }
  main.tables.push_back(budget_table(f.budget, f.compensating));
  const auto& shown_model = f.compensating ? f.given->record->model : f.runs_model;
  if (shown_model && shown_model->degree() > 0) {
    const auto& m = *shown_model;
    const std::size_t n = m.coeffs_dps.size();
    const std::size_t pts = f.compensating ? f.given->record->files.size() : runs.size();
    report::table mt{
        fmt::format("ΔN(T) = Σ c_k (T − {:.2f} °C)^k, fitted over {:.1f}–{:.1f} °C", m.t_ref_c,
                    m.temp_min_c, m.temp_max_c),
        {"k", "c_k (°/s per °C^k)", "standard error", "68.3 % interval (±)"},
        {},
        pts > n ? fmt::format("{} runs, {} degrees of freedom, χ²/dof {}", pts, pts - n,
                              g(m.chi2_per_dof, 3))
                : fmt::format("{} runs for {} coefficients: 0 degrees of freedom; the errors "
                              "below are the runs' own only and understate the truth",
                              pts, n)};
    for (std::size_t k = 0; k < n; ++k) {
      const auto c = coefficient_of(m, k, f.budget);
      // No "0" error where there are no degrees of freedom (third review of issue 31, M1).
      const bool none = pts <= n && !(c.se > 0.0);
      const std::string nd = "not determined (0 degrees of freedom)";
      mt.rows.push_back({std::to_string(k), c.value, none ? nd : u2(c.se),
                         std::isfinite(c.interval) && c.interval > 0.0 ? u2(c.interval) : nd});
    }
    main.tables.push_back(std::move(mt));
  }
  if (!f.compensating && runs.size() > 1) {
    auto fig = draw(report::delta_n_runs_figure(entries, "ΔN per run"), staging, "delta_n_runs",
                    "the paper's Tab. 3/4 as a figure");
    if (!fig) return fig.err();
    main.figures.push_back(*fig);
  }
  if (!f.compensating && f.model && f.model->degree() > 0) {
    auto dt = report::delta_n_temperature_figure(entries, *f.model, "ΔN against temperature");
    if (!f.budget.model_dps && f.model->interval_at(f.model->t_ref_c) > 0.0)
      dt.caption += ", 0 degrees of freedom: the band is the runs' own error only";
    auto fig = draw(dt, staging, "delta_n_temperature", "");
    if (!fig) return fig.err();
    main.figures.push_back(*fig);
  }
  page.sections.push_back(std::move(main));

  // The calibration runs' stationarity test (a ΔN given as a number has no runs to show).
  if (!f.compensating || f.given->record) {
    report::section stationary;
    stationary.heading = "Stationarity";
    stationary.tables.push_back(f.compensating ? stationarity_table(f.given->record->files, true)
                                               : stationarity_table(entries, false));
    page.sections.push_back(std::move(stationary));
  }

  report::section noise;
  noise.heading = "Noise";
  noise.tables.push_back(noise_table(runs));
  if (auto d = drift_table(runs); !d.rows.empty()) noise.tables.push_back(std::move(d));
  page.sections.push_back(std::move(noise));
  page.sections.push_back(pairing_section(runs));

  json north = json::array();  // the heading sections' numbers, for summary.json
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& a = runs[k];
    report::section s;
    s.heading = fmt::format("Run {}: {} ({}, {})", k + 1, a.run.file, minutes(a.cal.duration_s),
                            cycle_temps(a.run.cycles(r.pairing)).text());
    const auto add = [&](const report::figure& fig, const char* what,
                         const std::string& caption) -> status {
      auto fr = draw(fig, staging, stem_of(k, what), caption);
      if (!fr) return fr.err();
      s.figures.push_back(*fr);
      return ok();
    };
    std::vector<report::allan_curve> curves;
    // Both series with the terms the noise table prints for them.
    if (a.raw_noise)
      curves.push_back({"raw: dwell means at 0°", a.raw_noise->oadev, fitted_terms(*a.raw_noise)});
    if (a.comp_noise)
      curves.push_back({"compensated (" + std::string(method::to_string(a.pairing)) + " cycles)",
                        a.comp_noise->oadev, fitted_terms(*a.comp_noise)});
    const std::string name = a.run.file;
    for (const auto& st :
         {add(report::dwell_figure(a.run.positions.size() > 2 ? all_dwells(a.run) : a.run.dwells,
                                   name + (a.run.positions.size() > 2 ? ": output at each position"
                                                                      : ": output at 0° and 180°"),
                                   a.run.pair, a.run.positions),
              "dwells", "the paper's Figs 3/5/7/9"),
          add(report::compensated_figure(
                  a.comp.cycles, a.comp.summary,
                  name + (f.compensating ? ": compensated rate" : ": residual about its own ΔN"),
                  f.compensating),
              "compensated", "the paper's Figs 4/6/8/10"),
          add(report::bias_figure(a.run.cycles(a.pairing), name + ": bias estimate c(t)"), "bias",
              ""),
          curves.empty()
              ? ok()
              : add(report::gyro_allan_figure(curves, name + ": Allan deviation"), "allan",
                    "68.3 % bounds; dashed: the fitted IEEE 952 terms of the Noise "
                    "table")})
      if (!st) return st.err();
    page.sections.push_back(std::move(s));
    if (auto h = heading_section(a.run, k, r.geometry)) {
      page.sections.push_back(std::move(h->first));
      north.push_back(std::move(h->second));
    }
    if (on_progress) on_progress(r.files.size() + k + 1, steps);
  }
  for (const auto& s : page.sections) out.figures += s.figures.size();

  // summary.json: the same numbers.
  json sj = io::schema_object("report", summary_schema);
  json inj = json::array();
  for (const auto& in : page.made.inputs)
    inj.push_back({{"file", in.file},
                   {"bytes", in.size_bytes},
                   {"sha256", in.sha256},
                   {"origin", in.origin}});
  sj.update(
      json{{"command", page.made.command},
           {"made_utc", page.made.made_utc},
           {"commit", page.made.commit},
           {"title", page.title},
           {"mode", f.compensating ? "compensation" : "calibration"},
           {"pairing", method::to_string(r.pairing)},
           {"sensor",
            {{"name", f.id.preset},
             {"description", sensor_words(f.id)},
             {"serials", std::vector<std::string>(f.id.serials.begin(), f.id.serials.end())}}},
           {"simulated_runs", f.id.simulated},
           {"calibration_simulated_runs", cal_origin.simulated},
           {"inputs", std::move(inj)},
           {"calibration_runs",
            f.compensating ? calibration_runs_json(*f.given->record) : json::array()},
           {"runs", json::array()},
           {"budget", budget_json(f.budget)},
           {"warnings", f.warnings},
           {"conclusion", page.sections.front().paragraphs.front()}});
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& a = runs[k];
    const auto& s = a.comp.summary;
    json j = {{"file", a.run.file},
              {"sha256", page.made.inputs[k].sha256},
              {"cycles", a.cal.cycles},
              {"duration_s", a.cal.duration_s},
              {"temp_c", num(a.cal.temp_c)},
              {"delta_n_dps", a.cal.delta_n_dps},
              {"std_dps", a.cal.std_dps},
              {"stderr_dps", a.cal.stderr_dps},
              {"stderr_correlated_dps", a.cal.stderr_correlated_dps}};
    // The run's stationarity test as the page's table shows it (a calibration's runs; F7).
    if (!f.compensating && entries[k].stationarity)
      j["stationarity"] = io::stationarity_to_json(*entries[k].stationarity);
    if (f.compensating) {
      const auto [lo, hi] = applied_range(a.comp);
      j["compensated"] = {
          {"delta_n_applied_min_dps", lo},
          {"delta_n_applied_max_dps", hi},
          {"delta_n_new_power_up_dps", num(new_power_up_at(f.budget, a.cal.temp_c))},
          {"mean_dps", s.mean_dps},
          {"std_dps", s.std_dps},
          {"stderr_correlated_dps", s.stderr_correlated_dps},
          {"drift_dps", s.drift_dps ? json(*s.drift_dps) : json(nullptr)},
          {"drift_window_s", s.drift_window_s}};
      if (f.rates[k])
        j["compensated"].update(
            json{{"expected_rate_dps", *r.expected_rate_dps},
                 {"error_dps", f.rates[k]->error_dps},
                 {"scale_factor_error_ppm", num(f.rates[k]->scale_factor_ppm)},
                 {"scale_factor_error_u_ppm", num(f.rates[k]->scale_factor_u_ppm)}});
    } else {
      j["residual"] = {{"std_dps", s.std_dps},
                       {"drift_dps", s.drift_dps ? json(*s.drift_dps) : json(nullptr)},
                       {"drift_window_s", s.drift_window_s}};
    }
    const auto v = [](const analysis::noise_term& x, double to) {
      return x.resolved ? json(x.value * to) : json(nullptr);
    };
    if (a.comp_noise && noise_fitted(*a.comp_noise)) {
      const auto& t = a.comp_noise->terms;
      j["noise"] = {{"arw_deg_rth", v(t.arw, units::deg_rth_per_deg_rts)},
                    {"bias_instability_deg_h", v(t.bias_instability, units::dph_per_dps)},
                    {"rrw_deg_h_rth", v(t.rrw, units::dph_rth_per_dps_rts)}};
    }
    if (a.raw_noise && noise_fitted(*a.raw_noise)) {
      const auto& t = a.raw_noise->terms;
      j["raw_noise"] = {
          {"arw_deg_rth", v(t.arw, units::deg_rth_per_deg_rts)},
          {"bias_instability_deg_h", v(t.bias_instability, units::dph_per_dps)},
          {"rrw_deg_h_rth", v(t.rrw, units::dph_rth_per_dps_rts)},
          {"duty", a.raw_duty > 0.0 ? json(a.raw_duty) : json(nullptr)},
          {"sensor_arw_deg_rth", a.raw_duty > 0.0
                                     ? v(t.arw, units::deg_rth_per_deg_rts * std::sqrt(a.raw_duty))
                                     : json(nullptr)}};
    }
    sj["runs"].push_back(std::move(j));
  }
  if (!north.empty()) sj["north_finding"] = std::move(north);
  if (f.model)
    sj["delta_n_model"] = {{"coeffs_dps", f.model->coeffs_dps},
                           {"t_ref_c", num(f.model->t_ref_c)},
                           {"degree", f.model->degree()},
                           {"chi2_per_dof", f.model->chi2_per_dof}};
  auto summary_text = io::finite_dump(sj, r.output + "/summary.json");
  if (!summary_text) return summary_text.err();
  auto page_text = report::html(page, staging);
  if (!page_text) return page_text.err();
  for (const auto& [name, text] :
       {std::pair{"summary.json", *summary_text + "\n"}, std::pair{"index.html", *page_text}})
    if (auto s = io::write_file_atomically(staging + "/" + name, text); !s) return s.err();
  if (auto s = report::print_pdf(page, staging); !s) return s.err();
  if (auto s = folder->publish(fmt::format("{} {}", r.made_by, version())); !s) return s.err();
  out.summary_json = *summary_text;
  out.warnings = f.warnings;  // the page's and summary.json's
  if (on_progress) on_progress(steps, steps);
  return out;
}

}  // namespace gyroflip::workflow
