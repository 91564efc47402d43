/// \file
/// \brief `gyroflip earth`: the Earth-rate component along a sensitive axis.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"

namespace gyroflip::app {

int run_earth(const earth_options& o) {
  if (auto s = earth::check_latitude(o.lat_deg); !s) return report(s.err());
  const auto axis = earth::parse_axis(o.axis);
  if (!axis) return report(axis.err());
  const double w_dps = earth::earth_rate_component_dps(o.lat_deg, *axis);
  if (o.json) {
    const auto j = with_schema("earth", 1,
                               {{"lat_deg", o.lat_deg},
                                {"axis_ned", {axis->north, axis->east, axis->down}},
                                {"earth_rate_dps", w_dps},
                                {"earth_rate_deg_h", w_dps * units::dph_per_dps}});
    if (auto s = print_json(j); !s) return report(s.err());
    return 0;
  }
  const auto text = fmt::format(
      "{:.10e} deg/s  ({:.6f} deg/h) Earth rate along axis ({:.6f}, {:.6f}, {:.6f}) NED at {} "
      "deg\n",
      w_dps, w_dps * units::dph_per_dps, axis->north, axis->east, axis->down, o.lat_deg);
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
