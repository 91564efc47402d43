/// \file
/// \brief The field table of `sensor_params` and its validation.
#include "gyroflip/sensor/params.hpp"

#include <array>
#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::sensor {
namespace {

using P = sensor_params;

// Every range is finite: within them the simulator's arithmetic cannot overflow, and they are
// wider than any real MEMS or quartz rate sensor (docs/SIMULATOR.md, "Limits").
const std::array<field_info, 32> table{{
    {"range_dps", "deg/s", "saturation of the sensed rate", &P::range_dps, 1e-6, 1e6},
    {"scale_factor_v_per_dps", "V/(deg/s)", "nominal scale factor", &P::scale_factor_v_per_dps,
     1e-9, 100.0},
    {"null_v", "V", "nominal null output voltage", &P::null_v, -100.0, 100.0},
    {"bandwidth_hz", "Hz", "first-order low-pass corner (0 = none)", &P::bandwidth_hz, 0.0, 1e6},
    {"scale_factor_error_ppm", "ppm", "actual/nominal scale factor - 1", &P::scale_factor_error_ppm,
     -5e5, 5e5},
    {"scale_factor_tc_ppm_per_c", "ppm/degC", "scale-factor temperature coefficient",
     &P::scale_factor_tc_ppm_per_c, -1e4, 1e4},
    {"nonlinearity_fs", "-", "quadratic bow at +-range, fraction of full scale",
     &P::nonlinearity_fs, -0.5, 0.5},
    {"quantisation_deg", "deg", "angle quantum of a digital output (0 = none)",
     &P::quantisation_deg, 0.0, 1e3},
    {"arw_dps_rthz", "deg/s/rtHz", "angle random walk N, ADEV(tau) = N/sqrt(tau)", &P::arw_dps_rthz,
     0.0, 1e3},
    {"bias_instability_dps", "deg/s", "flicker coefficient B, ADEV floor 0.6643 B",
     &P::bias_instability_dps, 0.0, 1e3},
    // The bounds of the two flicker time constants and of warmup_tau_s bound the simulator's work:
    // the slow-bias grid steps by min(1 s, tau_min/10, warmup_tau/100) >= 1e-4 s, and the bank
    // has 2 log10(tau_max/tau_min) + 1 <= 25 parts, so a simulated hour costs at most ~3.6e7
    // grid points (about a second) whatever the preset (issue 13 item 3: 1e-6 s took 4 h).
    {"flicker_tau_min_s", "s", "shortest time constant of the flicker bank", &P::flicker_tau_min_s,
     1e-3, 1e9},
    {"flicker_tau_max_s", "s", "longest time constant of the flicker bank", &P::flicker_tau_max_s,
     1e-3, 1e9},
    {"rrw_dps_per_rts", "deg/s/rts", "rate random walk K, ADEV(tau) = K sqrt(tau/3)",
     &P::rrw_dps_per_rts, 0.0, 1e3},
    {"rate_ramp_dps_per_s", "deg/s/s", "rate ramp R", &P::rate_ramp_dps_per_s, -1e3, 1e3},
    {"bias_dps", "deg/s", "repeatable bias at temp_ref_c", &P::bias_dps, -1e6, 1e6},
    {"turn_on_bias_sigma_dps", "deg/s", "std of the per-power-up bias", &P::turn_on_bias_sigma_dps,
     0.0, 1e6},
    {"warmup_amplitude_dps", "deg/s", "warm-up transient amplitude at power-on",
     &P::warmup_amplitude_dps, -1e6, 1e6},
    {"warmup_tau_s", "s", "warm-up time constant", &P::warmup_tau_s, 1e-2, 1e9},
    {"bias_tc_dps_per_c", "deg/s/degC", "bias temperature coefficient", &P::bias_tc_dps_per_c, -1e3,
     1e3},
    {"temp_ref_c", "degC", "reference temperature of the coefficients", &P::temp_ref_c, -273.15,
     1000.0},
    {"g_sens_x_dps_per_g", "deg/s/g", "g-sensitivity along sensor x (sensitive axis)",
     &P::g_sens_x_dps_per_g, -1e3, 1e3},
    {"g_sens_y_dps_per_g", "deg/s/g", "g-sensitivity along sensor y", &P::g_sens_y_dps_per_g, -1e3,
     1e3},
    {"g_sens_z_dps_per_g", "deg/s/g", "g-sensitivity along sensor z", &P::g_sens_z_dps_per_g, -1e3,
     1e3},
    {"g_sens_tc_x_dps_per_g_c", "deg/s/g/degC", "temperature coefficient of g_sens_x",
     &P::g_sens_tc_x_dps_per_g_c, -1e2, 1e2},
    {"g_sens_tc_y_dps_per_g_c", "deg/s/g/degC", "temperature coefficient of g_sens_y",
     &P::g_sens_tc_y_dps_per_g_c, -1e2, 1e2},
    {"g_sens_tc_z_dps_per_g_c", "deg/s/g/degC", "temperature coefficient of g_sens_z",
     &P::g_sens_tc_z_dps_per_g_c, -1e2, 1e2},
    {"g_sens_turn_on_sigma_dps_per_g", "deg/s/g", "std of the per-power-up change of g_sens_z",
     &P::g_sens_turn_on_sigma_dps_per_g, 0.0, 1e3},
    {"g_sens_tc_turn_on_sigma_dps_per_g_c", "deg/s/g/degC",
     "std of the per-power-up change of g_sens_tc_z", &P::g_sens_tc_turn_on_sigma_dps_per_g_c, 0.0,
     1e2},
    {"g_sens_spec_max_dps_per_g", "deg/s/g",
     "specification: guaranteed maximum g-sensitivity (0 = not stated; not simulated)",
     &P::g_sens_spec_max_dps_per_g, 0.0, 1e3},
    {"g_sens_spec_typ_dps_per_g", "deg/s/g",
     "specification: typical g-sensitivity (0 = not stated; not simulated)",
     &P::g_sens_spec_typ_dps_per_g, 0.0, 1e3},
    {"cross_axis_y", "-", "cross-axis sensitivity to rate about sensor y", &P::cross_axis_y, -1.0,
     1.0},
    {"cross_axis_z", "-", "cross-axis sensitivity to rate about sensor z", &P::cross_axis_z, -1.0,
     1.0},
}};

}  // namespace

std::span<const field_info> fields() {
  return table;
}

const field_info* find_field(std::string_view key) {
  for (const auto& f : fields()) {
    if (f.key == key) return &f;
  }
  return nullptr;
}

status validate(const sensor_params& p) {
  for (const auto& f : fields()) {
    const double v = p.*f.member;
    if (!std::isfinite(v)) return usage_error(fmt::format("{}: must be finite", f.key));
    if (v < f.min_value || v > f.max_value) {
      return usage_error(fmt::format("{} = {}: must be within [{}, {}] {}", f.key, v, f.min_value,
                                     f.max_value, f.unit));
    }
  }
  if (p.flicker_tau_min_s >= p.flicker_tau_max_s) {
    return usage_error("flicker_tau_min_s must be smaller than flicker_tau_max_s");
  }
  return ok();
}

}  // namespace gyroflip::sensor
