/// \file
/// \brief The cycle layout in conversion slots (see schedule.hpp).
#include "gyroflip/rig/schedule.hpp"

#include <cmath>

#include "gyroflip/core/error.hpp"

namespace gyroflip::rig {
namespace {

std::size_t slots(double duration_s, double t_conv_s) {
  return static_cast<std::size_t>(std::ceil(duration_s / t_conv_s - 1e-9));
}

// Appends the conversions of a turn from `from_deg` by `turn` (backwards when `sign` is -1) plus
// the settling time.
void add_turn(std::vector<phase>& out, double from_deg, const turn_profile& turn, double sign,
              double settle_s, double t_conv_s) {
  const std::size_t n = slots(turn.duration_s(), t_conv_s) + slots(settle_s, t_conv_s);
  for (std::size_t i = 0; i < n; ++i) {
    const double t0 = static_cast<double>(i) * t_conv_s;
    const double a0 = turn.angle_at(t0);
    const double a1 = turn.angle_at(t0 + t_conv_s);
    phase p;
    p.angle_deg = from_deg + sign * turn.angle_at(t0 + 0.5 * t_conv_s);
    p.table_rate_dps = sign * (a1 - a0) / t_conv_s;
    p.moving = t0 < turn.duration_s();
    out.push_back(p);
  }
}

}  // namespace

result<schedule> schedule::make(const schedule_params& s, const stepper_params& m,
                                double t_conv_s) {
  if (s.n_avg < 1) return parameter_error("n_avg", "conversions per dwell (n_avg) must be >= 1");
  if (!(s.settle_s >= 0.0) || !std::isfinite(s.settle_s))
    return usage_error("settle time must be >= 0 s");
  if (!std::isfinite(s.pos_a_deg) || !std::isfinite(s.pos_b_deg)) {
    return usage_error("positions must be finite");
  }
  if (!s.flip) {  // one dwell at A after another: a cycle is one dwell
    schedule out;
    out.p_ = s;
    out.t_conv_s_ = t_conv_s;
    out.phases_.assign(static_cast<std::size_t>(s.n_avg), phase{s.pos_a_deg, 0.0, false, 0});
    return out;
  }
  const double ab =
      s.pos_b_deg - s.pos_a_deg - 360.0 * std::floor((s.pos_b_deg - s.pos_a_deg) / 360.0);
  if (ab == 0.0) return usage_error("the two positions must differ (or do not flip at all)");
  auto turn_ab = turn_profile::make(m, ab);
  if (!turn_ab) return turn_ab.err();
  auto turn_ba = turn_profile::make(m, s.one_way ? 360.0 - ab : ab);
  if (!turn_ba) return turn_ba.err();
  schedule out;
  out.p_ = s;
  out.t_conv_s_ = t_conv_s;
  out.turn_ab_s_ = turn_ab->duration_s();
  out.turn_ba_s_ = turn_ba->duration_s();
  const auto dwell = [&](double angle_deg, std::int8_t slot) {
    for (int i = 0; i < s.n_avg; ++i) out.phases_.push_back({angle_deg, 0.0, false, slot});
  };
  dwell(s.pos_a_deg, 0);
  add_turn(out.phases_, s.pos_a_deg, *turn_ab, 1.0, s.settle_s, t_conv_s);
  dwell(s.pos_a_deg + ab, 1);
  add_turn(out.phases_, s.pos_a_deg + ab, *turn_ba, s.one_way ? 1.0 : -1.0, s.settle_s, t_conv_s);
  return out;
}

}  // namespace gyroflip::rig
