/// \file
/// \brief `gyroflip compensate`: paper eqn 12 per cycle, w_in = r - dN(T).
#include <array>
#include <cmath>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/method/delta_n_model.hpp"

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/io/recording_writer.hpp"
#include "gyroflip/method/compensation.hpp"
#include "progress_bar.hpp"
#include "rig_input.hpp"

namespace gyroflip::app {
namespace {

struct delta_n_source {
  method::delta_n_model model;
  std::optional<method::pairing> pairing;        // the pairing the calibration used
  std::optional<io::calibration_record> record;  // the calibration file, when one was given
};

// A single-temperature dN applied more than this far from its calibration temperature: warn.
// The paper's HZ1-90-100A moved its dN by 7e-4 deg/s (23 %) between 20 and 4 degC (FACTS §3).
constexpr double far_from_calibration_c = 5.0;

// The calibration must belong to the recording's sensor (refused otherwise), on the same rig
// (warned), at about its temperature (warned) - docs/cli.md, "compensate".
status check_calibration_fits(const compensate_options& o, const io::calibration_record& cal,
                              const io::recording_cycles& rc) {
  const auto here = io::sensor_of(rc.metadata);
  if (!cal.sensor) {
    warn(
        fmt::format("{}: the calibration names no sensor (a file from before gyroflip recorded "
                    "it): nothing checks that it belongs to this sensor",
                    o.calibration));
  } else if (cal.sensor->known() && here.known() && cal.sensor->sensor != here.sensor) {
    return input_error({o.file},
                       fmt::format("recorded with sensor '{}', but {} calibrates '{}': "
                                   "a calibration applies to its own sensor only",
                                   printable(here.sensor, 80), printable(o.calibration, 200),
                                   printable(cal.sensor->sensor, 80)));
  } else {
    if (!cal.sensor->known() || !here.known())
      warn(
          fmt::format("{}: sensor unknown on one side ({} vs {}): nothing checks that the "
                      "calibration belongs to this sensor",
                      o.file, printable(here.sensor, 80), printable(cal.sensor->sensor, 80)));
    for (const auto& d : io::rig_differences(*cal.sensor, here))
      warn(fmt::format("{}: rig setting differs from the calibration's: {}", o.file, d));
  }
  if (cal.model && cal.model->degree() > 0) return ok();  // dN(T) covers temperature
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& c : rc.cycles)
    if (std::isfinite(c.temp_c)) {
      sum += c.temp_c;
      ++n;
    }
  if (n > 0 && std::isfinite(cal.pooled.temp_c) &&
      std::abs(sum / static_cast<double>(n) - cal.pooled.temp_c) > far_from_calibration_c)
    warn(
        fmt::format("{}: mean temperature {:.1f} degC, but the calibration was made at {:.1f} "
                    "degC: dN depends on temperature (calibrate at several temperatures for a "
                    "dN(T) model)",
                    o.file, sum / static_cast<double>(n), cal.pooled.temp_c));
  return ok();
}

result<delta_n_source> load_delta_n(const compensate_options& o) {
  if (o.calibration.empty()) {
    if (auto s = method::check_delta_n(o.delta_n_dps); !s) return s.err();
    return delta_n_source{method::constant_model(o.delta_n_dps), std::nullopt, std::nullopt};
  }
  auto rec = io::read_calibration_file(o.calibration);
  if (!rec) return rec.err();
  return delta_n_source{io::delta_n_model_of(*rec), rec->pairing, *rec};
}

std::string format_value(double v) {
  return std::isnan(v) ? std::string() : fmt::format("{}", v);
}

status write_csv(const std::string& path, const std::vector<method::compensated_cycle>& out,
                 const compensate_options& o, method::pairing p) {
  auto f = io::atomic_file::create(path);
  if (!f) return f.err();
  // The header first (scripts read line 1), then what made the series as metadata: `gyroflip
  // noise` reads `pairing` to model the abba pairing's correlated cycles.
  std::string head = "time_s,rate_dps,bias_dps,temp_c,delta_n_dps\n";
  io::append_metadata(head, std::vector<io::csv_metadata>{
                                {"gyroflip compensate", "one row per cycle (paper eqn 12)"},
                                {"version", GYROFLIP_VERSION},
                                {"source", o.file},
                                {"pairing", std::string(method::to_string(p))},
                                {"delta_n", o.calibration.empty() ? fmt::format("{}", o.delta_n_dps)
                                                                  : o.calibration}});
  f->write(head);
  fmt::memory_buffer buf;
  for (const auto& c : out) {
    fmt::format_to(std::back_inserter(buf), "{},{},{},{},{}\n", c.time_s, c.rate_dps, c.bias_dps,
                   format_value(c.temp_c), c.delta_n_dps);
    if (buf.size() > (1u << 16)) {
      if (auto s = check_finite({buf.data(), buf.size()}, path); !s) return s;
      f->write({buf.data(), buf.size()});
      buf.clear();
    }
  }
  if (auto s = check_finite({buf.data(), buf.size()}, path); !s) return s;
  f->write({buf.data(), buf.size()});
  return f->commit();
}

// The summary's layout: bumped when a key changes meaning or goes (new keys do not bump it).
constexpr int summary_schema_version = 1;

nlohmann::json summary_json(const method::compensation_summary& s, const compensate_options& o,
                            method::pairing p, const method::delta_n_model& model) {
  using nlohmann::json;
  // The dN that was subtracted: a constant, or the dN(T) polynomial about t_ref_c.
  json dn = {{"source", o.calibration.empty() ? std::string("--delta-n") : o.calibration},
             {"degree", model.degree()},
             {"coeffs_dps", model.coeffs_dps},
             {"t_ref_c", model.degree() > 0 ? json(model.t_ref_c) : json(nullptr)}};
  if (model.degree() == 0) dn["delta_n_dps"] = model.coeffs_dps.front();
  return json{{"schema_version", summary_schema_version},
              {"file", o.file},
              {"delta_n", std::move(dn)},
              {"pairing", method::to_string(p)},
              {"cycles", s.cycles},
              {"duration_s", s.duration_s},
              {"mean_dps", s.mean_dps},
              {"std_dps", s.std_dps},
              {"stderr_dps", s.stderr_dps},
              {"stderr_correlated_dps", s.stderr_correlated_dps},
              {"drift_dps", s.drift_dps ? json(*s.drift_dps) : json(nullptr)},
              {"drift_window_s", s.drift_window_s}};
}

}  // namespace

