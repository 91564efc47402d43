/// \file
/// \brief `gyroflip adev`: an Allan-family deviation curve with confidence intervals.
#include "cmd_adev.hpp"

#include "finite_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/method/flip_detect.hpp"
#include "progress_bar.hpp"
#include "rig_input.hpp"

namespace gyroflip::app {
namespace {

// `--ci none`: the bound, EDF and noise-type fields are empty (CSV) or null (JSON).
std::string csv_text(const std::vector<analysis::deviation_point>& pts, bool with_ci) {
  std::string s = "tau_s,dev,ci_lo,ci_hi,edf,n,alpha\n";
  for (const auto& p : pts) {
    if (with_ci) {
      s += fmt::format("{},{},{},{},{},{},{}\n", p.tau_s, p.dev, p.ci_lo, p.ci_hi, p.edf, p.n,
                       p.alpha);
    } else {
      s += fmt::format("{},{},,,,{},\n", p.tau_s, p.dev, p.n);
    }
  }
  return s;
}

nlohmann::json json_of(const adev_options& o, double tau0_s, std::size_t samples,
                       const std::vector<analysis::deviation_point>& pts,
                       const std::vector<analysis::dropped_factor>& dropped,
                       std::optional<double> level) {
  using nlohmann::json;
  const auto or_null = [&level](auto v) { return level ? json(v) : json(nullptr); };
  json gone = json::array();
  for (const auto& d : dropped) gone.push_back({{"m", d.m}, {"tau_s", d.tau_s}, {"why", d.why}});
  json points = json::array();
  for (const auto& p : pts)
    points.push_back({{"tau_s", p.tau_s},
                      {"m", p.m},
                      {"dev", p.dev},
                      {"ci_lo", or_null(p.ci_lo)},
                      {"ci_hi", or_null(p.ci_hi)},
                      {"edf", or_null(p.edf)},
                      {"n", p.n},
                      {"alpha", or_null(p.alpha)}});
  return json{{"kind", o.kind},
              {"input", o.in.input},
              {"file", o.in.file},
              {"column", o.in.column},
              {"units", unit_name(o.in)},
              {"tau0_s", tau0_s},
              {"samples", samples},
              {"ci", level ? json(*level) : json(nullptr)},
              {"points", std::move(points)},
              {"dropped", std::move(gone)}};
}

}  // namespace

double deg_per_unit(const series_input& in) {
  if (in.units == "rad/s" || in.units == "rad") return 180.0 / std::numbers::pi;
  if (in.units == "deg/h") return 1.0 / 3600.0;
  return 1.0;
}

std::string unit_name(const series_input& in) {
  // The defaults read as the input's kind: deg/s for a rate, deg for an angle.
  if (in.input == "angle") return in.units == "rad" || in.units == "rad/s" ? "rad" : "deg";
  return in.units == "deg" ? "deg/s" : in.units == "rad" ? "rad/s" : in.units;
}

result<analysis_input> load_series(const series_input& in) {
  if (in.input == "angle" && in.units == "deg/h")
    return usage_error("--units deg/h is a rate unit; angle input is deg or rad");
  io::series_options so;
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
  so.gaps = in.gaps == "split" ? io::gap_policy::split : io::gap_policy::error;
  auto s = is_rig_recording(in.file) ? read_rig_series(in.file, in.column)
                                     : io::read_series(in.file, so);
  if (!s) return s.err();
  for (const auto& n : s->notes()) note(fmt::format("{}: {}", in.file, n));
  // An uncompensated flip recording's rate switches with the angle: its Allan curve would show
  // the flipping (a square wave), not the sensor (issue 13 item 12).
  if (!s->angle_deg().empty() && !in.ignore_flip) {
    const auto flip = method::detect_flip_modulation(s->values(), s->angle_deg());
    if (flip.modulated)
      return input_error(
          {in.file},
          fmt::format("column '{}' switches with angle_deg (mean {:.6g} at 0 deg, {:.6g} at 180 "
                      "deg): this is an uncompensated flip recording, whose Allan curve shows the "
                      "flipping, not the sensor. Compensate it first (gyroflip compensate {} "
                      "--calibration CAL.json -o OUT.csv, then analyse OUT.csv), or analyse one "
                      "position, or give --ignore-flip to analyse it as it is",
                      printable(in.column, 60), flip.mean_0, flip.mean_180,
                      printable(in.file, 200)));
  }
  const auto kind = in.input == "angle" ? analysis::input_kind::angle : analysis::input_kind::rate;
  progress bar("reading " + in.file, 1000);
  auto phase = analysis::phase_source::make(s->samples(), kind, s->tau0_s(), per_mille(bar));
  bar.finish();
  // The sample rate was checked when reading, so what fails here is the data: name the file.
  if (!phase)
    return about_parameter(input_error({in.file}, phase.err().message), phase.err().parameter);
  // series keeps its samples on the heap: the source's reference survives the move.
  return analysis_input{std::move(*s), std::move(*phase)};
}

int run_adev(const adev_options& o) {
  const auto kind = analysis::parse_dev_kind(o.kind);
  if (!kind)
    return report(
        usage_error("--kind must be one of adev, oadev, mdev, tdev, hdev, ohdev, totdev"));
  const auto taus = analysis::parse_tau_spec(o.taus);
  if (!taus) return report(taus.err());
  // The validator (cli.cpp) let through only "none" or a number in (0, 1).
  const std::optional<double> level =
      o.ci == "none" ? std::nullopt : std::optional<double>(std::stod(o.ci));
  if (auto s = io::check_outputs(std::array{o.in.file}, std::array{o.output}); !s)
    return report(s.err());
  if (o.json)
    if (auto s = check_name_for_json(o.in.file); !s) return report(s.err());
  auto in = load_series(o.in);
  if (!in) return report(in.err());
  progress bar(fmt::format("{} of {}", o.kind, o.in.file), 1000);
  auto pts = analysis::deviation(*kind, in->phase, *taus, per_mille(bar));
  bar.finish();
  if (!pts) return report(pts.err());
  if (std::all_of(pts->begin(), pts->end(), [](const auto& p) { return p.dev == 0.0; }))
    warn(
        fmt::format("{}: every deviation is 0: the series is constant (a stuck sensor, a wrong "
                    "column?)",
                    o.in.file));
  // Factors asked for by name but without a single term: say which and why (not silently).
  const auto dropped =
      analysis::dropped_factors(*taus, *pts, *kind, in->phase.size(), in->phase.tau0_s());
  for (const auto& d : dropped)
    warn(fmt::format("{}: averaging factor {} dropped: {}", o.in.file, d.m, d.why));
  if (level) {
    progress ci_bar("noise identification", 1000);
    analysis::add_confidence(*pts, *kind, in->phase, *level, per_mille(ci_bar));
    ci_bar.finish();
  }
  // Everything is formatted and checked before anything is written (finite_output.hpp).
  const std::string csv = csv_text(*pts, level.has_value());
  if (auto s = check_finite(csv, o.output.empty() ? "<stdout>" : o.output); !s)
    return report(s.err());
  std::string json_line;
  if (o.json) {
    auto t = finite_dump(
        json_of(o, in->phase.tau0_s(), in->series.samples().size(), *pts, dropped, level),
        "<stdout>");
    if (!t) return report(t.err());
    json_line = *t + "\n";
  }
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, csv); !s) return report(s.err());
  if (o.json) {
    fmt::print("{}", json_line);
  } else if (o.output.empty()) {
    fmt::print("{}", csv);
  }
  return 0;
}

}  // namespace gyroflip::app
