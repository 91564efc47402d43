/// \file
/// \brief `gyroflip noise`: IEEE 952 noise terms (Q, N, B, K, R) with intervals and units.
#include <array>
#include <cmath>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cmd_adev.hpp"
#include "finite_output.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

using nlohmann::json;

// Puts `key` (value in base units times `to_unit`) and, when resolved, key_lo/key_hi; an
// unresolved term is null with key_upper (its upper limit at the same level).
void put(json& j, const std::string& key, const analysis::noise_term& t, double to_unit) {
  if (t.resolved) {
    j[key] = t.value * to_unit;
    j[key + "_lo"] = t.lo * to_unit;
    j[key + "_hi"] = t.hi * to_unit;
  } else {
    j[key] = nullptr;
    j[key + "_upper"] = t.hi * to_unit;
  }
}

std::string show(const analysis::noise_term& t, double to_unit) {
  if (!t.resolved) return fmt::format("not resolved (< {:.4g})", t.hi * to_unit);
  return fmt::format("{:.4g}  [{:.4g}, {:.4g}]", t.value * to_unit, t.lo * to_unit, t.hi * to_unit);
}

// The term in another unit, for the text's "= ..." (the value, or its upper limit).
std::string also(const analysis::noise_term& t, double to_unit) {
  return fmt::format("{}{:.4g}", t.resolved ? "" : "< ", (t.resolved ? t.value : t.hi) * to_unit);
}

// Kalibr's IMU noise file (kalibr/wiki "IMU Noise Model"): the continuous-time gyroscope noise
// density (rad/s/sqrt(Hz), our N) and bias random walk (rad/s^2/sqrt(Hz), our K), as measured:
// no inflation factor is applied (docs/ANALYSIS.md says what the field's x10 habit means).
std::string kalibr_yaml(const std::string& file, const analysis::noise_terms& f, double to_rad,
                        double rate_hz) {
  const auto value = [](const analysis::noise_term& t) { return t.resolved ? t.value : t.hi; };
  const auto remark = [](const analysis::noise_term& t) {
    return t.resolved ? std::string() : std::string("  # an upper limit: not resolved by the data");
  };
  return fmt::format(
      "# IMU noise model for Kalibr, measured by gyroflip noise from {}\n"
      "# continuous-time densities, not inflated; accelerometer fields are not measured here\n"
      "gyroscope_noise_density: {:.6e}  # rad/s/sqrt(Hz) (ARW N){}\n"
      "gyroscope_random_walk: {:.6e}  # rad/s^2/sqrt(Hz) (RRW K){}\n"
      "update_rate: {:.9g}  # Hz\n",
      printable(file, 200), value(f.arw) * to_rad, remark(f.arw), value(f.rrw) * to_rad,
      remark(f.rrw), rate_hz);
}

}  // namespace

