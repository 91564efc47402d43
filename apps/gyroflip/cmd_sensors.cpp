/// \file
/// \brief `gyroflip sensors`: the built-in sensor presets with parameters, units and sources.
#include <cmath>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cmd_simulate.hpp"
#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/plan.hpp"

namespace gyroflip::app {

namespace {

// An unbounded side of a parameter's range is empty in the text listing (null in JSON).
std::string range_text(const sensor::field_info& f) {
  const auto side = [](double v) { return std::isfinite(v) ? fmt::format("{:g}", v) : ""; };
  return fmt::format("[{}, {}]", side(f.min_value), side(f.max_value));
}

}  // namespace

int run_sensors(const sensors_options& o) {
  const auto& presets = sensor::builtin_presets();
  if (o.json) {
    if (auto s = print_json(workflow::sensors_json(o.dead_s, o.lat_deg)); !s)
      return report(s.err());
    return 0;
  }
  std::string text;
  const auto out = std::back_inserter(text);
  fmt::format_to(
      out,
      "Columns: parameter, value, unit, allowed range (a preset file may set values within it),\n"
      "source. The ranges bound the simulator's work: a simulated hour takes about a second\n"
      "whatever the preset (docs/SIMULATOR.md, \"Limits\").\n\n");
  for (const auto& p : presets) {
    fmt::format_to(out, "{}: {}\n", p.name, p.description);
    for (const auto& f : sensor::fields()) {
      const auto src = p.source_of(f.key);
      fmt::format_to(out, "  {:<26} {:>12} {:<13} {:<18} {}\n", f.key,
                     fmt::format("{}", p.params.*f.member), f.unit, range_text(f),
                     src.empty() ? "default (not applicable)" : src);
    }
    const auto im = workflow::implications_of(p.params, o.dead_s, o.lat_deg);
    fmt::format_to(out,
                   "  implies (docs/PLANNER.md, docs/NORTH.md): corner time tau_c = N^2/(0.4413 "
                   "B^2) = {:.3g} s; best dwell sqrt(d tau_c) = {:.3g} s for a dead time d = {:g} "
                   "s per turn (a 0/180 run's error then (N + 0.664 B sqrt(d))/sqrt(T) = {:.3g} "
                   "deg/s x sqrt(h/T)); north finding at {:g} deg latitude (>= 3 positions): "
                   "white-noise limit {:.3g} deg x sqrt(h/T), with the dead time {:.3g} deg x "
                   "sqrt(h/T)\n",
                   im.corner_tau_s, im.dwell_s, im.dead_s, im.sigma_dps_rth, im.lat_deg,
                   im.heading_white_deg_rth, im.heading_dead_time_deg_rth);
  }
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