int run_compensate(const compensate_options& o) {
  if (auto s = io::check_outputs(std::array{o.file, o.calibration}, std::array{o.output}); !s)
    return report(s.err());
  if (o.json)
    if (auto s = check_name_for_json(o.file); !s) return report(s.err());
  auto dn = load_delta_n(o);
  if (!dn) return report(dn.err());
  std::optional<method::pairing> chosen =
      o.pairing.empty() ? dn->pairing : method::parse_pairing(o.pairing);
  if (!o.pairing.empty() && !chosen) return report(usage_error("--pairing must be abba or simple"));
  const method::pairing p = chosen.value_or(method::pairing::abba);
  if (dn->pairing && *dn->pairing != p)
    fmt::print(stderr, "gyroflip: warning: calibration used pairing '{}', compensating with '{}'\n",
               method::to_string(*dn->pairing), method::to_string(p));
  if (auto s = method::check_drift_window(o.drift_window_s); !s) return report(s.err());

  progress bar("reading " + o.file, 1000);
  auto rc = read_recording_cycles(o.file, p, per_mille(bar), o.angle_tolerance_deg);
  bar.finish();
  if (!rc) return report(rc.err());
  for (const auto& w : rc->warnings) warn(w);
  if (dn->record)
    if (auto s = check_calibration_fits(o, *dn->record, *rc); !s) return report(s.err());
  const auto& model = dn->model;
  if (model.degree() > 0 && !rc->has_temp)
    return report(input_error(
        {o.file}, "no temp_c column, but the calibration's dN(T) model needs temperatures"));

  std::vector<method::compensated_cycle> out;
  out.reserve(rc->cycles.size());
  bool extrapolated = false;
  for (const auto& c : rc->cycles) {
    out.push_back(method::compensate(c, model));
    if (model.degree() > 0 &&
        (c.temp_c < model.temp_min_c - 1.0 || c.temp_c > model.temp_max_c + 1.0))
      extrapolated = true;
  }
  if (extrapolated)
    fmt::print(
        stderr,
        "gyroflip: warning: {}: some cycles lie outside the dN(T) model's {:.1f}..{:.1f} degC\n",
        o.file, model.temp_min_c, model.temp_max_c);

  // Every number is checked before anything is written (finite_output.hpp): the rows, so that
  // stdout gets no partial table, and the summary.
  const auto summary = method::summarize(out, o.drift_window_s);
  if (auto s = io::check_finite(out, summary, o.output.empty() ? "<stdout>" : o.output); !s)
    return report(s.err());
  std::string summary_text;
  if (o.json) {
    auto t = finite_dump(summary_json(summary, o, p, model), "<stdout>");
    if (!t) return report(t.err());
    summary_text = *t + "\n";
  } else if (!o.output.empty()) {
    summary_text = fmt::format(
        "{}: {} cycles, mean {:.6e} deg/s, std {:.3e}, stderr {:.3e} (correlated), drift {} over "
        "{} s\n",
        o.file, summary.cycles, summary.mean_dps, summary.std_dps, summary.stderr_correlated_dps,
        summary.drift_dps ? fmt::format("{:.3e} deg/s", *summary.drift_dps) : std::string("n/a"),
        summary.drift_window_s);
    if (auto s = check_finite(summary_text, "<stdout>"); !s) return report(s.err());
  }
  if (!o.output.empty() || !o.json)
    if (auto s = write_csv(o.output.empty() ? "-" : o.output, out, o, p); !s)
      return report(s.err());
  fmt::print("{}", summary_text);
  return 0;
}

}  // namespace gyroflip::app
