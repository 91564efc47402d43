/// \file
/// \brief The noise report's JSON object (noise_report.hpp).
#include "gyroflip/io/noise_report.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/error.hpp"
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

namespace {

// The OADEV points as JSON (in the samples' unit, as `adev` writes them).
json points_json(const std::vector<analysis::deviation_point>& pts) {
  json a = json::array();
  for (const auto& p : pts)
    a.push_back({{"tau_s", p.tau_s},
                 {"dev", p.dev},
                 {"ci_lo", p.ci_lo},
                 {"ci_hi", p.ci_hi},
                 {"edf", p.edf}});
  return a;
}

const auto opt = [](const std::optional<double>& v, double to) {
  return v ? json(*v * to) : json(nullptr);
};

// A gyro's terms in degree and radian units (IEEE Std 952-1997 Annex C).
void put_gyro_terms(json& j, const noise_report& r) {
  const auto& c = r.result;
  const auto& f = c.terms;
  const double k = r.deg_per_unit;
  const double k_rad = k * units::rad_per_deg;
  j["bias_floor_dps"] = f.bias_floor_dev * k;
  j["bias_floor_deg_h"] = f.bias_floor_dev * k * units::dph_per_dps;
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
  // The datasheet's ARW reading, ADEV(1 s) sqrt(1 s), beside the fitted N.
  const bool has_1s = std::isfinite(c.adev_1s);
  j["adev_1s_dps"] = has_1s ? json(c.adev_1s * k) : json(nullptr);
  j["adev_1s_deg_rth"] =
      has_1s ? json(c.adev_1s * std::sqrt(c.adev_1s_tau_s) * k * units::deg_rth_per_deg_rts)
             : json(nullptr);
  j["adev_1s_less_terms_deg_rth"] =
      has_1s ? json(c.adev_1s_arw * k * units::deg_rth_per_deg_rts) : json(nullptr);
  // N is the two-sided density (S(f) = N^2, ADEV = N/sqrt(tau)); a one-sided density is sqrt(2) N.
  j["arw_density"] = "two-sided";
  if (f.arw.resolved) j["arw_one_sided_dps_rthz"] = std::numbers::sqrt2 * f.arw.value * k;
  j["bias_floor_over_0664_deg_h"] = f.bias_floor_dev * k * units::dph_per_dps / 0.6643;
  const auto& ro = c.readoffs;
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
}

// An accelerometer's terms (IEEE Std 1293-2018): velocity random walk N, bias instability B,
// acceleration random walk K, velocity quantization Q and the ramp R, in m/s^2 units, g-units
// (g_n = 9.80665 m/s^2) and per sqrt(h).
void put_accel_terms(json& j, const noise_report& r) {
  const auto& c = r.result;
  const auto& f = c.terms;
  const double k = r.mps2_per_unit;
  const double mg = k / units::standard_gravity_mps2 * 1e3;
  const double rth = units::deg_rth_per_deg_rts;  // sqrt(3600 s/h) = 60
  j["bias_floor_mps2"] = f.bias_floor_dev * k;
  j["bias_floor_mg"] = f.bias_floor_dev * mg;
  j["bias_floor_ug"] = f.bias_floor_dev * mg * 1e3;
  put(j, "vrw_mps2_rthz", f.arw, k);
  put(j, "vrw_mps_rth", f.arw, k * rth);
  put(j, "vrw_mg_rthz", f.arw, mg);
  put(j, "vrw_ug_rthz", f.arw, mg * 1e3);
  put(j, "bias_instability_mps2", f.bias_instability, k);
  put(j, "bias_instability_mg", f.bias_instability, mg);
  put(j, "bias_instability_ug", f.bias_instability, mg * 1e3);
  put(j, "acceleration_rw_mps3_rthz", f.rrw, k);
  put(j, "acceleration_rw_mps2_rth", f.rrw, k * rth);
  put(j, "acceleration_rw_mg_rth", f.rrw, mg * rth);
  put(j, "quantization_mps", f.quantization, k);
  put(j, "rate_ramp_mps3", f.rate_ramp, k);
  put(j, "rate_ramp_mg_h", f.rate_ramp, mg * units::s_per_h);
  const bool has_1s = std::isfinite(c.adev_1s);
  j["adev_1s_mps2"] = has_1s ? json(c.adev_1s * k) : json(nullptr);
  j["adev_1s_mps2_rthz"] =
      has_1s ? json(c.adev_1s * std::sqrt(c.adev_1s_tau_s) * k) : json(nullptr);
  j["adev_1s_less_terms_mps2_rthz"] = has_1s ? json(c.adev_1s_arw * k) : json(nullptr);
  j["vrw_density"] = "two-sided";
  if (f.arw.resolved) j["vrw_one_sided_mps2_rthz"] = std::numbers::sqrt2 * f.arw.value * k;
  j["bias_floor_over_0664_mg"] = f.bias_floor_dev * mg / 0.6643;
  const auto& ro = c.readoffs;
  j["readoffs"] = {{"vrw_mps2_rthz", opt(ro.arw, k)},
                   {"vrw_mg_rthz", opt(ro.arw, mg)},
                   {"vrw_tau_s", ro.arw ? json(ro.arw_from_tau_s) : json(nullptr)},
                   {"acceleration_rw_mps3_rthz", opt(ro.rrw, k)},
                   {"acceleration_rw_tau_s", ro.rrw ? json(ro.rrw_from_tau_s) : json(nullptr)},
                   {"bias_instability_mg", ro.bias_instability * mg},
                   {"floor_tau_s", ro.floor_tau_s},
                   {"floor_mg", ro.floor_dev * mg},
                   {"floor_is_minimum", ro.floor_is_minimum}};
}

}  // namespace

