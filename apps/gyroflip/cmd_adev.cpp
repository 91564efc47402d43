/// \file
/// \brief `gyroflip adev`: an Allan-family deviation curve with confidence intervals.
#include "cmd_adev.hpp"

#include "finite_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>

#include <unistd.h>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/cross.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/ros_bag.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/method/flip_detect.hpp"
#include "gyroflip/report/figures.hpp"
#include "progress_bar.hpp"
#include "rig_input.hpp"

namespace gyroflip::app {
namespace {

// `--ci none`: the bound, EDF and noise-type fields are empty (CSV) or null (JSON).
constexpr const char* csv_header = "tau_s,dev,ci_lo,ci_hi,edf,n,alpha\n";

// What the numbers depend on beyond the data, as `#` lines after `# units` (review L2): the
// guarded interval rule, a given noise type and the bias correction when asked for (no line:
// Stable32's rule, no correction; the default output keeps its two header lines).
std::string csv_settings(const adev_options& o, std::optional<double> level) {
  std::string s;
  if (level && o.ci_guard) s += "# ci_rule: guarded\n";
  if (level && o.alpha) s += fmt::format("# ci_rule: given alpha {}\n", *o.alpha);
  if (!level && o.alpha) s += fmt::format("# alpha_given: {}\n", *o.alpha);
  if (o.bias_correction) s += "# bias_correction: stable32\n";
  return s;
}

// The rows of one curve (no header); `prefix` starts each row (a column's name and a comma).
// with_alpha: the noise type even without intervals (it scaled a bias-corrected value; review L2).
std::string csv_rows(const std::vector<analysis::deviation_point>& pts, bool with_ci,
                     const std::string& prefix, bool with_alpha = false) {
  std::string s;
  for (const auto& p : pts) {
    if (with_ci) {
      s += prefix + fmt::format("{},{},{},{},{},{},{}\n", p.tau_s, p.dev, p.ci_lo, p.ci_hi, p.edf,
                                p.n, p.alpha);
    } else {
      s += prefix + fmt::format("{},{},,,,{},{}\n", p.tau_s, p.dev, p.n,
                                with_alpha ? std::to_string(p.alpha) : std::string());
    }
  }
  return s;
}

// For a person at a terminal: aligned columns with 4 significant digits, the unit in the header,
// and the averaging factor m; `-o` and `--json` keep every digit.
std::string table_text(const std::vector<analysis::deviation_point>& pts, bool with_ci,
                       const std::string& title, const std::string& unit, bool with_alpha) {
  std::string s = title + "\n";
  const std::string dev = "dev [" + unit + "]";
  s += fmt::format("{:>11} {:>9} {:>13} {:>11} {:>11} {:>8} {:>9} {:>5}\n", "tau [s]", "m", dev,
                   "ci_lo", "ci_hi", "edf", "n", "alpha");
  for (const auto& p : pts) {
    if (with_ci)
      s += fmt::format("{:>11.4g} {:>9} {:>13.4e} {:>11.4e} {:>11.4e} {:>8.4g} {:>9} {:>5}\n",
                       p.tau_s, p.m, p.dev, p.ci_lo, p.ci_hi, p.edf, p.n, p.alpha);
    else
      s += fmt::format("{:>11.4g} {:>9} {:>13.4e} {:>11} {:>11} {:>8} {:>9} {:>5}\n", p.tau_s, p.m,
                       p.dev, "-", "-", "-", p.n, with_alpha ? std::to_string(p.alpha) : "-");
  }
  return s;
}

// The points as JSON; the interval columns are null when no interval was asked for (alpha too,
// unless with_alpha: see csv_rows).
nlohmann::json points_json(const std::vector<analysis::deviation_point>& pts, bool with_ci,
                           bool with_alpha = false) {
  using nlohmann::json;
  const auto or_null = [with_ci](auto v) { return with_ci ? json(v) : json(nullptr); };
  json points = json::array();
  for (const auto& p : pts)
    points.push_back({{"tau_s", p.tau_s},
                      {"m", p.m},
                      {"dev", p.dev},
                      {"ci_lo", or_null(p.ci_lo)},
                      {"ci_hi", or_null(p.ci_hi)},
                      {"edf", or_null(p.edf)},
                      {"n", p.n},
                      {"alpha", with_alpha ? json(p.alpha) : or_null(p.alpha)}});
  return points;
}

nlohmann::json json_of(const adev_options& o, const std::string& column, double tau0_s,
                       std::size_t samples, const std::vector<analysis::deviation_point>& pts,
                       const std::vector<analysis::dropped_factor>& dropped,
                       std::optional<double> level) {
  using nlohmann::json;
  json gone = json::array();
  for (const auto& d : dropped) gone.push_back({{"m", d.m}, {"tau_s", d.tau_s}, {"why", d.why}});
  json points = points_json(pts, level.has_value(), o.bias_correction);
  return with_schema("adev", 1,
                     {{"kind", o.kind},
                      {"input", o.in.input},
                      {"file", o.in.file},
                      {"column", column},
                      {"units", dev_unit(o.in, o.kind)},
                      {"tau0_s", tau0_s},
                      {"samples", samples},
                      {"ci", level ? json(*level) : json(nullptr)},
                      {"ci_rule", level ? json(o.ci_guard ? "guarded"
                                               : o.alpha  ? "given"
                                                          : "stable32")
                                        : json(nullptr)},
                      {"alpha_given", o.alpha ? json(*o.alpha) : json(nullptr)},
                      {"bias_correction", o.bias_correction},
                      {"points", std::move(points)},
                      {"dropped", std::move(gone)}});
}

}  // namespace

double deg_per_unit(const series_input& in) {
  return units::deg_per_unit(in.units);
}

std::string unit_name(const series_input& in) {
  return std::string(units::unit_name(in.input == "angle", in.units));
}

std::string bias_corrected_kinds() {
  std::vector<std::string_view> names;
  for (const auto& f : analysis::dev_table)
    if (f.bias_correction) names.push_back(f.name);
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + std::string(names[i]);
  return out;
}

std::string dev_unit(const series_input& in, std::string_view kind) {
  // Time-error statistics are in the angle unit: TDEV = tau MDEV / sqrt(3) (SP1065 eqn 15),
  // TTOTDEV (eqn 28), MTIE and TIE rms (ITU-T G.810: of x itself); the others in the rate unit.
  const auto k = analysis::parse_dev_kind(kind);  // gradev: OADEV's, of the rate
  const bool of_angle = k && analysis::facts(*k).angle_unit;
  const bool angle_in = in.input == "angle";
  const std::string u = unit_name(in);
  if (of_angle == angle_in) return u;
  if (angle_in) return u + "/s";                                  // deg -> deg/s
  return u == "deg/s" ? "deg" : u == "rad/s" ? "rad" : u + "*s";  // deg/h*s: deg/3600
}

namespace {

// `missing_is_nan`: GRADEV's reading, an empty field or nan is a gap (csv_dialect).
io::series_options series_options_of(const series_input& in, bool missing_is_nan = false) {
  io::series_options so;
  so.dialect.missing_is_nan = missing_is_nan;
  so.column = in.column;
  so.dataset = in.dataset;
  if (!std::isnan(in.rate_hz)) so.sample_rate_hz = in.rate_hz;
  so.dialect.delimiter = in.delimiter.empty()                             ? '\0'
                         : in.delimiter == "tab" || in.delimiter == "\\t" ? '\t'
                         : in.delimiter == "space"                        ? ' '
                                                                          : in.delimiter[0];
  so.dialect.decimal = in.decimal[0];
  so.dialect.header = !in.no_header;
  so.time_column = in.time_column;
  so.time_unit_s = in.time_unit == "ms"   ? 1e-3
                   : in.time_unit == "us" ? 1e-6
                   : in.time_unit == "ns" ? 1e-9
                                          : 1.0;
  so.gaps = in.gaps == "split"  ? io::gap_policy::split
            : in.gaps == "fill" ? io::gap_policy::fill
                                : io::gap_policy::error;
  so.topic = in.topic;
  return so;
}

// The series read, checked for flip modulation and ready for analysis as `column`.
result<analysis_input> prepare(io::series s, const series_input& in, const std::string& column) {
  // An uncompensated flip recording's rate switches with the angle: its Allan curve would show
  // the flipping (a square wave), not the sensor (issue 13 item 12).
  if (!s.angle_deg().empty() && !in.ignore_flip) {
    const auto flip = method::detect_flip_modulation(s.values(), s.angle_deg());
    if (flip.modulated)
      return input_error(
          {in.file},
          fmt::format("column '{}' switches with angle_deg (mean {:.6g} at 0 deg, {:.6g} at 180 "
                      "deg): this is an uncompensated flip recording, whose Allan curve shows the "
                      "flipping, not the sensor. Compensate it first (gyroflip compensate {} "
                      "--calibration CAL.json -o OUT.csv, then analyse OUT.csv), or analyse one "
                      "position, or give --ignore-flip to analyse it as it is",
                      printable(column, 60), flip.mean_0, flip.mean_180, printable(in.file, 200)));
  }
  const auto kind = in.input == "angle" ? analysis::input_kind::angle : analysis::input_kind::rate;
  progress bar("reading " + in.file, 1000);
  auto phase = analysis::phase_source::make(s.samples(), kind, s.tau0_s(), per_mille(bar));
  bar.finish();
  // The sample rate was checked when reading, so what fails here is the data: name the file.
  if (!phase)
    return about_parameter(input_error({in.file}, phase.err().message), phase.err().parameter);
  // series keeps its samples on the heap: the source's reference survives the move.
  return analysis_input{std::move(s), std::move(*phase), column, {}};
}

}  // namespace

result<std::vector<std::string>> column_names(const series_input& in) {
  if (in.columns == "all-numeric") return io::numeric_columns(in.file, series_options_of(in));
  std::vector<std::string> names;
  for (const auto& t : text::split(in.column, ',')) names.emplace_back(t.text);
  return names;
}

result<std::vector<analysis_input>> load_series(const series_input& in, bool pool_gaps) {
  if (in.input == "angle" && in.units == "deg/h")
    return usage_error("--units deg/h is a rate unit; angle input is deg or rad");
  if (!in.columns.empty() && in.columns != "all-numeric")
    return usage_error("--columns takes all-numeric (or name them: --column a,b,c)");
  auto names = column_names(in);
  if (!names) return names.err();
  const auto so = series_options_of(in);
  if (is_rig_recording(in.file) && so.gaps == io::gap_policy::fill)
    return usage_error(
        "--gaps fill is for time-stamped samples (CSV, ROS bags); a .gfr's lost dwells are "
        "analysed with --gaps split or --kind gradev");
  std::vector<io::series> read, parts;
  if (names->size() == 1 && in.columns.empty()) {
    const bool pooled = pool_gaps && so.gaps == io::gap_policy::split;
    auto s = is_rig_recording(in.file)
                 ? read_rig_series(in.file, in.column, so.gaps, false, pooled ? &parts : nullptr)
                 : io::read_series(in.file, so);
    if (!s) return s.err();
    read.push_back(std::move(*s));
  } else {
    if (is_rig_recording(in.file))
      return usage_error("several columns: a CSV file or a ROS bag only");
    auto all = io::read_series_columns(in.file, so, *names);
    if (!all) return all.err();
    read = std::move(*all);
  }
  for (const auto& n : read.front().notes()) note(fmt::format("{}: {}", in.file, n));
  std::vector<analysis_input> out;
  for (std::size_t i = 0; i < read.size(); ++i) {
    auto p = prepare(std::move(read[i]), in, (*names)[i]);
    if (!p) return p.err();
    out.push_back(std::move(*p));
  }
  for (auto& part : parts) {
    auto p = prepare(std::move(part), in, names->front());
    if (!p) return p.err();
    out.front().parts.push_back(std::move(*p));
  }
  return out;
}

namespace {

// "No averaging time fits" is about the data given (too short for the taus): an input error
// naming the file, exit 2, as every other bad input (review L3).
error too_short_is_bad_input(const error& e, const std::string& what) {
  if (e.message.starts_with("no averaging time")) return input_error({what}, e.message);
  return e;
}

struct adev_result {
  std::vector<analysis::deviation_point> points;
  std::vector<analysis::dropped_factor> dropped;
};

result<adev_result> deviation_of(const adev_options& o, analysis::dev_kind kind,
                                 const analysis::tau_spec& taus, std::optional<double> level,
                                 const analysis_input& in) {
  const std::string what = in.column == o.in.column ? o.in.file : o.in.file + ":" + in.column;
  // Noise identification for the bounds, or for the total deviations' bias correction alone
  // (then at the default level, the bounds not shown): with the curve, which shares its reads.
  const bool identify = level || o.bias_correction;
  progress bar(fmt::format("{} of {}", o.kind, what), 1000);
  // A known noise type (--alpha) needs no identification: the curve, then that type's EDF.
  auto pts = identify && !o.alpha
                 ? analysis::deviation_with_confidence(
                       kind, in.phase, taus, level.value_or(0.683), per_mille(bar),
                       o.ci_guard ? analysis::edf_rule::guarded : analysis::edf_rule::stable32)
                 : analysis::deviation(kind, in.phase, taus, per_mille(bar));
  bar.finish();
  if (!pts) return too_short_is_bad_input(pts.err(), what);
  if (o.alpha)
    analysis::add_confidence(*pts, kind, in.phase.size(), level.value_or(0.683), *o.alpha);
  if (std::all_of(pts->begin(), pts->end(), [](const auto& p) { return p.dev == 0.0; }))
    warn(
        fmt::format("{}: every deviation is 0: the series is constant (a stuck sensor, a wrong "
                    "column?), or its steps are below about 1e-154, whose squares underflow a "
                    "double (scale the samples)",
                    what));
  // Factors asked for by name but without a single term: say which and why (not silently).
  auto dropped = analysis::dropped_factors(taus, *pts, kind, in.phase.size(), in.phase.tau0_s());
  for (const auto& d : dropped)
    warn(fmt::format("{}: averaging factor {} dropped: {}", what, d.m, d.why));
  if (o.bias_correction) analysis::correct_total_bias(*pts, kind);
  return adev_result{std::move(*pts), std::move(dropped)};
}

// `--dynamic WINDOW_S[:STEP_S]`: the window and step in samples (analysis::dynamic_samples; the
// step a quarter window when not given) for a series of n samples.
result<std::pair<std::size_t, std::size_t>> dynamic_windows(const std::string& spec, double tau0_s,
                                                            std::size_t n) {
  const auto parts = text::split(spec, ':');
  const auto w = parts.empty() ? std::nullopt : text::to_double(parts[0].text);
  const auto st = parts.size() == 2 ? text::to_double(parts[1].text) : std::nullopt;
  if (parts.size() > 2 || !w || (parts.size() == 2 && !st))
    return usage_error("--dynamic takes WINDOW_S or WINDOW_S:STEP_S in seconds (> 0); got " +
                       printable(spec, 60));
  auto r = analysis::dynamic_samples(*w, st, tau0_s, n);
  if (!r) return usage_error(fmt::format("--dynamic {}: {}", printable(spec, 60), r.err().message));
  return r;
}

// DAVAR (cross.hpp): one curve per window, as CSV start_s,tau_s,dev,n (or JSON), and with
// --plot the windows' curves in one Allan plot.
int run_dynamic(const adev_options& o, analysis::dev_kind kind, const analysis::tau_spec& taus,
                std::optional<double> level, const std::optional<plot_file>& plot,
                const analysis_input& in) {
  const auto win = dynamic_windows(o.dynamic, in.series.tau0_s(), in.series.values().size());
  if (!win) return report(win.err());
  const auto kind_of_input =
      o.in.input == "angle" ? analysis::input_kind::angle : analysis::input_kind::rate;
  progress bar(fmt::format("dynamic {} of {}", o.kind, o.in.file), 1000);
  auto d = analysis::dynamic_deviation(kind, in.series.values(), kind_of_input, in.series.tau0_s(),
                                       win->first, win->second, taus, per_mille(bar), level);
  bar.finish();
  if (!d) return report(d.err());
  // Factors asked for by name that a window cannot hold: said once (review L4), as for one curve.
  if (!d->empty()) {
    const std::size_t window_points = win->first + (o.in.input == "angle" ? 0 : 1);
    for (const auto& g :
         analysis::dropped_factors(taus, d->front().curve, kind, window_points, in.series.tau0_s()))
      warn(fmt::format("{}: averaging factor {} dropped from every window of {} samples: {}",
                       o.in.file, g.m, win->first, g.why));
  }
  std::string csv =
      "start_s," + std::string(csv_header) + fmt::format("# units: {}\n", dev_unit(o.in, o.kind));
  nlohmann::json windows = nlohmann::json::array();
  std::vector<report::allan_curve> curves;
  for (const auto& w : *d) {
    // Each window's points with the intervals of that window (the main curve's columns).
    csv += csv_rows(w.curve, level.has_value(), fmt::format("{},", w.start_s));
    windows.push_back(
        {{"start_s", w.start_s}, {"points", points_json(w.curve, level.has_value())}});
    // The figure draws the windows' curves without bars (a family of curves; the bars are in
    // the table).
    auto bare = w.curve;
    for (auto& p : bare) p.ci_lo = p.ci_hi = 0.0;
    curves.push_back({fmt::format("t = {:g} s", w.start_s), std::move(bare), std::nullopt});
  }
  if (auto s = check_finite(csv, o.output.empty() ? "<stdout>" : o.output); !s)
    return report(s.err());
  std::string json_line;
  if (o.json) {
    const auto j = with_schema("adev_dynamic", 1,
                               {{"kind", o.kind},
                                {"file", o.in.file},
                                {"units", dev_unit(o.in, o.kind)},
                                {"tau0_s", in.series.tau0_s()},
                                {"ci", level ? nlohmann::json(*level) : nlohmann::json(nullptr)},
                                {"window_s", static_cast<double>(win->first) * in.series.tau0_s()},
                                {"step_s", static_cast<double>(win->second) * in.series.tau0_s()},
                                {"windows", std::move(windows)}});
    auto t = finite_dump(j, "<stdout>");
    if (!t) return report(t.err());
    json_line = *t + "\n";
  }
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, csv); !s) return report(s.err());
  if (plot) {
    const std::array formats{plot->format};
    if (auto s = report::render(report::allan_figure(curves, dev_unit(o.in, o.kind),
                                                     fmt::format("dynamic {} of {}", o.kind,
                                                                 printable(o.in.file, 100))),
                                plot->dir, plot->stem, formats);
        !s)
      return report(s.err());
  }
  if (o.json)
    fmt::print("{}", json_line);
  else if (o.output.empty())
    fmt::print("{}", csv);
  return 0;
}

