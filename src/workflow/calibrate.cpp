/// \file
/// \brief Multi-run calibration (calibrate.hpp).
#include "gyroflip/workflow/calibrate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <span>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/parallel.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/cycle_print.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/method/runs.hpp"
#include "gyroflip/report/page.hpp"
#include "gyroflip/rigdata/recording_source.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip::workflow {

namespace {

// With several files there is always a model (method::fit_runs_model); a chosen degree needs
// several files with temperatures.
result<std::optional<method::delta_n_model>> fit_model(
    const calibrate_request& r, const std::vector<io::calibration_entry>& files,
    std::vector<std::string>& warnings) {
  // The default degree: a run without temperatures makes the model a constant. Said, naming the
  // run and the span the constant now covers (fifth review of issue 31, F8); --degree 1 refuses.
  std::string no_temp;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& f : files)
    if (std::isnan(f.cal.temp_c)) {
      no_temp += (no_temp.empty() ? "" : ", ") + f.file;
    } else {
      lo = std::min(lo, f.cal.temp_c);
      hi = std::max(hi, f.cal.temp_c);
    }
  if (!r.degree && !no_temp.empty() && lo <= hi && hi - lo >= method::min_model_span_c)
    warnings.push_back(fmt::format(
        "{}: no temp_c column, so the runs' dN is fitted as one constant over {:.1f}-{:.1f} °C "
        "instead of a dN(T) line: leave the run out, or ask for degree 0 to mean it",
        no_temp, lo, hi));
  if (r.degree) {
    if (files.size() < 2)
      return parameter_error("degree", "a dN(T) model needs calibrations from several files");
    for (const auto& f : files)
      if (*r.degree > 0 && std::isnan(f.cal.temp_c))  // a constant needs no temperatures
        return about_parameter(
            input_error({f.file}, "no temp_c column; a dN(T) model needs temperatures"), "degree");
  }
  return method::fit_runs_model(calibrations_of(files), r.degree);
}

// The sensor model a simulated recording states in its header (`# sensor.KEY: value`, every
// sensor_params field; workflow/simulate.cpp), as a preset named by `# sensor_name:`: a run
// simulated from a TOML preset carries its g-sensitivity specification there (third review of
// issue 31, low: calibrate said "no sensor specification"). nullopt without a stated
// g_sens_spec_max/typ, or with a field missing or not a number.
std::optional<sensor::preset> header_preset(std::span<const io::csv_metadata> metadata,
                                            const std::string& file) {
  sensor::preset p;
  p.name = metadata_value(metadata, "sensor_name");
  for (const auto& f : sensor::fields()) {
    const std::string key = fmt::format("sensor.{}", f.key);
    const std::string text = metadata_value(metadata, key);
    if (text.empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(v)) return std::nullopt;
    p.params.*f.member = v;
    p.sources.emplace_back(std::string(f.key), fmt::format("{}'s header ({})", file, key));
  }
  if (!(p.params.g_sens_spec_max_dps_per_g > 0.0 || p.params.g_sens_spec_typ_dps_per_g > 0.0))
    return std::nullopt;
  if (p.name.empty()) p.name = file + "'s sensor";
  return p;
}

}  // namespace

result<std::optional<sensor::preset>> resolve_sensor_spec(
    const std::optional<sensor::preset>& given, std::span<const io::csv_metadata> metadata,
    const std::string& file, bool strict, std::vector<std::string>& warnings) {
  const std::string recorded = metadata_value(metadata, "sensor_name");
  if (given) {
    if (!recorded.empty() && !given->name.empty() && recorded != given->name) {
      const std::string what = fmt::format(
          "recorded with sensor '{}', but the specification given is of '{}': its g-term is "
          "checked against another part's",
          printable(recorded, 80), printable(given->name, 80));
      if (strict) return input_error({file}, what + "; refused (strict)");
      warnings.push_back(fmt::format("{}: {}", file, what));
    }
    return given;
  }
  if (auto h = header_preset(metadata, file)) return h;
  if (const auto* b = sensor::find_builtin(recorded)) return std::optional<sensor::preset>(*b);
  return std::optional<sensor::preset>();
}