json noise_json(const noise_report& r) {
  const auto& c = r.result;
  const auto& f = c.terms;
  json j = schema_object("noise", 1);
  j.update(json{{"file", r.file},
                {"column", r.column},
                {"quantity", r.quantity},
                {"input", r.input},
                {"units", r.units},
                {"tau0_s", r.tau0_s},
                {"samples", r.samples},
                {"bias_floor_tau_s", f.bias_floor_tau_s},
                {"chi2_per_dof", f.chi2_per_dof},
                {"bias_floor_reached", f.bias_floor_reached},
                {"abba_cycles", r.series.shaped()},
                {"ci", f.level},
                {"notes", f.notes}});
  // The fit ran in the samples' unit; every output is in the field's units.
  if (r.quantity == "accel")
    put_accel_terms(j, r);
  else
    put_gyro_terms(j, r);
  // The OADEV points stay in the samples' unit (`units`), as `adev` writes them; beyond
  // Stable32's m <= (N-1)/4 (long_taus): shown, never fitted.
  j["oadev"] = points_json(c.oadev);
  j["long_oadev"] = points_json(c.long_oadev);
  j["fit_tau_lo_s"] = f.fit_tau_lo_s;
  j["fit_tau_hi_s"] = f.fit_tau_hi_s;
  j["fit_ranges"] = f.fit_ranges;
  j["fit_min_tau_s"] = f.fit_min_tau_s;
  j["short_taus_left_out"] = c.shaping.points == 0 ? json(nullptr)
                                                   : json{{"points", c.shaping.points},
                                                          {"cause", c.shaping.cause},
                                                          {"to_tau_s", c.shaping.kink_tau_s},
                                                          {"z", c.shaping.kink_z}};
  j["adev_1s_tau_s"] = std::isfinite(c.adev_1s) ? json(c.adev_1s_tau_s) : json(nullptr);
  // B in three conventions: the IEEE 952 fit (the headline), the first floor / 0.6643, and the
  // raw floor that datasheets quote as "in-run bias stability".
  j["bias_instability_convention"] = "IEEE 952 fit";
  json misfit = json::array();
  for (const auto& m : f.misfit)
    misfit.push_back({{"tau_s", m.tau_s},
                      {"dev", m.dev},
                      {"model_dev", m.model_dev},
                      {"ci_lo", m.ci_lo},
                      {"ci_hi", m.ci_hi}});
  j["misfit"] = std::move(misfit);
  return j;
}

namespace {

// The unit text as the rule reads it: lower case, spaces and ^ dropped, ² as 2, µ/μ as u, ° as
// deg, _ as /.
std::string normalised_unit(std::string_view text) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 4> multibyte{
      {{"\xc2\xb2", "2"}, {"\xc2\xb5", "u"}, {"\xce\xbc", "u"}, {"\xc2\xb0", "deg"}}};
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    for (const auto& [from, to] : multibyte)
      if (text.substr(i).starts_with(from)) {
        out += to;
        i += from.size();
        replaced = true;
        break;
      }
    if (replaced) continue;
    const char c = text[i++];
    if (c == ' ' || c == '^' || c == '\t') continue;
    out += c == '_' ? '/' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

std::optional<column_unit> known_unit(const std::string& u) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 15> table{{
      {"m/s2", "m/s^2"},
      {"m/s/s", "m/s^2"},
      {"mps2", "m/s^2"},
      {"g", "g"},
      {"mg", "mg"},
      {"ug", "ug"},
      {"deg/s", "deg/s"},
      {"dps", "deg/s"},
      {"deg/sec", "deg/s"},
      {"rad/s", "rad/s"},
      {"radps", "rad/s"},
      {"rad/sec", "rad/s"},
      {"deg/h", "deg/h"},
      {"dph", "deg/h"},
      {"deg/hr", "deg/h"},
  }};
  for (const auto& [name, unit] : table)
    if (u == name)
      return column_unit{units::is_accel_unit(unit) ? "accel" : "gyro", std::string(unit)};
  return std::nullopt;
}

}  // namespace

