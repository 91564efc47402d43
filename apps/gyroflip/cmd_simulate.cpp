/// \file
/// \brief `gyroflip simulate`: a recording (docs/FORMATS.md) from the simulator, with its truth.
#include "cmd_simulate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/simulate.hpp"
#include "physics_options.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

// The `# key: value` metadata of the recording and the truth file: every option (the rig's as
// it takes them, rig_config), so that the file can be made again byte for byte (the simulator
// adds what it derived from them: workflow::simulate_recording).
std::vector<io::csv_metadata> metadata(const simulate_options& o, const sensor::preset& p,
                                       const rig::simulation_config& c) {
  const rig::rig_config& r = c.rig;
  std::vector<io::csv_metadata> m;
  const auto add = [&m](std::string key, std::string value) {
    m.push_back({std::move(key), std::move(value)});
  };
  const auto num = [](auto v) { return fmt::format("{}", v); };
  add("version", GYROFLIP_VERSION);
  add("sensor", o.sensor);
  add("seed", num(o.seed));
  add("duration_s", num(o.duration_s));
  if (o.temp_profile.empty()) {
    add("temp_c", num(o.temp_c.value_or(p.params.temp_ref_c)));
  } else {
    add("temp_profile", o.temp_profile);
  }
  add("latitude_deg", num(o.lat_deg));
  add("axis", o.axis);
  add("table_axis", o.table_axis.empty() ? "default" : o.table_axis);
  add("rate_profile", o.rate_profile);
  add("n_avg", num(r.n_avg));
  add("raw", o.raw ? "yes" : "no");
  add("settle_s", num(r.settle_s));
  add("positions_deg", o.rig.positions);
  add("flip", o.no_flip ? "no" : "yes");
  add("power_on_before_s", num(o.power_on_before_s));
  add("turns", r.one_way ? "one way" : "back and forth");
  add("hold_coils", r.hold_coils ? "yes" : "no");
  add("coil_heat_rise_c", num(c.coil.rise_c));
  add("coil_heat_tau_s", num(c.coil.tau_s));
  add("filter_word", num(r.filter_word));
  add("chop", r.chop ? "on" : "off");
  add("steps_per_rev", num(r.steps_per_rev));
  add("start_rate_sps", num(r.start_rate_sps));
  add("step_rate_sps", num(r.max_rate_sps));
  add("accel_sps2", num(r.accel_sps2));
  add("sensor_name", p.name);
  // Issue 33's settings, only when used (a two-position run's files stay as they were).
  if (c.rig.positions_deg.size() > 2 || o.order != "auto" || o.azimuth_deg || o.tilt_mrad != 0.0) {
    add("order", o.order);
    add("visits_deg", fmt::format("{}", fmt::join(c.rig.schedule(true, c.order).visits, ",")));
    add("azimuth_deg", o.azimuth_deg ? num(*o.azimuth_deg) : "none");
    add("tilt_mrad", num(o.tilt_mrad));
    add("tilt_azimuth_deg", num(o.tilt_azimuth_deg));
  }
  return m;
}

}  // namespace

int run_simulate(const simulate_options& o) {
  // Preset and temperature-profile files are inputs too (the names of built-in presets and
  // profile specs are not files, and check_outputs skips what does not exist).
  if (auto s = io::check_outputs(std::array{o.sensor, o.temp_profile}, std::array{o.out, o.truth});
      !s)
    return report(s.err());
  rig::simulation_config c;
  auto preset = load_physics(o.sensor, o.temp_c, o.temp_profile, o.rate_profile, c);
  if (!preset) return report(preset.err());
  c.lat_deg = o.lat_deg;
  c.axis = o.axis;
  c.table_axis = o.table_axis;
  auto mount = mount_of(o.axis, o.azimuth_deg, o.tilt_mrad, o.tilt_azimuth_deg);
  if (!mount) return report(mount.err());
  c.mount = *mount;
  c.order = o.order == "sweep"   ? rig::visit_order::sweep
            : o.order == "cycle" ? rig::visit_order::cycle
                                 : rig::visit_order::automatic;
  auto rig = rig_config_of(o.rig);
  if (!rig) return report(rig.err());
  c.rig = *rig;
  // The device's order (record --order there-and-back): its angle table, visited as written.
  if (o.order == "there-and-back") {
    auto visits =
        rig::device_visits(c.rig.positions_deg, rig::device_order::there_and_back, c.rig.one_way);
    if (!visits) return report(visits.err());
    c.rig.positions_deg = std::move(*visits);
    if (auto s = c.rig.check(); !s) return report(s.err());
  }
  c.flip = !o.no_flip;
  auto coil = coil_heating_of(o.rig.coil_heat);
  if (!coil) return report(coil.err());
  c.coil = *coil;
  c.duration_s = o.duration_s;
  c.power_on_before_s = o.power_on_before_s;
  c.seed = o.seed;
  workflow::recording_request req{
      c, o.raw, o.out, o.truth, "gyroflip simulate", metadata(o, *preset, c)};
  progress bar("simulate", 1000);
  auto truth = workflow::simulate_recording(req, per_mille(bar));
  bar.finish();
  if (!truth) return report(truth.err());
  return 0;
}

}  // namespace gyroflip::app
