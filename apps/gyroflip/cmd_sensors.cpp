/// \file
/// \brief `gyroflip sensors`: the built-in sensor presets with parameters, units and sources.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cmd_simulate.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::app {

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
                                      {"source", p.source_of(f.key)}};
      }
      list.push_back({{"name", p.name}, {"description", p.description}, {"params", params}});
    }
    fmt::print("{}\n", nlohmann::json{{"sensors", list}}.dump(
                           -1, ' ', false, nlohmann::json::error_handler_t::replace));
    return 0;
  }
  for (const auto& p : presets) {
    fmt::print("{}: {}\n", p.name, p.description);
    for (const auto& f : sensor::fields()) {
      const auto src = p.source_of(f.key);
      fmt::print("  {:<26} {:>12} {:<13} {}\n", f.key, fmt::format("{}", p.params.*f.member),
                 f.unit, src.empty() ? "default (not applicable)" : src);
    }
  }
  return 0;
}

}  // namespace gyroflip::app