// `--codev` (GCODEV of two columns) and `--three-cornered-hat` (clocks A, B, C from the columns
// AB, BC, CA): CSV `clock,tau_s,dev,n` (clock "AB*BC" for the codeviation), or JSON.
int run_multi(const adev_options& o, analysis::dev_kind kind, const analysis::tau_spec& taus,
              const std::optional<plot_file>& plot, const std::vector<analysis_input>& in) {
  const std::size_t want = o.codev ? 2 : 3;
  if (in.size() != want)
    return report(usage_error(
        o.codev ? "--codev needs two columns: --column AB,CB (comparisons with the common clock B)"
                : "--three-cornered-hat needs three columns: --column "
                  "AB,BC,CA (the comparisons of clocks A, B, C)"));
  const auto kind_of_input =
      o.in.input == "angle" ? analysis::input_kind::angle : analysis::input_kind::rate;
  const double tau0 = in[0].series.tau0_s();
  std::vector<std::pair<std::string, std::vector<analysis::deviation_point>>> curves;
  if (o.codev) {
    auto c =
        analysis::gcodev(in[0].series.values(), in[1].series.values(), kind_of_input, tau0, taus);
    if (!c) return report(too_short_is_bad_input(c.err(), o.in.file));
    curves.emplace_back(in[0].column + "*" + in[1].column, std::move(*c));
  } else {
    auto h = analysis::three_cornered_hat(kind, in[0].series.values(), in[1].series.values(),
                                          in[2].series.values(), kind_of_input, tau0, taus);
    if (!h) return report(too_short_is_bad_input(h.err(), o.in.file));
    for (std::size_t c = 0; c < 3; ++c) curves.emplace_back(std::string(1, "ABC"[c]), (*h)[c]);
  }
  // A factor of the list without a term: said, as for one curve (review F-L6).
  for (const auto& d : analysis::dropped_factors(taus, curves.front().second,
                                                 o.codev ? analysis::dev_kind::oadev : kind,
                                                 in[0].phase.size(), tau0))
    warn(fmt::format("{}: averaging factor {} dropped: {}", o.in.file, d.m, d.why));
  const std::string unit = dev_unit(o.in, o.codev ? "oadev" : o.kind);
  std::string csv = "clock,tau_s,dev,n\n" + fmt::format("# units: {}\n", unit);
  nlohmann::json j = nlohmann::json::array();
  std::vector<report::allan_curve> drawn;
  for (const auto& [name, pts] : curves) {
    nlohmann::json points = nlohmann::json::array();
    std::vector<analysis::deviation_point> resolved;
    std::string unresolved;
    for (const auto& p : pts) {
      // The hat's negative variance estimates (analysis reports them as 0): not a measurement of
      // zero but a clock below what the comparisons resolve (review L5): an empty field, null.
      const bool none = o.three_cornered_hat && p.dev == 0.0;
      csv += none ? fmt::format("{},{},,{}\n", name, p.tau_s, p.n)
                  : fmt::format("{},{},{},{}\n", name, p.tau_s, p.dev, p.n);
      points.push_back({{"tau_s", p.tau_s},
                        {"m", p.m},
                        {"dev", none ? nlohmann::json(nullptr) : nlohmann::json(p.dev)},
                        {"n", p.n}});
      if (none)
        unresolved += fmt::format("{}{:g}", unresolved.empty() ? "" : ", ", p.tau_s);
      else
        resolved.push_back(p);
    }
    if (!unresolved.empty())
      warn(
          fmt::format("clock {}: not resolved at tau = {} s (its variance estimate is negative: "
                      "the other clocks' noise dominates there); left empty",
                      name, unresolved));
    j.push_back({{"clock", name}, {"points", std::move(points)}});
    drawn.push_back({name, std::move(resolved), std::nullopt});
  }
  if (auto s = check_finite(csv, o.output.empty() ? "<stdout>" : o.output); !s)
    return report(s.err());
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, csv); !s) return report(s.err());
  if (plot) {  // the three clocks in one Allan plot (--codev was refused a plot: it may be < 0)
    const std::array formats{plot->format};
    if (auto s = report::render(
            report::allan_figure(
                drawn, unit,
                fmt::format("three-cornered hat ({}) of {}", o.kind, printable(o.in.file, 100))),
            plot->dir, plot->stem, formats);
        !s)
      return report(s.err());
  }
  if (o.json) {
    auto t = finite_dump(with_schema("adev_curves", 1,
                                     {{"kind", o.codev ? "gcodev" : o.kind},
                                      {"file", o.in.file},
                                      {"units", unit},
                                      {"curves", std::move(j)}}),
                         "<stdout>");
    if (!t) return report(t.err());
    fmt::print("{}\n", *t);
  } else if (o.output.empty()) {
    fmt::print("{}", csv);
  }
  return 0;
}

