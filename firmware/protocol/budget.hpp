/// \file
/// \brief What a device accepts in CONFIGURE, and the serial link's budget (docs/PROTOCOL.md,
/// "CONFIGURE" and "Link budget"): the one validation the firmware, the host library's rig
/// configuration and the recorder share. Bytes per second count each frame's exact size on the
/// wire (line_bytes: COBS adds one byte to a frame shorter than 254 bytes, the line code doubles
/// every byte, two delimiters end it). The device refuses a CONFIGURE whose worst case exceeds
/// the link; the test suite checks that the paper's configuration keeps >= 30 % headroom.
#pragma once

#include <stdint.h>

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "firmware/protocol/status.hpp"

namespace gyroflip::protocol {

/// Limits of a CONFIGURE (beyond its field types).
inline constexpr uint16_t max_n_avg = 65535;
inline constexpr uint8_t max_n_temp = 64;
inline constexpr uint16_t max_step_rate_sps = 5000;
inline constexpr uint16_t max_status_period_ms = 60000;

/// 115200 b/s, 8N1: 10 bits on the line per byte.
inline constexpr uint32_t link_bytes_per_s = 115200 / 10;

/// Payload bytes of each device-to-host message (their layouts in messages.hpp), and of
/// CONFIGURE.
inline constexpr uint32_t configure_payload = 54;
inline constexpr uint32_t info_payload = 92;
inline constexpr uint32_t dwell_payload = 49;
inline constexpr uint32_t status_payload = 39;
inline constexpr uint32_t compensated_payload = 13;
[[nodiscard]] constexpr uint32_t raw_payload(uint32_t codes) {
  return 5 + 3 * codes;
}

/// Wire bytes of the frames of one dwell of `n_avg` gyro conversions: DWELL, RAW blocks when
/// `raw`, and half a COMPENSATED (one per cycle of two dwells) when `compensate`, x 2 (so the
/// half frame stays an integer).
[[nodiscard]] constexpr uint32_t dwell_bytes_x2(uint32_t n_avg, bool raw, bool compensate) {
  uint32_t b = 2 * static_cast<uint32_t>(line_bytes(dwell_payload));
  if (raw) {
    constexpr uint32_t per = raw_msg::max_codes;
    b += 2 * (n_avg / per) * static_cast<uint32_t>(line_bytes(raw_payload(per)));
    if (n_avg % per != 0) b += 2 * static_cast<uint32_t>(line_bytes(raw_payload(n_avg % per)));
  }
  if (compensate) b += static_cast<uint32_t>(line_bytes(compensated_payload));
  return b;
}

/// Steps of the turn from position `from` to the next one (index from + 1, or 0 after the last)
/// in the direction the device turns: straight there, or with one-way turns always in the
/// direction of position 0 -> 1 (a rotary joint's wiring stays untwisted only this way round).
[[nodiscard]] constexpr int32_t turn_steps(const configure_msg& c, int32_t from_steps,
                                           uint8_t to_position) {
  const int32_t target = c.pos_steps[to_position % max_positions];
  if ((c.flags & cfg_one_way) == 0) return target - from_steps;
  const int32_t rev = c.steps_per_rev;
  const int32_t dir = c.pos_steps[1] > c.pos_steps[0] ? 1 : -1;
  int32_t d = (dir * (target - from_steps)) % rev;
  if (d < 0) d += rev;
  return dir * d;
}

/// The most bytes per second a configuration can send: every dwell as short as it can be (its
/// (n_avg + n_temp) conversions at `mclk_hz`, the shortest turn of the sequence at the top step
/// rate without the ramp, and the settling time), plus STATUS. Lower bounds of each time, so an
/// upper bound of the rate.
[[nodiscard]] constexpr uint32_t worst_bytes_per_s(const configure_msg& c, uint32_t mclk_hz) {
  const uint64_t conv_mclk = ad7739::conversion_mclk((c.flags & cfg_chop) != 0, c.filter_word);
  const uint64_t conv_ns = conv_mclk * (uint64_t{c.n_avg} + c.n_temp) * 1000000000u / mclk_hz;
  uint64_t steps = 0xFFFFFFFFu;
  const uint8_t n =
      c.n_positions < 2 ? 2 : (c.n_positions > max_positions ? max_positions : c.n_positions);
  for (uint8_t i = 0; i < n; ++i) {
    const int32_t d = turn_steps(c, c.pos_steps[i], static_cast<uint8_t>((i + 1) % n));
    const uint64_t s = static_cast<uint64_t>(d < 0 ? -d : d);
    if (s < steps) steps = s;
  }
  const uint64_t turn_ns = c.step_rate_sps == 0 ? 0 : steps * 1000000000u / c.step_rate_sps;
  const uint64_t dwell_ns = conv_ns + turn_ns + uint64_t{c.settle_ms} * 1000000u;
  const uint64_t x2 =
      dwell_bytes_x2(c.n_avg, (c.flags & cfg_raw) != 0, (c.flags & cfg_compensate) != 0);
  uint64_t bps =
      dwell_ns == 0 ? 0xFFFFFFFFu : (x2 * 1000000000u + 2 * dwell_ns - 1) / (2 * dwell_ns);
  if (c.status_period_ms != 0)
    bps +=
        (uint64_t{line_bytes(status_payload)} * 1000 + c.status_period_ms - 1) / c.status_period_ms;
  return bps > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<uint32_t>(bps);
}

/// Whether a device accepts configuration `c` (status::ok) or refuses it (status::bad_arg):
/// every field in its range (docs/PROTOCOL.md, CONFIGURE), 2..8 distinct consecutive
/// positions within one revolution, angles below 360 deg, on-board compensation only for the
/// method's pair (two positions 180 deg apart), and the worst case within the link.
[[nodiscard]] constexpr status check_configure(const configure_msg& c, uint32_t mclk_hz) {
  if (c.n_positions < 2 || c.n_positions > max_positions || c.steps_per_rev < 4) {
    return status::bad_arg;
  }
  for (uint8_t i = 0; i < c.n_positions; ++i) {
    const int32_t p = c.pos_steps[i];
    const int32_t next = c.pos_steps[(i + 1) % c.n_positions];
    if (p == next || p >= c.steps_per_rev || -p >= c.steps_per_rev ||
        c.pos_cdeg[i] >= centidegrees_per_turn) {
      return status::bad_arg;
    }
  }
  const bool pair = is_method_pair(c);
  const bool ok = c.n_avg >= 1 && c.n_temp <= max_n_temp && c.step_rate_sps >= 1 &&
                  c.step_rate_sps <= max_step_rate_sps && c.start_rate_sps >= 1 &&
                  c.start_rate_sps <= c.step_rate_sps && c.ramp_sps2 >= 1 &&
                  c.filter_word >= ad7739::fw_min && c.filter_word <= ad7739::fw_max &&
                  (c.flags & ~cfg_all) == 0 && c.flip_motor <= 1 && c.other_motor <= 3 &&
                  c.gyro_channel <= 3 && c.temp_channel <= 3 && c.gyro_channel != c.temp_channel &&
                  c.status_period_ms <= max_status_period_ms &&
                  ((c.flags & cfg_compensate) == 0 || pair);
  if (!ok) return status::bad_arg;
  // The link must carry the worst case, or frames would be dropped by design.
  return worst_bytes_per_s(c, mclk_hz) <= link_bytes_per_s ? status::ok : status::bad_arg;
}

}  // namespace gyroflip::protocol
