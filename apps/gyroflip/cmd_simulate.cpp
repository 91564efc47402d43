/// \file
/// \brief `gyroflip simulate`: a recording (docs/FORMATS.md) from the simulator, with its truth.
#include "cmd_simulate.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <iterator>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

result<std::pair<double, double>> parse_positions(std::string_view text) {
  const auto comma = text.find(',');
  double a = 0.0;
  double b = 0.0;
  if (comma != std::string_view::npos) {
    const auto first = text.substr(0, comma);
    const auto second = text.substr(comma + 1);
    const auto r1 = std::from_chars(first.data(), first.data() + first.size(), a);
    const auto r2 = std::from_chars(second.data(), second.data() + second.size(), b);
    if (r1.ec == std::errc{} && r1.ptr == first.data() + first.size() && r2.ec == std::errc{} &&
        r2.ptr == second.data() + second.size()) {
      return std::pair{a, b};
    }
  }
  return usage_error(fmt::format("--positions '{}': expected A,B in degrees", text));
}

// The `# key: value` header shared by the recording and the truth file.
std::string metadata(const simulate_options& o, const sensor::preset& p, const rig::simulator& sim,
                     std::string_view kind) {
  std::string m;
  auto out = std::back_inserter(m);
  fmt::format_to(out, "# gyroflip simulate: {}\n# version: {}\n", kind, GYROFLIP_VERSION);
  fmt::format_to(out, "# sensor: {}\n# seed: {}\n# duration_s: {}\n", o.sensor, o.seed,
                 o.duration_s);
  if (o.temp_profile.empty()) {
    fmt::format_to(out, "# temp_c: {}\n", o.temp_c.value_or(p.params.temp_ref_c));
  } else {
    fmt::format_to(out, "# temp_profile: {}\n", o.temp_profile);
  }
  fmt::format_to(out, "# latitude_deg: {}\n# axis: {}\n# table_axis: {}\n# rate_profile: {}\n",
                 o.lat_deg, o.axis, o.table_axis.empty() ? "default" : o.table_axis,
                 o.rate_profile);
  fmt::format_to(out, "# n_avg: {}\n# raw: {}\n# settle_s: {}\n# positions_deg: {}\n# flip: {}\n",
                 o.n_avg, o.raw ? "yes" : "no", o.settle_s, o.positions, o.no_flip ? "no" : "yes");
  fmt::format_to(out, "# power_on_before_s: {}\n# filter_word: {}\n# chop: {}\n",
                 o.power_on_before_s, o.filter_word, o.no_chop ? "off" : "on");
  fmt::format_to(
      out, "# steps_per_rev: {}\n# start_rate_sps: {}\n# step_rate_sps: {}\n# accel_sps2: {}\n",
      o.steps_per_rev, o.start_rate_sps, o.step_rate_sps, o.accel_sps2);
  fmt::format_to(out, "# conversion_time_s: {}\n# cycle_s: {}\n# turn_s: {}\n",
                 sim.conversion_time_s(), sim.sched().cycle_s(), sim.sched().turn_ab_s());
  fmt::format_to(out, "# scale_factor_v_per_dps: {} (nominal; rate_dps = ADC volts / this)\n",
                 p.params.scale_factor_v_per_dps);
  fmt::format_to(out, "# sensor_name: {}\n", p.name);
  for (const auto& f : sensor::fields()) {
    fmt::format_to(out, "# sensor.{}: {}\n", f.key, p.params.*f.member);
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
  auto preset = sensor::load_preset(o.sensor);
  if (!preset) return report(preset.err());
  if (o.temp_c && !o.temp_profile.empty()) {
    return report(usage_error("--temp and --temp-profile are mutually exclusive"));
  }
  rig::simulation_config c;
  c.sensor = preset->params;
  c.lat_deg = o.lat_deg;
  c.axis = o.axis;
  c.table_axis = o.table_axis;
  auto rate = rig::profile::parse_rate(o.rate_profile);
  if (!rate) return report(rate.err());
  c.rate = *rate;
  if (!o.temp_profile.empty()) {
    auto temp = rig::profile::parse_temperature(o.temp_profile);
    if (!temp) return report(temp.err());
    c.temperature = *temp;
  } else {
    c.temperature = rig::profile::constant(o.temp_c.value_or(preset->params.temp_ref_c));
  }
  c.sched.n_avg = o.n_avg;
  c.sched.settle_s = o.settle_s;
  auto pos = parse_positions(o.positions);
  if (!pos) return report(pos.err());
  c.sched.pos_a_deg = pos->first;
  c.sched.pos_b_deg = pos->second;
  c.sched.flip = !o.no_flip;
  c.adc.filter_word = o.filter_word;
  c.adc.chop = !o.no_chop;
  c.stepper = {o.steps_per_rev, o.start_rate_sps, o.step_rate_sps, o.accel_sps2};
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
  out->write(metadata(o, *preset, *sim, "recording"));
  out->write("time_s,angle_deg,rate_dps,temp_c,n_avg\n");
  if (truth) {
    truth->write(metadata(o, *preset, *sim, "truth"));
    truth->write(fmt::format(
        "# sign convention: each term as seen by the sensor at that row's orientation (Earth, "
        "g-term and input reverse at 180 deg, bias does not); rate_dps ~ bias + g_term + earth + "
        "input + noise\n# dN expected at position A and the run's start temperature: earth {} + "
        "g_term {} deg/s\n",
        sim->earth_at_a_dps(), sim->g_term_at_a_dps(c.temperature.at(0.0))));
    truth->write("time_s,bias_dps,g_term_dps,earth_dps,input_dps,temp_c\n");
  }

  rig::sample_block block(1U << 14, truth.has_value());  // truth columns only when written
  rig::dwell_averager avg(o.n_avg);
  std::vector<rig::dwell_row> rows;
  fmt::memory_buffer rec;
  fmt::memory_buffer tru;
  progress bar("simulate", sim->total_samples());
  while (sim->fill(block) > 0) {
    rec.clear();
    tru.clear();
    if (o.raw) {
      for (std::size_t i = 0; i < block.size; ++i) {
        if (std::isnan(block.angle_deg[i])) {
          fmt::format_to(std::back_inserter(rec), "{},,{},{},1\n", block.time_s[i],
                         block.rate_dps[i], block.temp_c[i]);
        } else {
          fmt::format_to(std::back_inserter(rec), "{},{},{},{},1\n", block.time_s[i],
                         block.angle_deg[i], block.rate_dps[i], block.temp_c[i]);
        }
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
        fmt::format_to(std::back_inserter(rec), "{},{},{},{},{}\n", r.time_s, r.angle_deg,
                       r.rate_dps, r.temp_c, r.n_avg);
        if (truth) {
          fmt::format_to(std::back_inserter(tru), "{},{},{},{},{},{}\n", r.time_s, r.bias_dps,
                         r.g_term_dps, r.earth_dps, r.input_dps, r.temp_c);
        }
      }
    }
    // The gate of every written number (finite_output.hpp); on failure the temporaries go.
    if (auto s = check_finite({rec.data(), rec.size()}, o.out); !s) return report(s.err());
    if (auto s = check_finite({tru.data(), tru.size()}, o.truth); !s) return report(s.err());
    out->write(std::string_view(rec.data(), rec.size()));
    if (truth) truth->write(std::string_view(tru.data(), tru.size()));
    bar.update(sim->produced());
  }
  bar.finish();
  // Both files or neither: a full disk on --truth must not leave a recording without its truth.
  if (auto s = io::commit_all({&*out, truth ? &*truth : nullptr}); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