// One column's curve, ready to print.
struct computed {
  std::string column;
  adev_result r;
  std::size_t samples = 0;
  double tau0_s = 0.0;
};

// `--kind gradev`: each column read with its gaps (an empty field or nan in a CSV, NaN in a
// binary file), GRADEV (cross.hpp) of each. The bad-input rules hold for every other field.
result<std::vector<computed>> gradev_columns(const adev_options& o,
                                             const analysis::tau_spec& taus) {
  auto names = column_names(o.in);
  if (!names) return names.err();
  const auto so = series_options_of(o.in, true);
  std::vector<io::series> read;
  if (is_rig_recording(o.in.file)) {
    // A rig recording's lost dwells are gaps on its grid of cycles.
    if (names->size() != 1 || !o.in.columns.empty())
      return usage_error("several columns: a CSV file only");
    auto s = read_rig_series(o.in.file, o.in.column, so.gaps, true);
    if (!s) return s.err();
    read.push_back(std::move(*s));
  } else if (names->size() == 1 && o.in.columns.empty()) {
    auto s = io::read_series(o.in.file, so);
    if (!s) return s.err();
    read.push_back(std::move(*s));
  } else {
    auto all = io::read_series_columns(o.in.file, so, *names);
    if (!all) return all.err();
    read = std::move(*all);
  }
  const auto in_kind =
      o.in.input == "angle" ? analysis::input_kind::angle : analysis::input_kind::rate;
  std::vector<computed> out;
  for (std::size_t i = 0; i < read.size(); ++i) {
    const auto& col = (*names)[i];
    const std::string what = names->size() == 1 ? o.in.file : o.in.file + ":" + col;
    auto pts = analysis::gradev(read[i].values(), in_kind, read[i].tau0_s(), taus);
    if (!pts) return input_error({what}, pts.err().message);
    out.push_back(
        {col, adev_result{std::move(*pts), {}}, read[i].values().size(), read[i].tau0_s()});
  }
  return out;
}