std::optional<column_unit> unit_of_column(std::string_view name) {
  // A trailing [unit] or (unit).
  if (!name.empty() && (name.back() == ']' || name.back() == ')')) {
    const char open = name.back() == ']' ? '[' : '(';
    const auto at = name.rfind(open);
    if (at == std::string_view::npos) return std::nullopt;
    return known_unit(normalised_unit(name.substr(at + 1, name.size() - at - 2)));
  }
  // The last one, two or three _-separated words, longest first (ax_m_s2, gyro_x_rad_s).
  std::vector<std::size_t> cuts;
  for (std::size_t at = name.size(); at > 0 && cuts.size() < 3;) {
    at = name.rfind('_', at - 1);
    if (at == std::string_view::npos || at == 0) break;
    cuts.push_back(at);
  }
  std::reverse(cuts.begin(), cuts.end());
  for (const auto at : cuts)
    if (auto u = known_unit(normalised_unit(name.substr(at + 1)))) return u;
  return std::nullopt;
}

kalibr_axis kalibr_axis_of(const noise_report& r) {
  const double k = r.quantity == "accel" ? r.mps2_per_unit : r.deg_per_unit * units::rad_per_deg;
  const auto scaled = [k](analysis::noise_term t) {
    for (double* v : {&t.value, &t.lo, &t.hi, &t.range_lo, &t.range_hi}) *v *= k;
    return t;
  };
  return {r.column, scaled(r.result.terms.arw), scaled(r.result.terms.rrw)};
}

namespace {

// A term's value, or for an unresolved term its upper limit.
double value_or_limit(const analysis::noise_term& t) {
  return t.resolved ? t.value : t.hi;
}

// A YAML 1.1 float: PyYAML reads "1e-05" as a string and "100" as an int, so the text always
// has a dot and a signed exponent (or is a whole number with ".0").
std::string yaml_float(double x, int digits = 6) {
  if (x == std::floor(x) && std::abs(x) < 1e9) return fmt::format("{:.1f}", x);
  return fmt::format("{:.{}e}", x, digits);
}

// One Kalibr key: the largest axis of `which`, the axes as a comment above it.
result<std::string> kalibr_key(std::string_view key, std::string_view unit,
                               const std::vector<kalibr_axis>& axes,
                               analysis::noise_term kalibr_axis::*which) {
  const kalibr_axis* worst = &axes.front();
  std::string each;
  for (const auto& a : axes) {
    const auto& t = a.*which;
    if (value_or_limit(t) > value_or_limit((*worst).*which)) worst = &a;
    each += fmt::format("{}{} {}{:.4e}", each.empty() ? "" : ", ", printable(a.column, 40),
                        t.resolved ? "" : "< ", value_or_limit(t));
  }
  const double v = value_or_limit((*worst).*which);
  if (!(v > 0.0) || !std::isfinite(v))
    return runtime_error(fmt::format("{} of column {} is {}: Kalibr needs a positive number", key,
                                     printable(worst->column, 40), v));
  return fmt::format(
      "# {} per axis ({}): {}\n{}: {}  # the largest: {}{}\n", key, unit, each, key, yaml_float(v),
      printable(worst->column, 40),
      ((*worst).*which).resolved ? "" : ", an upper limit (not resolved by the data)");
}

}  // namespace

result<std::string> kalibr_yaml(const kalibr_imu& imu) {
  if (imu.gyro.empty() || imu.accel.empty())
    return runtime_error(fmt::format(
        "Kalibr's IMU file needs the gyro's and the accelerometer's terms; no {} column was "
        "analysed",
        imu.gyro.empty() ? "gyro" : "accelerometer"));
  if (!(imu.update_rate_hz > 0.0) || !std::isfinite(imu.update_rate_hz))
    return runtime_error("Kalibr's update_rate must be a positive sample rate");
  std::string y = fmt::format(
      "# IMU noise model for Kalibr (kalibr wiki \"IMU Noise Model\"), measured by gyroflip\n"
      "# gyro: {}\n# accelerometer: {}\n"
      "# continuous-time densities as measured (two-sided: ADEV = N/sqrt(tau), K sqrt(tau/3)),\n"
      "# not inflated; each key holds the largest axis (Kalibr has one value for all axes)\n",
      printable(imu.gyro_source, 200), printable(imu.accel_source, 200));
  // rostopic as a JSON string: a valid YAML double-quoted scalar, read as a string always.
  y += "rostopic: " + nlohmann::json(imu.rostopic).dump() + "\n";
  y += "update_rate: " + yaml_float(imu.update_rate_hz, 9) + "  # Hz\n";
  const std::array keys{
      std::tuple{"accelerometer_noise_density", "m/s^2/sqrt(Hz), VRW N", &imu.accel,
                 &kalibr_axis::density},
      std::tuple{"accelerometer_random_walk", "m/s^3/sqrt(Hz), acceleration random walk K",
                 &imu.accel, &kalibr_axis::random_walk},
      std::tuple{"gyroscope_noise_density", "rad/s/sqrt(Hz), ARW N", &imu.gyro,
                 &kalibr_axis::density},
      std::tuple{"gyroscope_random_walk", "rad/s^2/sqrt(Hz), RRW K", &imu.gyro,
                 &kalibr_axis::random_walk}};
  for (const auto& [key, unit, axes, which] : keys) {
    auto line = kalibr_key(key, unit, *axes, which);
    if (!line) return line.err();
    y += *line;
  }
  return y;
}

}  // namespace gyroflip::io