int run_noise(const noise_options& o) {
  if (o.json)
    if (auto s = check_name_for_json(o.in.file); !s) return report(s.err());
  if (auto s = io::check_outputs(std::array{o.in.file}, std::array{o.kalibr}); !s)
    return report(s.err());
  auto in = load_series(o.in);
  if (!in) return report(in.err());
  progress bar("noise of " + o.in.file, 1000);
  auto pts = analysis::deviation(analysis::dev_kind::oadev, in->phase, {}, per_mille(bar));
  bar.finish();
  if (!pts) return report(pts.err());
  // The OADEV points in the output carry bounds at the same level as the terms.
  analysis::add_confidence(*pts, analysis::dev_kind::oadev, in->phase, o.ci);
  const double tau0_s = in->phase.tau0_s();
  const std::size_t samples = in->series.samples().size();
  // The rate column of `gyroflip compensate` with the abba pairing: correlated cycles.
  analysis::noise_series series;
  for (const auto& m : in->series.metadata())
    if (m.key == "pairing" && m.value == "abba" && o.in.input == "rate")
      series.abba_cycle_s = tau0_s;
  const auto fit = analysis::fit_noise_terms(*pts, o.ci, series);
  // Too few points for the fit is a property of this input (too short a series): name it.
  if (!fit) return report(input_error({o.in.file}, fit.err().message));
  const auto& f = *fit;
  // The fit ran in the samples' unit; every output is in deg (and rad) units.
  const double k = deg_per_unit(o.in);
  const double k_rad = k * units::rad_per_deg;
  const std::string unit = unit_name(o.in);
  if (!o.kalibr.empty()) {
    if (!f.arw.resolved || !f.rrw.resolved)
      warn(fmt::format("{}: {} not resolved: the Kalibr file holds its upper limit", o.kalibr,
                       !f.arw.resolved ? "ARW" : "RRW"));
    if (auto s =
            io::write_file_atomically(o.kalibr, kalibr_yaml(o.in.file, f, k_rad, 1.0 / tau0_s));
        !s)
      return report(s.err());
  }
  if (o.json) {
    json j = {{"file", o.in.file},
              {"column", o.in.column},
              {"input", o.in.input},
              {"units", unit},
              {"tau0_s", tau0_s},
              {"samples", samples},
              {"bias_floor_tau_s", f.bias_floor_tau_s},
              {"bias_floor_dps", f.bias_floor_dev * k},
              {"bias_floor_deg_h", f.bias_floor_dev * k * units::dph_per_dps},
              {"chi2_per_dof", f.chi2_per_dof},
              {"bias_floor_reached", f.bias_floor_reached},
              {"abba_cycles", series.abba_cycle_s > 0.0},
              {"ci", f.level},
              {"notes", f.notes}};
    put(j, "arw_dps_rthz", f.arw, k);
    put(j, "arw_deg_rth", f.arw, k * units::deg_rth_per_deg_rts);
    put(j, "arw_rad_s_rthz", f.arw, k_rad);
    put(j, "bias_instability_dps", f.bias_instability, k);
    put(j, "bias_instability_deg_h", f.bias_instability, k * units::dph_per_dps);
    put(j, "bias_instability_rad_s", f.bias_instability, k_rad);
    put(j, "rrw_deg_h_rth", f.rrw, k * units::dph_rth_per_dps_rts);
    put(j, "rrw_rad_s2_rthz", f.rrw, k_rad);
    put(j, "quantization_deg", f.quantization, k);
    put(j, "quantization_rad", f.quantization, k_rad);
    put(j, "rate_ramp_deg_h2", f.rate_ramp, k * units::dph2_per_dps2);
    // The OADEV points stay in the samples' unit (`units`), as `adev` writes them.
    json points = json::array();
    for (const auto& p : *pts)
      points.push_back({{"tau_s", p.tau_s},
                        {"dev", p.dev},
                        {"ci_lo", p.ci_lo},
                        {"ci_hi", p.ci_hi},
                        {"edf", p.edf}});
    j["oadev"] = std::move(points);
    json misfit = json::array();
    for (const auto& m : f.misfit)
      misfit.push_back({{"tau_s", m.tau_s},
                        {"dev", m.dev},
                        {"model_dev", m.model_dev},
                        {"ci_lo", m.ci_lo},
                        {"ci_hi", m.ci_hi}});
    j["misfit"] = std::move(misfit);
    if (auto s = print_json(j); !s) return report(s.err());
    return 0;
  }
  std::string text;
  const auto out = std::back_inserter(text);
  fmt::format_to(out,
                 "{}: column {}, {} samples at {:g} Hz in {}, IEEE 952 terms from OADEV ({:g} % "
                 "intervals)\n",
                 o.in.file, printable(o.in.column, 60), samples, 1.0 / tau0_s, unit,
                 100.0 * f.level);
  fmt::format_to(
      out, "  angle random walk N    {} deg/sqrt(h)   = {} deg/s/sqrt(Hz) = {} rad/s/sqrt(Hz)\n",
      show(f.arw, k * units::deg_rth_per_deg_rts), also(f.arw, k), also(f.arw, k_rad));
  fmt::format_to(
      out, "  bias instability  B    {} deg/h   = {} rad/s   ({} {:.4g} deg/h at tau {:g} s)\n",
      show(f.bias_instability, k * units::dph_per_dps), also(f.bias_instability, k_rad),
      f.bias_floor_reached ? "OADEV floor" : "no floor: OADEV still falls, last",
      f.bias_floor_dev * k * units::dph_per_dps, f.bias_floor_tau_s);
  fmt::format_to(out, "  rate random walk  K    {} deg/h/sqrt(h)   = {} rad/s^2/sqrt(Hz)\n",
                 show(f.rrw, k * units::dph_rth_per_dps_rts), also(f.rrw, k_rad));
  fmt::format_to(out, "  quantization      Q    {} deg\n", show(f.quantization, k));
  fmt::format_to(out, "  rate ramp         R    {} deg/h^2\n",
                 show(f.rate_ramp, k * units::dph2_per_dps2));
  fmt::format_to(out, "  fit chi2/dof {:.3g}\n", f.chi2_per_dof);
  for (const auto& n : f.notes)
    if (n.find("not resolved by the data") == std::string::npos)
      fmt::format_to(out, "  note: {}\n", n);
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
