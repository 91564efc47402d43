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

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/io/recording_writer.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "physics_options.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

// The positions `calibrate` reads (io::recording_reader): A within its largest angle tolerance of
// 0 (mod 360), B of 180. Others would make a recording no calibration accepts.
status check_readable_positions(const rig::rig_config& r, std::string_view text) {
  const auto off = [](double a, double target) {
    const double turned = std::fmod(std::fmod(a - target, 360.0) + 360.0, 360.0);
    return std::min(turned, 360.0 - turned);
  };
  const double tol = io::recording_reader::max_angle_tolerance_deg;
  if (r.positions_deg.size() != 2 || !(off(r.positions_deg[0], 0.0) <= tol) ||
      !(off(r.positions_deg[1], 180.0) <= tol))
    return usage_error(fmt::format(
        "--positions '{}': A must lie within {:g} deg of 0 and B within {:g} deg of 180 (the "
        "positions calibrate reads, with --angle-tolerance for any offset)",
        printable(text, 60), tol, tol));
  return ok();
}

// The `# key: value` metadata shared by the recording and the truth file: every input, so that
// the file can be reproduced byte for byte.
std::vector<io::csv_metadata> metadata(const simulate_options& o, const sensor::preset& p,
                                       const rig::simulator& sim, std::string_view kind) {
  std::vector<io::csv_metadata> m;
  const auto add = [&m](std::string key, std::string value) {
    m.push_back({std::move(key), std::move(value)});
  };
  const auto num = [](auto v) { return fmt::format("{}", v); };
  add("gyroflip simulate", std::string(kind));
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
  const rig::rig_config& r = sim.config().rig;
  add("n_avg", num(r.n_avg));
  add("raw", o.raw ? "yes" : "no");
  add("settle_s", num(r.settle_s));
  add("positions_deg", o.rig.positions);
  add("flip", o.no_flip ? "no" : "yes");
  add("power_on_before_s", num(o.power_on_before_s));
  add("turns", r.one_way ? "one way" : "back and forth");
  add("hold_coils", r.hold_coils ? "yes" : "no");
  add("coil_heat_rise_c", num(sim.config().coil.rise_c));
  add("coil_heat_tau_s", num(sim.config().coil.tau_s));
  add("filter_word", num(r.filter_word));
  add("chop", r.chop ? "on" : "off");
  add("steps_per_rev", num(r.steps_per_rev));
  add("start_rate_sps", num(r.start_rate_sps));
  add("step_rate_sps", num(r.max_rate_sps));
  add("accel_sps2", num(r.accel_sps2));
  add("conversion_time_s", num(sim.conversion_time_s()));
  add("cycle_s", num(sim.sched().cycle_s()));
  add("turn_s", num(sim.sched().turn_ab_s()));
  add("scale_factor_v_per_dps",
      fmt::format("{} (nominal; rate_dps = ADC volts / this)", p.params.scale_factor_v_per_dps));
  add("sensor_name", p.name);
  for (const auto& f : sensor::fields())
    add(fmt::format("sensor.{}", f.key), num(p.params.*f.member));
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
  auto rig = rig_config_of(o.rig);
  if (!rig) return report(rig.err());
  if (auto s = check_readable_positions(*rig, o.rig.positions); !s) return report(s.err());
  c.rig = *rig;
  c.flip = !o.no_flip;
  auto coil = coil_heating_of(o.rig.coil_heat);
  if (!coil) return report(coil.err());
  c.coil = *coil;
  c.duration_s = o.duration_s;
  c.power_on_before_s = o.power_on_before_s;
  c.seed = o.seed;
  auto sim = rig::simulator::make(c);
  if (!sim) return report(sim.err());

  auto out = io::atomic_file::create(o.out);
  if (!out) return report(out.err());
  std::optional<io::atomic_file> truth;
  if (!o.truth.empty()) {
    auto t = io::atomic_file::create(o.truth);
    if (!t) return report(t.err());
    truth.emplace(std::move(*t));
  }
  std::string head;
  io::append_recording_header(head, metadata(o, *preset, *sim, "recording"));
  out->write(head);
  if (truth) {
    head.clear();
    io::append_metadata(head, metadata(o, *preset, *sim, "truth"));
    truth->write(head);
    truth->write(fmt::format(
        "# sign convention: each term as seen by the sensor at that row's orientation (Earth, "
        "g-term and input reverse at 180 deg, bias does not); rate_dps ~ bias + g_term + earth + "
        "input + noise\n# dN expected at position A and the run's start temperature: earth {} + "
        "g_term {} deg/s\n",
        sim->earth_at_a_dps(), sim->g_term_at_a_dps(c.temperature.at(0.0))));
    truth->write("time_s,bias_dps,g_term_dps,earth_dps,input_dps,temp_c\n");
  }

  rig::sample_block block(1U << 14, truth.has_value());  // truth columns only when written
  rig::dwell_averager avg(c.rig.n_avg);
  std::vector<rig::dwell_row> rows;
  std::string rec;
  fmt::memory_buffer tru;
  progress bar("simulate", sim->total_samples());
  while (sim->fill(block) > 0) {
    rec.clear();
    tru.clear();
    if (o.raw) {
      for (std::size_t i = 0; i < block.size; ++i) {
        io::append_recording_row(
            rec, {block.time_s[i], block.angle_deg[i], block.rate_dps[i], block.temp_c[i], 1});
        if (truth) {
          fmt::format_to(std::back_inserter(tru), "{},{},{},{},{},{}\n", block.time_s[i],
                         block.bias_dps[i], block.g_term_dps[i], block.earth_dps[i],
                         block.input_dps[i], block.temp_c[i]);
        }
      }
    } else {
      rows.clear();
      avg.add(block, rows);
      for (const auto& r : rows) {
        io::append_recording_row(rec, {r.time_s, r.angle_deg, r.rate_dps, r.temp_c,
                                       static_cast<std::uint32_t>(r.n_avg)});
        if (truth) {
          fmt::format_to(std::back_inserter(tru), "{},{},{},{},{},{}\n", r.time_s, r.bias_dps,
                         r.g_term_dps, r.earth_dps, r.input_dps, r.temp_c);
        }
      }
    }
    // The gate of every written number (finite_output.hpp); on failure the temporaries go.
    if (auto s = check_finite(rec, o.out); !s) return report(s.err());
    if (auto s = check_finite({tru.data(), tru.size()}, o.truth); !s) return report(s.err());
    out->write(rec);
    if (truth) truth->write(std::string_view(tru.data(), tru.size()));
    bar.update(sim->produced());
  }
  bar.finish();
  // Both files or neither: a full disk on --truth must not leave a recording without its truth.
  if (auto s = io::commit_all({&*out, truth ? &*truth : nullptr}); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
