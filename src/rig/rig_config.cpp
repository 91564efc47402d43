/// \file
/// \brief The rig's settings and their one validation (see rig_config.hpp).
#include "gyroflip/rig/rig_config.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "firmware/protocol/budget.hpp"
#include "gyroflip/core/error.hpp"

namespace gyroflip::rig {
namespace {

bool in(double v, double lo, double hi) {
  return v >= lo && v <= hi;
}

// A value in [lo, hi] with at most 1e-9 of rounding from a whole number of `step`.
// A table that names an angle twice is a visiting order already (written out by the user or by
// device_visits): it is visited as written.
bool names_an_angle_twice(const std::vector<double>& positions_deg) {
  for (std::size_t i = 0; i < positions_deg.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (positions_deg[i] == positions_deg[j]) return true;
  return false;
}

bool whole(double v, double step) {
  const double k = v / step;
  return std::isfinite(k) && std::abs(k - std::round(k)) <= 1e-9 * std::max(1.0, std::abs(k));
}

std::string range_text(double lo, double hi) {
  return fmt::format("{:g}..{:g}", lo, hi);
}

status out_of(std::string_view field, std::string_view what, double v, double lo, double hi) {
  return parameter_error(field,
                         fmt::format("{} must be in {}; got {:g}", what, range_text(lo, hi), v));
}

status check_positions(const rig_config& c) {
  const auto n = c.positions_deg.size();
  if (n < 2 || n > protocol::max_positions)
    return parameter_error(
        "positions_deg",
        fmt::format("the angle table holds 2 to {} positions; got {}", protocol::max_positions, n));
  const double step_deg = 360.0 / c.steps_per_rev;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = c.positions_deg[i];
    if (!(a >= 0.0 && a < 360.0))
      return parameter_error("positions_deg",
                             fmt::format("position {} at {:g} deg: angles are in [0, 360)", i, a));
    if (!whole(a, step_deg))
      return parameter_error(
          "positions_deg",
          fmt::format("position {} at {:g} deg is not a whole number of the table's {:g}-deg "
                      "steps ({} steps per revolution)",
                      i, a, step_deg, c.steps_per_rev));
    if (!whole(a, 0.01))
      return parameter_error("positions_deg",
                             fmt::format("position {} at {:g} deg: the device keeps angles in "
                                         "hundredths of a degree",
                                         i, a));
    if (a == c.positions_deg[(i + 1) % n])
      return parameter_error(
          "positions_deg",
          fmt::format("positions {} and {} are both at {:g} deg: the table would not turn", i,
                      (i + 1) % n, a));
  }
  return ok();
}

}  // namespace

int rig_config::position_steps(std::size_t i) const {
  return static_cast<int>(std::lround(positions_deg.at(i) * steps_per_rev / 360.0));
}

position_table rig_config::table() const {
  std::vector<std::int32_t> steps;
  for (std::size_t i = 0; i < positions_deg.size(); ++i) steps.push_back(position_steps(i));
  auto t = position_table::of_visits(positions_deg, steps);
  return t ? std::move(*t) : position_table{};
}

// Each field against the device's range (docs/PROTOCOL.md, CONFIGURE; firmware/protocol/
// budget.hpp), then the device's own check as the last word (link budget included).
status rig_config::check(double mclk_hz) const {
  if (!in(n_avg, 1, protocol::max_n_avg))
    return out_of("n_avg", "conversions per dwell (n_avg)", n_avg, 1, protocol::max_n_avg);
  if (!in(n_temp, 0, protocol::max_n_temp))
    return out_of("n_temp", "temperature conversions per dwell", n_temp, 0, protocol::max_n_temp);
  if (!in(settle_s, 0.0, 65.535) || !whole(settle_s, 1e-3))
    return parameter_error("settle_s", fmt::format("the settling time must be 0..65.535 s in "
                                                   "whole ms; got {:g} s",
                                                   settle_s));
  if (!in(steps_per_rev, 4, 32767))
    return out_of("steps_per_rev", "steps per revolution", steps_per_rev, 4, 32767);
  if (!in(max_rate_sps, 1, protocol::max_step_rate_sps))
    return out_of("max_rate_sps", "the top step rate (steps/s)", max_rate_sps, 1,
                  protocol::max_step_rate_sps);
  if (!in(start_rate_sps, 1, max_rate_sps))
    return out_of("start_rate_sps", "the start step rate (steps/s)", start_rate_sps, 1,
                  max_rate_sps);
  if (!in(accel_sps2, 1, 65535))
    return out_of("accel_sps2", "the ramp (steps/s^2)", accel_sps2, 1, 65535);
  if (!in(filter_word, ad7739::fw_min, ad7739::fw_max))
    return out_of("filter_word", "the AD7739 filter word", filter_word, ad7739::fw_min,
                  ad7739::fw_max);
  if (!in(status_period_s, 0.0, protocol::max_status_period_ms / 1e3) ||
      !whole(status_period_s, 1e-3))
    return parameter_error(
        "status_period_s",
        fmt::format("the STATUS period must be 0..{:g} s in whole ms; got {:g} s",
                    protocol::max_status_period_ms / 1e3, status_period_s));
  if (!in(flip_motor, 0, 1)) return out_of("flip_motor", "the flip motor", flip_motor, 0, 1);
  if (!in(gyro_channel, 0, 3) || !in(temp_channel, 0, 3) || gyro_channel == temp_channel)
    return parameter_error("gyro_channel", "the gyro and temperature channels: two of 0..3");
  if (auto s = check_positions(*this); !s) return s;
  const auto m = to_configure();
  if (compensate && !protocol::is_method_pair(m))
    return parameter_error("compensate",
                           "on-board compensation needs the method's pair: two positions 180 deg "
                           "apart");
  const auto mclk = static_cast<std::uint32_t>(std::lround(mclk_hz));
  if (const auto bps = protocol::worst_bytes_per_s(m, mclk); bps > protocol::link_bytes_per_s)
    return parameter_error(
        "n_avg", fmt::format("these settings send up to {} B/s, beyond the link's {} B/s "
                             "(115200 b/s): average more conversions per dwell, turn slower or "
                             "leave RAW off",
                             bps, protocol::link_bytes_per_s));
  if (protocol::check_configure(m, mclk) != protocol::status::ok)
    return parameter_error("configure", "the device would refuse these settings");
  return ok();
}

protocol::configure_msg rig_config::to_configure() const {
  protocol::configure_msg c;
  c.n_avg = static_cast<std::uint16_t>(n_avg);
  c.n_temp = static_cast<std::uint8_t>(n_temp);
  c.settle_ms = static_cast<std::uint16_t>(std::lround(settle_s * 1e3));
  c.n_positions = static_cast<std::uint8_t>(positions_deg.size());
  for (std::size_t i = 0; i < positions_deg.size() && i < protocol::max_positions; ++i) {
    c.pos_steps[i] = static_cast<std::int16_t>(position_steps(i));
    c.pos_cdeg[i] = static_cast<std::uint16_t>(std::lround(positions_deg[i] * 100.0));
  }
  c.steps_per_rev = static_cast<std::uint16_t>(steps_per_rev);
  c.step_rate_sps = static_cast<std::uint16_t>(max_rate_sps);
  c.start_rate_sps = static_cast<std::uint16_t>(start_rate_sps);
  c.ramp_sps2 = static_cast<std::uint16_t>(accel_sps2);
  c.filter_word = static_cast<std::uint8_t>(filter_word);
  c.flags = static_cast<std::uint8_t>(
      (chop ? protocol::cfg_chop : 0) | (raw ? protocol::cfg_raw : 0) |
      (one_way ? protocol::cfg_one_way : 0) | (home ? protocol::cfg_home : 0) |
      (compensate ? protocol::cfg_compensate : 0) | (hold_coils ? protocol::cfg_hold_coils : 0));
  c.flip_motor = static_cast<std::uint8_t>(flip_motor);
  c.other_motor = static_cast<std::uint8_t>(other_motor);
  c.gyro_channel = static_cast<std::uint8_t>(gyro_channel);
  c.temp_channel = static_cast<std::uint8_t>(temp_channel);
  c.status_period_ms = static_cast<std::uint16_t>(std::lround(status_period_s * 1e3));
  return c;
}

result<rig_config> rig_config::from_configure(const protocol::configure_msg& m) {
  rig_config c;
  c.n_avg = m.n_avg;
  c.n_temp = m.n_temp;
  c.settle_s = m.settle_ms / 1e3;
  c.positions_deg.clear();
  if (m.n_positions < 2 || m.n_positions > protocol::max_positions)
    return parameter_error("n_positions",
                           fmt::format("CONFIGURE with {} positions", m.n_positions));
  for (std::uint8_t i = 0; i < m.n_positions; ++i) c.positions_deg.push_back(m.pos_cdeg[i] / 100.0);
  c.steps_per_rev = m.steps_per_rev;
  c.max_rate_sps = m.step_rate_sps;
  c.start_rate_sps = m.start_rate_sps;
  c.accel_sps2 = m.ramp_sps2;
  c.filter_word = m.filter_word;
  c.chop = (m.flags & protocol::cfg_chop) != 0;
  c.raw = (m.flags & protocol::cfg_raw) != 0;
  c.one_way = (m.flags & protocol::cfg_one_way) != 0;
  c.home = (m.flags & protocol::cfg_home) != 0;
  c.compensate = (m.flags & protocol::cfg_compensate) != 0;
  c.hold_coils = (m.flags & protocol::cfg_hold_coils) != 0;
  c.flip_motor = m.flip_motor;
  if (m.other_motor > 3) return parameter_error("other_motor", "an other_motor value of 0..3");
  c.other_motor = static_cast<protocol::other_motor>(m.other_motor);
  c.gyro_channel = m.gyro_channel;
  c.temp_channel = m.temp_channel;
  c.status_period_s = m.status_period_ms / 1e3;
  // The steps stand where the angles say (a table that agrees with itself).
  for (std::uint8_t i = 0; i < m.n_positions; ++i)
    if (c.position_steps(i) != m.pos_steps[i] &&
        c.position_steps(i) - c.steps_per_rev != m.pos_steps[i])
      return parameter_error(
          "pos_steps", fmt::format("position {}: step {} does not stand for {:g} deg at {} steps "
                                   "per revolution",
                                   i, m.pos_steps[i], c.positions_deg[i], c.steps_per_rev));
  if (auto s = c.check(); !s) return s.err();
  return c;
}

stepper_params rig_config::stepper() const {
  return {steps_per_rev, static_cast<double>(start_rate_sps), static_cast<double>(max_rate_sps),
          static_cast<double>(accel_sps2)};
}

result<std::vector<double>> device_visits(const std::vector<double>& positions_deg,
                                          device_order order, bool one_way) {
  const std::size_t n = positions_deg.size();
  const bool repeats = names_an_angle_twice(positions_deg);
  const std::size_t back = n >= 2 ? 2 * n - 2 : n;
  const bool fits = n > 2 && back <= protocol::max_positions && !one_way;
  if (order == device_order::there_and_back) {
    if (repeats)
      return usage_error(
          "the there-and-back order: the positions name an angle twice (a visiting order "
          "already): give each position once");
    if (one_way)
      return usage_error(
          "the there-and-back order turns back at each end; one-way turns cannot: visit the "
          "positions in cycle order");
    if (back > protocol::max_positions)
      return usage_error(fmt::format(
          "the there-and-back order: {} positions take {} entries of the device's angle table, "
          "which holds {}: at most {} positions, or the cycle order",
          n, back, protocol::max_positions, protocol::max_positions / 2 + 1));
  }
  const bool go_back = order == device_order::there_and_back ||
                       (order == device_order::automatic && fits && !repeats);
  if (!go_back) return positions_deg;
  std::vector<double> out(positions_deg);
  for (std::size_t i = n - 1; i-- > 1;) out.push_back(positions_deg[i]);
  return out;
}

schedule_params rig_config::schedule(bool flip, visit_order order) const {
  schedule_params s;
  if (names_an_angle_twice(positions_deg)) {
    s.visits = positions_deg;
  } else if (positions_deg.size() > 2 || order == visit_order::sweep) {
    s.visits = order == visit_order::cycle ? positions_deg : sweep_order(positions_deg);
  }
  s.n_avg = n_avg;
  s.settle_s = settle_s;
  s.pos_a_deg = positions_deg.empty() ? 0.0 : positions_deg[0];
  s.pos_b_deg = positions_deg.size() < 2 ? 180.0 : positions_deg[1];
  s.flip = flip;
  s.one_way = one_way;
  return s;
}

}  // namespace gyroflip::rig
