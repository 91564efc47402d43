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
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/simulate.hpp"
#include "physics_options.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

// The positions `calibrate` reads (io::recording_reader): A within its largest angle tolerance of
// 0 (mod 360), B of 180. Others would make a recording no calibration accepts.
result<std::pair<double, double>> parse_positions(std::string_view text) {
  const auto v = text::to_doubles(text, ',');
  if (!v || v->size() != 2)
    return usage_error(
        fmt::format("--positions '{}': expected A,B in degrees", printable(text, 60)));
  const auto off = [](double a, double target) {
    const double turned = std::fmod(std::fmod(a - target, 360.0) + 360.0, 360.0);
    return std::min(turned, 360.0 - turned);
  };
  const double tol = io::recording_reader::max_angle_tolerance_deg;
  if (!(std::abs((*v)[0]) <= 1e4 && std::abs((*v)[1]) <= 1e4) || !(off((*v)[0], 0.0) <= tol) ||
      !(off((*v)[1], 180.0) <= tol))
    return usage_error(fmt::format(
        "--positions '{}': A must lie within {:g} deg of 0 and B within {:g} deg of 180 (the "
        "positions calibrate reads, with --angle-tolerance for any offset)",
        printable(text, 60), tol, tol));
  return std::pair{(*v)[0], (*v)[1]};
}

// The `# key: value` metadata of the recording and the truth file: every option, so that the
// file can be made again byte for byte (the simulator adds what it derived from them).
std::vector<io::csv_metadata> metadata(const simulate_options& o, const sensor::preset& p) {
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
  add("n_avg", num(o.n_avg));
  add("raw", o.raw ? "yes" : "no");
  add("settle_s", num(o.settle_s));
  add("positions_deg", o.positions);
  add("flip", o.no_flip ? "no" : "yes");
  add("power_on_before_s", num(o.power_on_before_s));
  add("filter_word", num(o.filter_word));
  add("chop", o.no_chop ? "off" : "on");
  add("steps_per_rev", num(o.steps_per_rev));
  add("start_rate_sps", num(o.start_rate_sps));
  add("step_rate_sps", num(o.step_rate_sps));
  add("accel_sps2", num(o.accel_sps2));
  add("sensor_name", p.name);
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
  workflow::recording_request req{
      c, o.raw, o.out, o.truth, "gyroflip simulate", metadata(o, *preset)};
  progress bar("simulate", 1000);
  auto truth = workflow::simulate_recording(req, per_mille(bar));
  bar.finish();
  if (!truth) return report(truth.err());
  return 0;
}

}  // namespace gyroflip::app
