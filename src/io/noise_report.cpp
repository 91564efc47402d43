/// \file
/// \brief The noise report's JSON object (noise_report.hpp).
#include "gyroflip/io/noise_report.hpp"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "gyroflip/core/units.hpp"
#include "gyroflip/io/schema.hpp"

namespace gyroflip::io {

namespace {

using nlohmann::json;

// Puts `key` (value in base units times `to_unit`) and, when resolved, key_lo/key_hi; an
// unresolved term is null with key_upper (its upper limit at the same level).
void put(json& j, const std::string& key, const analysis::noise_term& t, double to_unit) {
  if (t.resolved) {
    j[key] = t.value * to_unit;
    j[key + "_lo"] = t.lo * to_unit;
    j[key + "_hi"] = t.hi * to_unit;
    // The readings over the alternative fit ranges, which [lo, hi] includes.
    j[key + "_range_lo"] = t.range_lo * to_unit;
    j[key + "_range_hi"] = t.range_hi * to_unit;
  } else {
    j[key] = nullptr;
    j[key + "_upper"] = t.hi * to_unit;
  }
}

}  // namespace

json noise_json(const noise_report& r) {
  const auto& c = r.result;
  const auto& f = c.terms;
  // The fit ran in the samples' unit; every output is in deg (and rad) units.
  const double k = r.deg_per_unit;
  const double k_rad = k * units::rad_per_deg;
  json j = schema_object("noise", 1);
  j.update(json{{"file", r.file},
                {"column", r.column},
                {"input", r.input},
                {"units", r.units},
                {"tau0_s", r.tau0_s},
                {"samples", r.samples},
                {"bias_floor_tau_s", f.bias_floor_tau_s},
                {"bias_floor_dps", f.bias_floor_dev * k},
                {"bias_floor_deg_h", f.bias_floor_dev * k * units::dph_per_dps},
                {"chi2_per_dof", f.chi2_per_dof},
                {"bias_floor_reached", f.bias_floor_reached},
                {"abba_cycles", r.series.shaped()},
                {"ci", f.level},
                {"notes", f.notes}});
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
  for (const auto& p : c.oadev)
    points.push_back({{"tau_s", p.tau_s},
                      {"dev", p.dev},
                      {"ci_lo", p.ci_lo},
                      {"ci_hi", p.ci_hi},
                      {"edf", p.edf}});
  j["oadev"] = std::move(points);
  // Beyond Stable32's m <= (N-1)/4, with long_taus: shown, never fitted.
  json long_points = json::array();
  for (const auto& p : c.long_oadev)
    long_points.push_back({{"tau_s", p.tau_s},
                           {"dev", p.dev},
                           {"ci_lo", p.ci_lo},
                           {"ci_hi", p.ci_hi},
                           {"edf", p.edf}});
  j["long_oadev"] = std::move(long_points);
  j["fit_tau_lo_s"] = f.fit_tau_lo_s;
  j["fit_tau_hi_s"] = f.fit_tau_hi_s;
  j["fit_ranges"] = f.fit_ranges;
  j["fit_min_tau_s"] = f.fit_min_tau_s;
  j["short_taus_left_out"] = c.shaping.points == 0 ? json(nullptr)
                                                   : json{{"points", c.shaping.points},
                                                          {"cause", c.shaping.cause},
                                                          {"to_tau_s", c.shaping.kink_tau_s},
                                                          {"z", c.shaping.kink_z}};
  // The datasheet's ARW reading, ADEV(1 s) sqrt(1 s), beside the fitted N.
  const bool has_1s = std::isfinite(c.adev_1s);
  j["adev_1s_tau_s"] = has_1s ? json(c.adev_1s_tau_s) : json(nullptr);
  j["adev_1s_dps"] = has_1s ? json(c.adev_1s * k) : json(nullptr);
  j["adev_1s_deg_rth"] =
      has_1s ? json(c.adev_1s * std::sqrt(c.adev_1s_tau_s) * k * units::deg_rth_per_deg_rts)
             : json(nullptr);
  j["adev_1s_less_terms_deg_rth"] =
      has_1s ? json(c.adev_1s_arw * k * units::deg_rth_per_deg_rts) : json(nullptr);
  // N is the two-sided density (S(f) = N^2, ADEV = N/sqrt(tau)); a one-sided density is sqrt(2) N.
  j["arw_density"] = "two-sided";
  if (f.arw.resolved) j["arw_one_sided_dps_rthz"] = std::numbers::sqrt2 * f.arw.value * k;
  // B in three conventions: the IEEE 952 fit (the headline), the first floor / 0.6643, and the
  // raw floor that datasheets quote as "in-run bias stability".
  j["bias_instability_convention"] = "IEEE 952 fit";
  j["bias_floor_over_0664_deg_h"] = f.bias_floor_dev * k * units::dph_per_dps / 0.6643;
  json misfit = json::array();
  for (const auto& m : f.misfit)
    misfit.push_back({{"tau_s", m.tau_s},
                      {"dev", m.dev},
                      {"model_dev", m.model_dev},
                      {"ci_lo", m.ci_lo},
                      {"ci_hi", m.ci_hi}});
  j["misfit"] = std::move(misfit);
  const auto& ro = c.readoffs;
  const auto opt = [](const std::optional<double>& v, double to) {
    return v ? json(*v * to) : json(nullptr);
  };
  j["readoffs"] = {{"arw_dps_rthz", opt(ro.arw, k)},
                   {"arw_deg_rth", opt(ro.arw, k * units::deg_rth_per_deg_rts)},
                   {"arw_tau_s", ro.arw ? json(ro.arw_from_tau_s) : json(nullptr)},
                   {"rrw_deg_h_rth", opt(ro.rrw, k * units::dph_rth_per_dps_rts)},
                   {"rrw_rad_s2_rthz", opt(ro.rrw, k_rad)},
                   {"rrw_tau_s", ro.rrw ? json(ro.rrw_from_tau_s) : json(nullptr)},
                   {"bias_instability_deg_h", ro.bias_instability * k * units::dph_per_dps},
                   {"floor_tau_s", ro.floor_tau_s},
                   {"floor_deg_h", ro.floor_dev * k * units::dph_per_dps},
                   {"floor_is_minimum", ro.floor_is_minimum}};
  return j;
}

}  // namespace gyroflip::io
