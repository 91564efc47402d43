/// \file
/// \brief THE PRESET FILE: built-in sensor figures with their source, one line per figure.
///
/// Tags as in docs/FACTS.md: [V] seen in a public source, [U] recollection not verified,
/// [D] derived here, "assumption" = chosen by us (reason given), "paper" = fitted to the
/// Arnaudov & Angelov measurements (FACTS §3). Geometry of the fits: default rig of
/// `gyroflip simulate` (sensitive axis north, table axis east, latitude 42.6 deg N), where the
/// specific force at 0 deg is f = (0, 0, -1) g in sensor axes, so a g-sensitivity g_z gives the
/// 0-deg g-term -g_z and dN = -g_z + W_E cos(42.6 deg) = -g_z + 3.0755e-3 deg/s.
#include <algorithm>
#include <iterator>

#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::sensor {
namespace {

// The sources of the values fitted to the paper's measurements (the "paper" tag above).
constexpr std::string_view paper_fit_tags[] = {"paper Tab. 3", "paper Tab. 4", "paper Figs.",
                                               "fitted to paper"};

struct entry {
  std::string_view key;
  double value;
  std::string_view source;
};

preset make(std::string name, std::string description, std::initializer_list<entry> entries) {
  preset p{std::move(name), std::move(description), sensor_params{}, {}};
  for (const auto& e : entries) {
    const auto* f = find_field(e.key);
    if (f != nullptr) p.params.*f->member = e.value;  // test_sensor checks every key is a field
    p.sources.emplace_back(std::string(e.key), std::string(e.source));
  }
  return p;
}

std::vector<preset> build() {
  std::vector<preset> v;
  v.push_back(make(
      "adxrs150", "Analog Devices ADXRS150 +-150 deg/s yaw-rate gyro (paper Tab. 4, Figs. 3-6)",
      {
          {"range_dps", 150.0, "datasheet [V] (FACTS §4.1)"},
          {"scale_factor_v_per_dps", 0.0125, "datasheet [V] 12.5 mV/(deg/s)"},
          {"null_v", 2.5, "datasheet [U] 2.50 V"},
          {"bandwidth_hz", 40.0, "datasheet [U] ~40 Hz with the default capacitor"},
          {"scale_factor_error_ppm", 0.0, "assumption: nominal unit (datasheet +-10 % [U])"},
          {"scale_factor_tc_ppm_per_c", 200.0, "assumption: typical MEMS, not in sources"},
          {"nonlinearity_fs", 0.001, "datasheet [U] 0.1 % FS"},
          {"quantisation_deg", 0.0, "analog output: none"},
          {"arw_dps_rthz", 0.0353553,
           "datasheet [V] 0.05 deg/s/rtHz one-sided density; IEEE N = "
           "0.05/sqrt(2); reproduces paper Fig. 4/6 std 3.5e-2 deg/s"},
          {"bias_instability_dps", 0.02, "assumption: ~70 deg/h, typical of the part's era"},
          {"flicker_tau_min_s", 1.0, "assumption: bank span covers the paper's 1.8 s - 2.5 h"},
          {"flicker_tau_max_s", 1.0e4, "assumption"},
          {"rrw_dps_per_rts", 1e-4, "assumption"},
          {"rate_ramp_dps_per_s", 0.0, "assumption: none"},
          {"bias_dps", 0.0, "assumption: the null tolerance is drawn per power-up instead"},
          {"turn_on_bias_sigma_dps", 0.1, "assumption (initial null 2.3-2.7 V [U] is wider)"},
          {"warmup_amplitude_dps", 0.3, "assumption: Fig. 3 (off before) vs Fig. 5 (on before)"},
          {"warmup_tau_s", 300.0, "assumption"},
          {"bias_tc_dps_per_c", 0.01, "assumption: null drift over temperature not in sources"},
          {"temp_ref_c", 20.0, "paper: room temperature ~20 degC"},
          {"g_sens_z_dps_per_g", -0.3921445,
           "paper Tab. 4: dN 0.39522 = g-term 0.39214 + Earth 3.0755e-3 (datasheet 0.2 deg/s/g "
           "typical [U], imusim 0.2 for ADXRS300 [V])"},
          {"g_sens_turn_on_sigma_dps_per_g", 0.01626,
           "fitted to paper Tab. 4: its 14 runs' dN scatter by 0.01626 deg/s (std), 30x their "
           "within-run error; a change of the g-term at each power-up is the reading that "
           "explains it (8 % of the datasheet's 0.2 deg/s/g; assumption)"},
          {"g_sens_spec_typ_dps_per_g", 0.2,
           "datasheet [U] 0.2 deg/s/g typical, no maximum stated (FACTS §4.1, not verified)"},
          {"cross_axis_y", 0.02, "assumption (imusim: 5 % 3-sigma for ADXRS300 [V])"},
      }));
  v.push_back(make(
      "hz1-90-100a",
      "BEI/Systron Donner GyroChip Horizon HZ1-90-100A +-90 deg/s quartz rate sensor (paper "
      "Tab. 2-3, Figs. 7-10)",
      {
          {"range_dps", 90.0, "datasheet (paper Tab. 2)"},
          {"scale_factor_v_per_dps", 0.0222, "datasheet (paper Tab. 2) 22.2 mV/(deg/s) +-2 %"},
          {"null_v", 2.5, "assumption: 2.5 V +- 2.0 V swing [D]"},
          {"bandwidth_hz", 18.0, "datasheet [U] > 18 Hz"},
          {"scale_factor_error_ppm", 0.0, "assumption: nominal unit (datasheet +-2 %)"},
          {"scale_factor_tc_ppm_per_c", 100.0, "assumption"},
          {"nonlinearity_fs", 0.0005, "assumption"},
          {"quantisation_deg", 0.0, "analog output: none"},
          {"arw_dps_rthz", 0.0046,
           "paper Figs. 8/10: compensated std 4.6e-3 deg/s per 1.79-s cycle (datasheet <= 0.025 "
           "deg/s/rtHz [U] is a bound)"},
          {"bias_instability_dps", 0.004, "assumption: below threshold < 0.004 deg/s (Tab. 2)"},
          {"flicker_tau_min_s", 1.0, "assumption"},
          {"flicker_tau_max_s", 1.0e4, "assumption"},
          {"rrw_dps_per_rts", 2e-5, "assumption: short-term stability (100 s) < 0.05 deg/s"},
          {"rate_ramp_dps_per_s", 0.0, "assumption: none"},
          {"bias_dps", 0.0, "assumption"},
          {"turn_on_bias_sigma_dps", 0.05, "assumption"},
          {"warmup_amplitude_dps", 0.02, "assumption"},
          {"warmup_tau_s", 300.0, "assumption"},
          {"bias_tc_dps_per_c", 0.002, "assumption"},
          {"temp_ref_c", 20.0, "paper: room temperature ~20 degC"},
          {"g_sens_z_dps_per_g", -1.45e-5,
           "paper Tab. 3: dN(20 C) 0.00309 = Earth 0.0030755 + g-term 1.45e-5 (datasheet < 0.06 "
           "deg/s/g)"},
          {"g_sens_tc_z_dps_per_g_c", 4.5e-5,
           "paper Tab. 3: dN(4 C) 0.00381 - dN(20 C) = 7.2e-4 over -16 degC (FACTS §3)"},
          {"g_sens_turn_on_sigma_dps_per_g", 0.000959,
           "fitted to paper Tab. 3: dN std over 13 runs at ~20 degC is 0.000959 deg/s, 14x the "
           "within-run error: a per-power-up change of the g-term (assumption)"},
          {"g_sens_tc_turn_on_sigma_dps_per_g_c", 8.75e-5,
           "fitted to paper Tab. 3: at ~4 degC the std is 0.001697 = sqrt(0.000959^2 + (16 degC "
           "x 8.75e-5)^2): the turn-on change reaches the temperature coefficient too "
           "(assumption)"},
          {"g_sens_spec_max_dps_per_g", 0.06,
           "specification < 0.06 deg/s/g (paper Tab. 2, FACTS §4.2)"},
          {"cross_axis_y", 0.01, "assumption"},
      }));
  return v;
}

}  // namespace

bool fitted_to_paper(const preset& p, std::string_view key) {
  const auto s = p.source_of(key);
  return std::any_of(std::begin(paper_fit_tags), std::end(paper_fit_tags),
                     [&](std::string_view tag) { return s.starts_with(tag); });
}

std::string_view preset::source_of(std::string_view key) const {
  for (const auto& [k, s] : sources) {
    if (k == key) return s;
  }
  return {};
}

const std::vector<preset>& builtin_presets() {
  static const std::vector<preset> presets = build();  // immutable constants
  return presets;
}

const preset* find_builtin(std::string_view name) {
  const auto& all = builtin_presets();
  const auto it =
      std::find_if(all.begin(), all.end(), [&](const preset& p) { return p.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace gyroflip::sensor
