/// \file
/// \brief The rig's settings as options (rig_options.hpp).
#include "rig_options.hpp"

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"

namespace gyroflip::app {

result<rig::rig_config> rig_config_of(const rig_options& o) {
  rig::rig_config c;
  c.n_avg = o.n_avg;
  c.n_temp = o.n_temp;
  c.settle_s = o.settle_s;
  const auto pos = text::to_doubles(o.positions, ',');
  if (!pos)
    return parameter_error("positions_deg",
                           fmt::format("'{}': expected table positions in degrees, A,B,...",
                                       printable(o.positions, 60)));
  c.positions_deg = *pos;
  c.filter_word = o.filter_word;
  c.chop = !o.no_chop;
  c.steps_per_rev = o.steps_per_rev;
  c.max_rate_sps = o.step_rate_sps;
  c.start_rate_sps = o.start_rate_sps;
  c.accel_sps2 = o.accel_sps2;
  c.one_way = o.one_way;
  c.home = o.home;
  c.hold_coils = o.hold_coils;
  if (auto s = c.check(); !s) return s.err();
  return c;
}

}  // namespace gyroflip::app
