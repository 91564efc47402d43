/// \file
/// \brief The cycle layout in conversion slots (see schedule.hpp).
#include "gyroflip/rig/schedule.hpp"

#include <algorithm>
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

// The settle residual of the turn that starts at slot `turn_at` (lasting `duration` s, in
// direction `dir`, its next dwell at slot `dwell_at`), added to every slot from the turn to the
// next turn's start `until` (the cycle of n slots wraps).
void add_residual(std::vector<phase>& phases, const schedule_params& s, double t_conv_s,
                  std::size_t turn_at, std::size_t dwell_at, double duration, int dir,
                  std::size_t until) {
  const double release =
      s.release_before_dwell_s < 0.0 ? s.settle_s / 2.0 : s.release_before_dwell_s;
  const std::size_t n = phases.size();
  const double t_last = static_cast<double>(turn_at) * t_conv_s + duration;
  double t_dwell = static_cast<double>(dwell_at) * t_conv_s;
  if (dwell_at < turn_at) t_dwell += static_cast<double>(n) * t_conv_s;  // the next cycle's
  const double t_release = std::max(t_last, t_dwell - release) - t_last;
  for (std::size_t k = turn_at; k != until; k = (k + 1) % n) {
    double t0 = static_cast<double>(k) * t_conv_s - t_last;
    if (k < turn_at) t0 += static_cast<double>(n) * t_conv_s;  // wrapped past the cycle's end
    const double t1 = t0 + t_conv_s;
    const double a0 = s.settle.residual_deg(t0, t_release, dir);
    const double a1 = s.settle.residual_deg(t1, t_release, dir);
    // The rate only: the dwell keeps its table position's label (a residual of a fraction of
    // a step changes the Earth and gravity terms by parts in 10^5).
    phases[k].table_rate_dps += (a1 - a0) / t_conv_s;
  }
}

// The cycle of more than two positions: a dwell per visit, a turn (and settling) between
// visits at different angles.
status make_visits(const schedule_params& s, const stepper_params& m, double t_conv_s,
                   std::vector<phase>& phases, double& first_turn_s) {
  struct turn_at {
    std::size_t slot, next_dwell;
    double duration_s;
    int dir;
  };
  std::vector<turn_at> turns;
  const std::size_t n = s.visits.size();
  if (n < 2 || n > 127) return usage_error("a cycle visits 2 to 127 positions");
  for (const double a : s.visits)
    if (!(a >= 0.0 && a < 360.0)) return usage_error("a visited angle is in [0, 360)");
  double at_deg = s.visits[0];  // unwrapped (one-way turns keep going round)
  first_turn_s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < s.n_avg; ++k)
      phases.push_back({at_deg, 0.0, false, static_cast<std::int8_t>(i)});
    const double next = s.visits[(i + 1) % n];
    const double here = at_deg - 360.0 * std::floor(at_deg / 360.0);
    if (next == here) continue;
    double by = next - here;
    if (s.one_way && by < 0.0) by += 360.0;
    auto turn = turn_profile::make(m, std::abs(by));
    if (!turn) return turn.err();
    if (first_turn_s == 0.0) first_turn_s = turn->duration_s();
    const int dir = by < 0.0 ? -1 : 1;
    turns.push_back({phases.size(), 0, turn->duration_s(), dir});
    add_turn(phases, at_deg, *turn, dir, s.settle_s, t_conv_s);
    turns.back().next_dwell = phases.size();  // the cycle's end is its first dwell: wrapped below
    at_deg += by;
  }
  if (turns.empty()) return usage_error("the visited positions must differ (or do not flip)");
  if (s.settle.on())
    for (std::size_t i = 0; i < turns.size(); ++i) {
      const auto& t = turns[i];
      add_residual(phases, s, t_conv_s, t.slot, t.next_dwell % phases.size(), t.duration_s, t.dir,
                   turns[(i + 1) % turns.size()].slot);
    }
  return ok();
}

}  // namespace

std::vector<double> sweep_order(const std::vector<double>& angles_deg) {
  std::vector<double> out(angles_deg);
  out.insert(out.end(), angles_deg.rbegin(), angles_deg.rend());
  return out;
}

double schedule::dead_time_per_dwell_s() const noexcept {
  std::size_t dead = 0;
  for (const auto& p : phases_) dead += p.dwell < 0 ? 1U : 0U;
  return static_cast<double>(dead) * t_conv_s_ / dwells_per_cycle();
}

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
    out.p_.visits.clear();
    return out;
  }
  if (!s.visits.empty()) {
    schedule out;
    out.p_ = s;
    out.t_conv_s_ = t_conv_s;
    auto made = make_visits(s, m, t_conv_s, out.phases_, out.turn_ab_s_);
    if (!made) return made.err();
    out.turn_ba_s_ = out.turn_ab_s_;
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
  const std::size_t turn_ab_at = out.phases_.size();
  add_turn(out.phases_, s.pos_a_deg, *turn_ab, 1.0, s.settle_s, t_conv_s);
  const std::size_t dwell_b_at = out.phases_.size();
  dwell(s.pos_a_deg + ab, 1);
  const std::size_t turn_ba_at = out.phases_.size();
  add_turn(out.phases_, s.pos_a_deg + ab, *turn_ba, s.one_way ? 1.0 : -1.0, s.settle_s, t_conv_s);
  if (s.settle.on()) {
    // Each turn's residual runs from its last step to the next turn's start (the cycle wraps:
    // the B -> A turn's runs through the dwell at A that opens the cycle).
    add_residual(out.phases_, s, t_conv_s, turn_ab_at, dwell_b_at, turn_ab->duration_s(), 1,
                 turn_ba_at);
    add_residual(out.phases_, s, t_conv_s, turn_ba_at, 0, turn_ba->duration_s(), s.one_way ? 1 : -1,
                 turn_ab_at);
  }
  return out;
}

}  // namespace gyroflip::rig