// Options that do not combine are refused, not ignored (review M2).
status check_combination(const adev_options& o, analysis::dev_kind kind) {
  const bool multi = o.codev || o.three_cornered_hat;
  if (o.codev && o.three_cornered_hat)
    return usage_error("--codev and --three-cornered-hat: give one of them");
  if (multi && !o.dynamic.empty())
    return usage_error("--dynamic analyses one column: not with --codev or --three-cornered-hat");
  if (multi && (o.ci_guard || o.bias_correction))
    return usage_error(
        "--codev and --three-cornered-hat give no intervals and no bias correction: leave out "
        "--ci-guard and --bias-correction");
  if (!o.dynamic.empty() && (o.ci_guard || o.bias_correction))
    return usage_error(
        "--dynamic gives each window the intervals of the noise type identified in it, and no "
        "bias correction: leave out --ci-guard and --bias-correction");
  if (o.codev && kind != analysis::dev_kind::oadev)
    return usage_error(
        "--codev is the Groslambert codeviation of the overlapping Allan deviation: --kind oadev "
        "(the default) only");
  if (o.codev && !o.plot.empty())
    return usage_error(
        "--plot: a codeviation may be negative, which a log-log Allan plot cannot draw (write it "
        "with -o and plot it linearly)");
  // MTIE is a maximum; TIE rms keeps the pair's mean rate (review M4), whose square does not add
  // over independent clocks: (fA - fB)(fA - fC) tau^2 would land in clock A's share.
  if (o.three_cornered_hat &&
      (kind == analysis::dev_kind::mtie || kind == analysis::dev_kind::tierms))
    return usage_error(
        "--three-cornered-hat separates variances that add for independent clocks; MTIE (a "
        "maximum) and TIE rms (which keeps each pair's frequency offset) do not");
  if (multi && !o.ci.empty() && o.ci != "none")
    return usage_error(
        "--codev and --three-cornered-hat give no intervals: leave out --ci (or give --ci none)");
  if (o.alpha && (multi || !o.dynamic.empty() || o.ci_guard))
    return usage_error(
        "--alpha sets one noise type for one curve's intervals: not with --codev, "
        "--three-cornered-hat, --dynamic or --ci-guard");
  if (o.ci_guard && (o.ci == "none" || !analysis::has_edf(kind)))
    return usage_error(
        "--ci-guard guards intervals: not with --ci none, nor with pdev, mtie or tierms (no "
        "intervals)");
  if (o.alpha && o.ci == "none" && !o.bias_correction)
    return usage_error(
        "--alpha sets the noise type of the intervals and the bias correction: with --ci none "
        "and no --bias-correction it has nothing to set");
  if (!analysis::has_edf(kind) && ((!o.ci.empty() && o.ci != "none") || o.alpha))
    return usage_error(
        "pdev, mtie and tierms have no intervals (SP1065 gives them no EDF): leave out --ci and "
        "--alpha");
  return ok();
}

}  // namespace

