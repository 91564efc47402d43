/// \file
/// \brief The sensor and the profiles of a simulated rig from their option texts: one reading
/// for `simulate` and `emulate`.
#pragma once

#include <optional>
#include <string>

#include "gyroflip/core/result.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::app {

/// Sets `c.sensor` from a preset name or TOML file, `c.rate` from a rate spec, and
/// `c.temperature` from a constant (default: the preset's T_ref) or a temperature spec or table
/// file (mutually exclusive). Returns the preset (its name and sources go into metadata).
[[nodiscard]] result<sensor::preset> load_physics(const std::string& sensor,
                                                  std::optional<double> temp_c,
                                                  const std::string& temp_profile,
                                                  const std::string& rate_profile,
                                                  rig::simulation_config& c);

/// The rig's mount (rig::rig_mount) from simulate's and emulate's options: `azimuth_deg` names
/// the sensitive axis at the table's 0 deg instead of `axis` (an error when `axis` is not its
/// default, north: both would name it), and the tilt.
[[nodiscard]] result<rig::rig_mount> mount_of(const std::string& axis,
                                              std::optional<double> azimuth_deg, double tilt_mrad,
                                              double tilt_azimuth_deg);

}  // namespace gyroflip::app
