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

// An unbounded side of a parameter's range is null in JSON and empty in the text listing.
nlohmann::json bound(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string range_text(const sensor::field_info& f) {
  const auto side = [](double v) { return std::isfinite(v) ? fmt::format("{:g}", v) : ""; };
  return fmt::format("[{}, {}]", side(f.min_value), side(f.max_value));
}

}  // namespace

int run_sensors(const sensors_options& o) {
  const auto& presets = sensor::builtin_presets();
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& p : presets) {
      nlohmann::json params = nlohmann::json::object();
      for (const auto& f : sensor::fields()) {
        params[std::string(f.key)] = {{"value", p.params.*f.member},
                                      {"unit", f.unit},
                                      {"what", f.what},
                                      {"source", p.source_of(f.key)},
                                      {"min", bound(f.min_value)},
                                      {"max", bound(f.max_value)}};
      }
      const auto im = workflow::implications_of(p.params, o.dead_s, o.lat_deg);
      const nlohmann::json implied = {
          {"dead_time_s", im.dead_s},
          {"latitude_deg", im.lat_deg},
          {"corner_tau_s", im.corner_tau_s},
          {"dwell_s", im.dwell_s},
          {"flip_sigma_dps_rth", im.sigma_dps_rth},
          {"heading_white_limit_deg_rth", im.heading_white_deg_rth},
          {"heading_dead_time_limit_deg_rth", im.heading_dead_time_deg_rth}};
      list.push_back({{"name", p.name},
                      {"description", p.description},
                      {"params", params},
                      {"implied", implied}});
    }
    if (auto s = print_json(with_schema("sensors", 1, {{"sensors", list}})); !s)
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