int run_adev(const adev_options& o) {
  // A ROS bag's columns are in rad/s and m/s^2 (REP 103), as their names say: the deviations
  // are labelled with that unit, not --units' default deg/s.
  if (io::is_ros_bag(io::series_file(o.in.file)) && !o.in.units_given) {
    auto names = column_names(o.in);
    if (!names) return report(names.err());
    std::string unit;
    for (const auto& n : *names) {
      // A column's name, its message field's, or its number from 1: 1-3 the gyro's.
      std::size_t axis = 0;
      for (std::size_t i = 0; i < io::imu_columns.size(); ++i)
        if (n == io::imu_columns[i] || n == io::imu_fields[i] || n == std::to_string(i + 1))
          axis = i;
      const std::string this_unit = axis < 3 ? "rad/s" : "m/s^2";
      if (!unit.empty() && this_unit != unit)
        return report(usage_error(fmt::format(
            "{}: the columns are in {} and {}: analyse the gyro and accelerometer columns in "
            "separate runs, or give --units",
            o.in.file, unit, this_unit)));
      unit = this_unit;
    }
    adev_options named = o;
    named.in.units = unit;
    named.in.units_given = true;
    return run_adev(named);
  }
  // GRADEV is OADEV over the terms without a gap: checked as OADEV, without intervals.
  const bool gaps = o.kind == "gradev";
  const auto kind =
      gaps ? std::optional(analysis::dev_kind::oadev) : analysis::parse_dev_kind(o.kind);
  if (!kind)
    return report(
        usage_error("--kind must be one of " + analysis::dev_kind_names(", ") + ", gradev"));
  if (gaps && (o.codev || o.three_cornered_hat || !o.dynamic.empty() || o.ci_guard || o.alpha ||
               (!o.ci.empty() && o.ci != "none")))
    return report(usage_error(
        "--kind gradev analyses columns with gaps on their own: not with --codev, "
        "--three-cornered-hat, --dynamic, --ci, --alpha or --ci-guard (it has no intervals)"));
  const auto taus = analysis::parse_tau_spec(o.taus);
  if (!taus) return report(taus.err());
  // The validator (cli.cpp) let through only "none" or a number in (0, 1). Kinds without an EDF
  // (PDEV, MTIE, TIE rms) have no bounds: as with --ci none.
  const std::optional<double> level =
      o.ci == "none" || gaps || !analysis::has_edf(*kind)
          ? std::nullopt
          : std::optional<double>(o.ci.empty() ? 0.683 : std::stod(o.ci));
  if (o.bias_correction && !analysis::facts(*kind).bias_correction)
    return report(usage_error("--bias-correction applies to " + bias_corrected_kinds() + " only"));
  if (auto s = check_combination(o, *kind); !s) return report(s.err());
  const auto plot = plot_target(o.plot);
  if (!plot) return report(plot.err());
  // --plot writes its script and one data file per column beside the image: none may be an input.
  // Nor may the script or a data file be the user's, or one restyled since gyroflip wrote it.
  std::vector<std::string> outputs{o.output};
  std::size_t plotted = 0;  // data files
  if (*plot) {
    auto names = column_names(o.in);
    if (!names) return report(names.err());
    plotted = names->size();
    const std::array format{(*plot)->format};
    outputs = report::rendered_files((*plot)->dir, (*plot)->stem, plotted, format);
    outputs.push_back(o.output);
  }
  if (auto s = io::check_outputs(std::array{o.in.file}, outputs); !s) return report(s.err());
  if (*plot)
    if (auto s = report::check_rendered_files((*plot)->dir, (*plot)->stem, plotted); !s)
      return report(s.err());
  if (o.json)
    if (auto s = check_name_for_json(o.in.file); !s) return report(s.err());
  std::vector<computed> done;
  if (gaps) {
    auto g = gradev_columns(o, *taus);
    if (!g) return report(g.err());
    done = std::move(*g);
  } else {
    auto inputs = load_series(o.in);
    if (!inputs) return report(inputs.err());
    if (o.codev || o.three_cornered_hat) return run_multi(o, *kind, *taus, *plot, *inputs);
    if (!o.dynamic.empty()) {
      if (inputs->size() != 1) return report(usage_error("--dynamic analyses one column"));
      return run_dynamic(o, *kind, *taus, level, *plot, inputs->front());
    }
    for (const auto& in : *inputs) {
      auto r = deviation_of(o, *kind, *taus, level, in);
      if (!r) return report(r.err());
      done.push_back({in.column, std::move(*r), in.series.samples().size(), in.phase.tau0_s()});
    }
  }
  // One column: the CSV and JSON of one curve; several: a `column` field in each CSV row and one
  // JSON object per column.
  const bool several = done.size() > 1;
  // Nothing asked of the output and a person reading it: a table instead of CSV.
  const bool table = !o.json && o.output.empty() && ::isatty(STDOUT_FILENO) == 1;
  std::string csv, tables;
  nlohmann::json per_column = nlohmann::json::array();
  std::vector<report::allan_curve> curves;
  for (const auto& [column, r, samples, tau0_s] : done) {
    curves.push_back({several ? column : o.kind, r.points, std::nullopt});
    // The header, then the unit of `dev` as metadata (readers skip `#` lines; scripts read line 1),
    // then the rows: with several columns each row starts with its column.
    if (csv.empty())
      csv = std::string(several ? "column," : "") + csv_header +
            fmt::format("# units: {}\n", dev_unit(o.in, o.kind)) + csv_settings(o, level);
    csv += csv_rows(r.points, level.has_value(), several ? column + "," : "", o.bias_correction);
    if (table)
      tables += table_text(
          r.points, level.has_value(),
          fmt::format("{}{}: {} of column {}, {} samples at {:g} Hz{}", tables.empty() ? "" : "\n",
                      o.in.file, o.kind, column, samples, 1.0 / tau0_s,
                      level ? fmt::format(", {:g} % intervals", 100.0 * *level) : ""),
          dev_unit(o.in, o.kind), o.bias_correction);
    if (o.json)
      per_column.push_back(json_of(o, column, tau0_s, samples, r.points, r.dropped, level));
  }
  // Everything is formatted and checked before anything is written (finite_output.hpp).
  if (auto s = check_finite(csv, o.output.empty() ? "<stdout>" : o.output); !s)
    return report(s.err());
  std::string json_line;
  if (o.json) {
    const nlohmann::json j =
        several ? with_schema("adev_columns", 1,
                              {{"file", o.in.file}, {"columns", std::move(per_column)}})
                : std::move(per_column[0]);
    auto t = finite_dump(j, "<stdout>");
    if (!t) return report(t.err());
    json_line = *t + "\n";
  }
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, csv); !s) return report(s.err());
  if (*plot) {
    const auto title = fmt::format("{} of {}", o.kind, printable(o.in.file, 120));
    const std::array formats{(*plot)->format};
    if (auto s = report::render(report::allan_figure(curves, dev_unit(o.in, o.kind), title),
                                (*plot)->dir, (*plot)->stem, formats);
        !s)
      return report(s.err());
  }
  if (o.json) {
    fmt::print("{}", json_line);
  } else if (table) {
    fmt::print("{}", tables);
  } else if (o.output.empty()) {
    fmt::print("{}", csv);
  }
  return 0;
}

// `--plot FILE.png|.svg|.pdf`: the folder, the stem and the format (nullopt without --plot).
result<std::optional<plot_file>> plot_target(const std::string& path) {
  if (path.empty()) return std::optional<plot_file>{};
  const std::filesystem::path p(path);
  const auto ext = p.extension().string();
  const std::optional<report::image_format> f =
      ext == ".png"   ? std::optional(report::image_format::png)
      : ext == ".svg" ? std::optional(report::image_format::svg)
      : ext == ".pdf" ? std::optional(report::image_format::pdf)
                      : std::nullopt;
  if (!f || p.stem().empty())
    return usage_error("--plot must name a .png, .svg or .pdf file; got " + printable(path));
  const auto dir = p.parent_path().string();
  return std::optional<plot_file>{plot_file{dir.empty() ? "." : dir, p.stem().string(), *f}};
}

}  // namespace gyroflip::app
