/// \file
/// \brief `gyroflip noise`: IEEE 952 noise terms (Q, N, B, K, R) with intervals and units.
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

}  // namespace

int run_noise(const noise_options& o) {
  if (o.json)
    if (auto s = check_name_for_json(o.in.file); !s) return report(s.err());
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
  if (o.json) {
    json j = {{"file", o.in.file},
              {"input", o.in.input},
              {"tau0_s", tau0_s},
              {"samples", samples},
              {"bias_floor_tau_s", f.bias_floor_tau_s},
              {"bias_floor_dps", f.bias_floor_dev},
              {"chi2_per_dof", f.chi2_per_dof},
              {"bias_floor_reached", f.bias_floor_reached},
              {"abba_cycles", series.abba_cycle_s > 0.0},
              {"ci", f.level},
              {"notes", f.notes}};
    put(j, "arw_dps_rthz", f.arw, 1.0);
    put(j, "arw_deg_rth", f.arw, units::deg_rth_per_deg_rts);
    put(j, "bias_instability_dps", f.bias_instability, 1.0);
    put(j, "bias_instability_deg_h", f.bias_instability, units::dph_per_dps);
    put(j, "rrw_deg_h_rth", f.rrw, units::dph_rth_per_dps_rts);
    put(j, "quantization_deg", f.quantization, 1.0);
    put(j, "rate_ramp_deg_h2", f.rate_ramp, units::dph2_per_dps2);
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
  fmt::format_to(out, "{}: {} samples at {:g} Hz, IEEE 952 terms from OADEV ({:g} % intervals)\n",
                 o.in.file, samples, 1.0 / tau0_s, 100.0 * f.level);
  fmt::format_to(out, "  angle random walk N    {} deg/sqrt(h)   = {} deg/s/sqrt(Hz)\n",
                 show(f.arw, units::deg_rth_per_deg_rts), show(f.arw, 1.0));
  fmt::format_to(out, "  bias instability  B    {} deg/h   ({} {:.4g} deg/s at tau {:g} s)\n",
                 show(f.bias_instability, units::dph_per_dps),
                 f.bias_floor_reached ? "OADEV floor" : "no floor: OADEV still falls, last",
                 f.bias_floor_dev, f.bias_floor_tau_s);
  fmt::format_to(out, "  rate random walk  K    {} deg/h/sqrt(h)\n",
                 show(f.rrw, units::dph_rth_per_dps_rts));
  fmt::format_to(out, "  quantization      Q    {} deg\n", show(f.quantization, 1.0));
  fmt::format_to(out, "  rate ramp         R    {} deg/h^2\n",
                 show(f.rate_ramp, units::dph2_per_dps2));
  fmt::format_to(out, "  fit chi2/dof {:.3g}\n", f.chi2_per_dof);
  for (const auto& n : f.notes)
    if (n.find("not resolved by the data") == std::string::npos)
      fmt::format_to(out, "  note: {}\n", n);
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
