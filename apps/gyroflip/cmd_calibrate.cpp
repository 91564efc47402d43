/// \file
/// \brief `gyroflip calibrate`: dN from stationary recordings (paper eqns 8-11), its Earth and
/// g terms, and a dN(T) model when recordings at several temperatures are given.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/recording.hpp"
#include "progress_bar.hpp"
#include "rig_input.hpp"

namespace gyroflip::app {
namespace {

result<std::optional<io::calibration_geometry>> geometry_of(const calibrate_options& o) {
  const bool has_lat = !std::isnan(o.lat_deg);
  if (has_lat != !o.axis.empty())
    return usage_error(
        "--latitude and --axis go together: give both to split dN into Earth and g terms");
  if (!has_lat) return std::optional<io::calibration_geometry>{};
  if (auto s = earth::check_latitude(o.lat_deg); !s) return s.err();
  auto axis = earth::parse_axis(o.axis);
  if (!axis) return axis.err();
  return std::optional<io::calibration_geometry>{io::calibration_geometry{o.lat_deg, *axis}};
}

// With several files there is always a model (io::fit_runs_model); --degree needs several files
// with temperatures.
result<std::optional<method::delta_n_model>> fit_model(
    const calibrate_options& o, const std::vector<io::calibration_entry>& files) {
  if (o.degree_given) {
    if (files.size() < 2) return usage_error("--degree needs calibrations from several files");
    for (const auto& f : files)
      if (std::isnan(f.cal.temp_c))
        return input_error({f.file},
                           "no temp_c column; a dN(T) model (--degree) needs temperatures");
  }
  return io::fit_runs_model(files, o.degree_given ? std::optional(o.degree) : std::nullopt);
}

void print_entry(std::string& out, const io::calibration_entry& e,
                 const std::optional<io::calibration_geometry>& g) {
  const auto& c = e.cal;
  fmt::format_to(std::back_inserter(out), "{}: {} cycles over {:.0f} s", e.file, c.cycles,
                 c.duration_s);
  if (!std::isnan(c.temp_c)) fmt::format_to(std::back_inserter(out), ", {:.2f} degC", c.temp_c);
  fmt::format_to(std::back_inserter(out),
                 "\n  dN = {:.6e} deg/s   std {:.3e}   stderr {:.3e} (naive) {:.3e} (correlated)\n",
                 c.delta_n_dps, c.std_dps, c.stderr_dps, c.stderr_correlated_dps);
  fmt::format_to(std::back_inserter(out), "  bias (half-sum) mean {:.6e} deg/s\n", c.bias_mean_dps);
  if (g) {
    const auto s = method::split_delta_n(c.delta_n_dps, g->lat_deg, g->axis);
    fmt::format_to(std::back_inserter(out), "  Earth term {:.6e} deg/s   g term {:.6e} deg/s\n",
                   s.earth_rate_dps, s.g_term_dps);
  }
}

std::string summary_text(const io::calibration_record& rec) {
  std::string out;
  fmt::format_to(std::back_inserter(out), "pairing: {}\n", method::to_string(rec.pairing));
  for (const auto& f : rec.files) print_entry(out, f, rec.geometry);
  if (rec.files.size() > 1) print_entry(out, {"all files", rec.pooled}, rec.geometry);
  if (rec.model) {
    const auto& m = *rec.model;
    if (m.degree() == 0) {
      fmt::format_to(std::back_inserter(out),
                     "dN over {} runs (weighted mean) = {:.6e} +- {:.3e} deg/s, chi2/dof {:.3g}\n",
                     rec.files.size(), m.coeffs_dps[0], m.stderr_at(0.0), m.chi2_per_dof);
    } else {
      fmt::format_to(
          std::back_inserter(out),
          "dN(T) = sum c_k (T - {:.2f})^k, c = [{:.6e}], fitted over {:.1f}..{:.1f} degC, chi2/dof "
          "{:.3g}\n",
          m.t_ref_c, fmt::join(m.coeffs_dps, ", "), m.temp_min_c, m.temp_max_c, m.chi2_per_dof);
    }
  }
  return out;
}

}  // namespace

int run_calibrate(const calibrate_options& o) {
  const auto pairing = method::parse_pairing(o.pairing);
  if (!pairing) return report(usage_error("--pairing must be abba or simple"));
  auto geometry = geometry_of(o);
  if (!geometry) return report(geometry.err());
  if (auto s = io::check_outputs(o.files, std::array{o.output}); !s) return report(s.err());
  if (auto s = io::check_distinct_inputs(o.files); !s) return report(s.err());
  // The calibration record names its files, and it is JSON (docs/FORMATS.md).
  for (const auto& file : o.files)
    if (auto s = check_name_for_json(file); !s) return report(s.err());
  io::calibration_record rec;
  rec.pairing = *pairing;
  rec.geometry = *geometry;
  std::vector<method::cycle> all;
  for (const auto& file : o.files) {
    progress bar("reading " + file, 1000);
    auto rc = read_recording_cycles(file, *pairing, per_mille(bar), o.angle_tolerance_deg);
    bar.finish();
    if (!rc) return report(rc.err());
    for (const auto& w : rc->warnings) warn(w);
    auto cal = method::calibrate(rc->cycles);
    if (!cal) return report(input_error({file}, cal.err().message));
    rec.files.push_back({file, *cal});
    // One sensor per calibration: its identity and rig come from the recordings' metadata.
    const auto sr = io::sensor_of(rc->metadata);
    if (!rec.sensor) {
      rec.sensor = sr;
    } else if (sr.sensor != rec.sensor->sensor) {
      return report(input_error(
          {file}, fmt::format("recorded with sensor '{}', but {} with '{}': calibrate one sensor "
                              "at a time",
                              printable(sr.sensor, 80), printable(o.files.front(), 200),
                              printable(rec.sensor->sensor, 80))));
    } else {
      for (const auto& d : io::rig_differences(*rec.sensor, sr))
        warn(fmt::format("{}: rig setting differs from {}: {}", file, o.files.front(), d));
    }
    all.insert(all.end(), rc->cycles.begin(), rc->cycles.end());
  }
  if (!rec.sensor->known())
    warn(
        "the recordings name no sensor (no `# sensor_name:` or `# serial:` line): compensate "
        "cannot check that this calibration is applied to the same sensor");
  auto pooled = method::calibrate(all);
  if (!pooled) return report(pooled.err());
  rec.pooled = *pooled;
  rec.pooled.stderr_correlated_dps = io::pooled_correlated_stderr(rec.files);
  auto model = fit_model(o, rec.files);
  if (!model) return report(model.err());
  rec.model = *model;

  // Formatted and checked (every number finite) before anything is written.
  const auto text = io::to_json(rec, GYROFLIP_VERSION);
  if (!text) return report(text.err());
  const std::string summary = o.json ? *text + "\n" : summary_text(rec);
  if (auto s = check_finite(summary, "<stdout>"); !s) return report(s.err());
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, *text + "\n"); !s) return report(s.err());
  fmt::print("{}", summary);
  return 0;
}

}  // namespace gyroflip::app