status check_geometry_header(const std::optional<io::calibration_geometry>& given,
                             std::span<const io::csv_metadata> metadata, const std::string& file,
                             bool strict, std::vector<std::string>& warnings) {
  if (!given) return ok();
  std::vector<std::string> what;
  const std::string lat = metadata_value(metadata, "latitude_deg");
  char* end = nullptr;
  const double lat_deg = std::strtod(lat.c_str(), &end);
  if (!lat.empty() && end != lat.c_str() && *end == '\0' && std::isfinite(lat_deg) &&
      std::abs(lat_deg - given->lat_deg) > 0.01)
    what.push_back(
        fmt::format("latitude {:g}° (the recording says {})", given->lat_deg, printable(lat, 40)));
  const std::string ax = metadata_value(metadata, "axis");
  if (const auto a = earth::parse_axis(ax); !ax.empty() && a) {
    const auto& g = given->axis;
    const double dot = a->north * g.north + a->east * g.east + a->down * g.down;
    const double na = std::sqrt(a->north * a->north + a->east * a->east + a->down * a->down);
    const double ng = std::sqrt(g.north * g.north + g.east * g.east + g.down * g.down);
    if (!(dot >= 0.9999 * na * ng))  // about 0.8 deg apart or more
      what.push_back(
          fmt::format("sensitive axis ({:.3g}, {:.3g}, {:.3g}) N,E,D (the recording "
                      "says '{}')",
                      g.north, g.east, g.down, printable(ax, 40)));
  }
  if (what.empty()) return ok();
  const std::string msg = fmt::format(
      "the geometry given contradicts the recording's header: {}; the Earth term and the g-term "
      "are split with the given one",
      fmt::join(what, "; "));
  if (strict) return input_error({file}, msg + "; refused (strict)");
  warnings.push_back(fmt::format("{}: {}", file, msg));
  return ok();
}

method::stationarity_inputs stationarity_inputs_of(
    method::pairing p, const sensor::preset* preset,
    const std::optional<io::calibration_geometry>& geometry) {
  method::stationarity_inputs in;
  in.pair = p;
  if (preset != nullptr) in.spec = g_term_spec_of(*preset);
  if (preset != nullptr && preset->params.arw_dps_rthz > 0.0)
    in.noise = method::noise_spec{
        preset->params.arw_dps_rthz,
        fmt::format("{}: N = {} °/s/√Hz; {}", preset->name, preset->params.arw_dps_rthz,
                    preset->source_of("arw_dps_rthz"))};
  if (geometry) {
    in.lat_deg = geometry->lat_deg;
    in.axis = geometry->axis;
  }
  return in;
}

std::string stationarity_warning(const std::string& file, const method::stationarity& st) {
  std::string s =
      fmt::format("{}: not a stationary run, so its mean r is not the sensor's dN: ", file);
  const auto f = st.failures();
  for (std::size_t k = 0; k < f.size(); ++k) s += (k ? "; " : "") + f[k];
  return s;
}

result<run_standing> judge_run(const run_subject& who, const method::stationarity& st, bool strict,
                               std::vector<std::string>& warnings) {
  const std::string prefix = who.within.empty() ? "" : who.within + ": its run ";
  const source_location at{who.within.empty() ? who.file : who.within};
  const std::string named = who.within.empty() ? "" : "its run " + who.file + ": ";
  if (st.failed()) {
    const auto w = stationarity_warning(who.file, st);
    if (strict)
      return input_error(at, named + w.substr(who.file.size() + 2) + "; refused (strict)");
    warnings.push_back(prefix + w);
    return run_standing::failed;
  }
  if (st.vouched()) return run_standing::vouched;
  // Not vouched for: scatter and drift not tested (too few cycles), or the g-term not checked.
  for (auto c : st.caveats()) {
    const bool g = c.starts_with("its g-term");
    if (g && !who.hint.empty()) c += ": " + who.hint;
    if (strict)
      return input_error(
          at, fmt::format("{}{}; refused (strict): a strict {} needs {}", named, c, who.task,
                          g ? "the g-term checked" : "the scatter and drift tested"));
    warnings.push_back(fmt::format("{}{}: {}", prefix, who.file, c));
  }
  return st.checked ? run_standing::g_unchecked : run_standing::untested;
}

status one_sensor::add(const std::string& file, std::span<const io::csv_metadata> metadata,
                       std::vector<std::string>& warnings) {
  const auto sr = io::sensor_of(metadata);
  const auto power_on = metadata_value(metadata, "power_on_before_s");
  if (!sensor_) {
    sensor_ = sr;
    first_file_ = file;
    first_power_on_ = power_on;
    return ok();
  }
  if (sr.sensor != sensor_->sensor)
    return input_error({file}, fmt::format("recorded with sensor '{}', but {} with '{}': {} one "
                                           "sensor at a time",
                                           printable(sr.sensor, 80), printable(first_file_, 200),
                                           printable(sensor_->sensor, 80), task_));
  for (const auto& d : io::rig_differences(*sensor_, sr))
    warnings.push_back(fmt::format("{}: rig setting differs from {}: {}", file, first_file_, d));
  if (!power_on.empty() && !first_power_on_.empty() && power_on != first_power_on_)
    warnings.push_back(fmt::format(
        "{}: the sensor was on {} s before the run, {} s before {}'s: a warm-up transient moves "
        "dN differently",
        file, power_on, first_power_on_, first_file_));
  return ok();
}

