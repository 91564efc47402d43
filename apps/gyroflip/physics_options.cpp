/// \file
/// \brief The sensor and the profiles of a simulated rig (physics_options.hpp).
#include "physics_options.hpp"

#include <utility>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::app {

result<sensor::preset> load_physics(const std::string& sensor, std::optional<double> temp_c,
                                    const std::string& temp_profile,
                                    const std::string& rate_profile, rig::simulation_config& c) {
  auto preset = sensor::load_preset(sensor);
  if (!preset) return preset.err();
  if (temp_c && !temp_profile.empty())
    return usage_error("--temp and --temp-profile are mutually exclusive");
  c.sensor = preset->params;
  auto rate = rig::profile::parse_rate(rate_profile);
  if (!rate) return rate.err();
  c.rate = *rate;
  if (!temp_profile.empty()) {
    // A spec, or a table file read by io's CSV reader (FILE:LINE:COL in its errors).
    result<rig::profile> temp = rig::profile::parse_temperature(temp_profile);
    if (!rig::profile::is_temperature_spec(temp_profile)) {
      auto tab = io::read_time_table(temp_profile, "temp_c");
      if (!tab) return tab.err();
      temp = rig::profile::table(std::move(tab->time_s), std::move(tab->value));
    }
    if (!temp) return temp.err();
    c.temperature = *temp;
  } else {
    c.temperature = rig::profile::constant(temp_c.value_or(preset->params.temp_ref_c));
  }
  return std::move(*preset);
}

result<rig::rig_mount> mount_of(const std::string& axis, std::optional<double> azimuth_deg,
                                double tilt_mrad, double tilt_azimuth_deg) {
  rig::rig_mount m;
  if (azimuth_deg) {
    if (axis != "north")
      return usage_error("--azimuth and --axis both name the sensitive axis: give one");
    m.azimuth_deg = *azimuth_deg;
  }
  m.tilt_mrad = tilt_mrad;
  m.tilt_azimuth_deg = tilt_azimuth_deg;
  return m;
}

}  // namespace gyroflip::app