namespace {

// Every run's fit of the harmonic scheme's terms (method::fit_harmonics), one table and one set of
// separable terms across the runs; the first run's table and table_axis header are kept.
struct harmonic_runs {
  std::vector<method::harmonic_fit> fits;
  std::optional<position_table> table;
  std::string axis_text;
};

result<harmonic_runs> fit_harmonic_runs(const calibrate_request& r) {
  harmonic_runs out;
  auto& fits = out.fits;
  auto& table = out.table;
  std::string first;
  for (const auto& file : r.files) {
    auto rows = rigdata::read_recording_rows(file, r.angle_tolerance_deg);
    if (!rows) return rows.err();
    if (table && rows->positions.describe() != table->describe())
      return input_error({file}, fmt::format("its table ({} deg) is not {}'s ({} deg): the "
                                             "harmonic terms of one table at a time",
                                             rows->positions.describe(), first, table->describe()));
    if (!table) {
      table = rows->positions;
      first = file;
      for (const auto& m : rows->metadata)
        if (m.key == "table_axis") out.axis_text = m.value;
    }
    method::harmonic_options o;
    o.separable = true;
    auto f = method::fit_harmonics(method::indexed_dwells(rows->rows), rows->positions, o);
    if (!f) return input_error({file}, f.err().message);
    if (!fits.empty() && f->names != fits.front().names)
      return input_error(
          {file}, fmt::format("its visiting order separates {}, {}'s {}", fmt::join(f->names, ", "),
                              first, fmt::join(fits.front().names, ", ")));
    fits.push_back(std::move(*f));
  }
  return out;
}

// The harmonic scheme's terms (issue 33 item 2): the runs' plain mean with the covariance of a
// mean of independent runs (sum of their covariances / k^2: within-run errors; the run-to-run
// spread of c1 is the budget's, of dN), and the separability report of the table and its axis.
status add_harmonic_terms_of_files(const calibrate_request& r, io::calibration_record& rec) {
  auto runs = fit_harmonic_runs(r);
  if (!runs) return runs.err();
  add_harmonic_terms(runs->fits, *runs->table, runs->axis_text, rec);
  return ok();
}

}  // namespace

void add_harmonic_terms(std::span<const method::harmonic_fit> fits, const position_table& table,
                        const std::string& axis_text, io::calibration_record& rec) {
  if (fits.empty()) return;
  const auto& names = fits.front().names;
  const std::size_t n = names.size();
  const auto k = static_cast<double>(fits.size());
  std::vector<double> value(n, 0.0), cov(n * n, 0.0);
  for (const auto& f : fits)
    for (std::size_t i = 0; i < n; ++i) {
      value[i] += f.value[i] / k;
      for (std::size_t j = 0; j < n; ++j) cov[i * n + j] += f.covariance[i * n + j] / (k * k);
    }
  rec.terms.clear();
  for (std::size_t i = 0; i < n; ++i)
    rec.terms.push_back({names[i], value[i], std::sqrt(std::max(cov[i * n + i], 0.0))});
  rec.terms_covariance = std::move(cov);
  auto sep = method::separability_of(table, method::table_axis_kind_of(axis_text));
  sep.axis_recorded = !axis_text.empty();
  for (const auto& t : fits.front().dropped) {
    std::erase(sep.estimable, t);
    std::erase_if(sep.meanings, [&t](const method::term_meaning& m) { return m.term == t; });
    sep.pairs.push_back({t, "the bias's slope", t,
                         fmt::format("a visiting period of {} dwells has no room for it beside "
                                     "the bias, its slope and the other terms",
                                     fits.front().period),
                         "a visiting order with a longer period (simulate's default sweep)"});
  }
  rec.separability = std::move(sep);
}

namespace {

// A run whose cycles are an earlier run's (a copy rounded, shifted in time, trimmed or split:
// method::find_in_print; fifth review of issue 31, F5) is not another power-up: a warning naming
// both runs, refused under strict. The same recording twice is refused by check_distinct_runs.
status check_not_a_copy(const std::string& file, std::span<const double> dwell_rates,
                        std::span<const io::calibration_entry> earlier, bool strict,
                        std::vector<std::string>& warnings) {
  for (const auto& e : earlier) {
    const auto hit = e.print ? method::find_in_print(dwell_rates, *e.print) : std::nullopt;
    if (!hit) continue;
    const std::string what = fmt::format(
        "dwells {}–{} of its {} are dwells {}–{} of the run {} ({} in a row alike to a quarter of "
        "that run's scatter): the same data twice, not another power-up",
        hit->first + 1, hit->first + hit->length, dwell_rates.size(), hit->first_print + 1,
        hit->first_print + hit->length, e.file, hit->length);
    if (strict) return input_error({file}, what + "; refused (strict)");
    warnings.push_back(fmt::format("{}: {}", file, what));
  }
  return ok();
}

}  // namespace

result<calibrate_result> calibrate_runs(const calibrate_request& r,
                                        const progress_fn& on_progress) {
  if (r.files.empty()) return usage_error("no recording to calibrate");
  if (auto s = io::check_distinct_inputs(r.files); !s) return s.err();
  // The calibration record names its files, and it is JSON (docs/FORMATS.md).
  for (const auto& file : r.files)
    if (auto s = check_name_for_json(file); !s) return s.err();
  calibrate_result out;
  auto& rec = out.record;
  rec.pairing = r.pairing;
  rec.geometry = r.geometry;
  std::vector<method::cycle> all;
  one_sensor sensors("calibrate");
  const sensor::preset* preset = nullptr;
  std::optional<sensor::preset> resolved;
  for (std::size_t k = 0; k < r.files.size(); ++k) {
    const auto& file = r.files[k];
    auto rc = read_cycles(file, r.pairing, part_progress(on_progress, k, r.files.size()),
                          r.angle_tolerance_deg);
    if (!rc) return rc.err();
    for (auto& w : rc->warnings) out.warnings.push_back(std::move(w));
    auto cal = method::calibrate(rc->cycles);
    if (!cal) return input_error({file}, cal.err().message);
    // The specification: the sensor given, else the recording's built-in preset by name (one
    // sensor for every file: one_sensor refuses a second).
    if (k == 0) {
      auto spec = resolve_sensor_spec(r.sensor, rc->metadata, file, r.strict, out.warnings);
      if (!spec) return spec.err();
      resolved = std::move(*spec);
      preset = resolved ? &*resolved : nullptr;
    }
    if (auto s = check_geometry_header(r.geometry, rc->metadata, file, r.strict, out.warnings); !s)
      return s.err();
    const auto st = method::check_stationarity(
        rc->cycles, *cal, stationarity_inputs_of(r.pairing, preset, r.geometry));
    if (auto s = judge_run({file, {}, "calibration", r.sensor_hint}, st, r.strict, out.warnings);
        !s)
      return s.err();
    // What the calibration was made of, so a report that applies it can say (review R18).
    auto id = report::identify_file(file);
    if (!id) return id.err();
    if (auto s = check_not_a_copy(file, rc->dwell_rates, rec.files, r.strict, out.warnings); !s)
      return s.err();
    rec.files.push_back(
        {file, *cal, source_of(file, rc->metadata, *id), st, method::print_of(rc->dwell_rates)});
    if (auto s = sensors.add(file, rc->metadata, out.warnings); !s) return s.err();
    all.insert(all.end(), rc->cycles.begin(), rc->cycles.end());
  }
  if (auto s = check_distinct_runs(rec.files); !s) return s.err();
  rec.sensor = sensors.sensor();
  if (!rec.sensor->known())
    out.warnings.emplace_back(
        "the recordings name no sensor (no `# sensor_name:` or `# serial:` line): a compensation "
        "cannot check that this calibration is applied to the same sensor");
  auto pooled = method::calibrate(all);
  if (!pooled) return pooled.err();
  rec.pooled = *pooled;
  rec.pooled.stderr_correlated_dps = method::pooled_correlated_stderr(calibrations_of(rec.files));
  auto model = fit_model(r, rec.files, out.warnings);
  if (!model) return model.err();
  rec.model = std::move(*model);
  if (auto w = runs_disagree_warning(rec.model)) out.warnings.push_back(std::move(*w));
  if (auto w = runs_too_alike_warning(rec.model)) out.warnings.push_back(std::move(*w));
  out.budget = budget_of(rec.files, rec.model, preset != nullptr ? &preset->params : nullptr,
                         preset != nullptr ? preset->name : std::string());
  if (r.pairing == method::pairing::harmonic)
    if (auto s = add_harmonic_terms_of_files(r, rec); !s) return s.err();
  const auto& b = out.budget;
  rec.uncertainty = io::calibration_uncertainty{
      b.calibration_dps, b.run_to_run_dps,   b.run_to_run_measured, b.run_to_run_source,
      b.between_run_dps, b.new_power_up_dps, b.coverage_factor,     b.run_to_run_dof};
  return out;
}

}  // namespace gyroflip::workflow
