/// \file
/// \brief The serial link's budget (docs/PROTOCOL.md "Link budget"): bytes per second a
/// configuration sends at most, counted from the wire size of each frame (protocol::wire_bytes:
/// exact, as every frame is shorter than 254 bytes and COBS adds one byte to it). The device
/// refuses a CONFIGURE whose worst case exceeds the link; the test suite checks that the
/// paper's configuration keeps >= 30 % headroom.
#pragma once

#include <stdint.h>

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/protocol/frame.hpp"

namespace gyroflip::fw {

/// 115200 b/s, 8N1: 10 bits on the line per byte.
inline constexpr uint32_t link_bytes_per_s = 115200 / 10;

/// Payload bytes of each device-to-host message (their layouts in messages.hpp).
inline constexpr uint32_t dwell_payload = 49;
inline constexpr uint32_t status_payload = 22;
inline constexpr uint32_t compensated_payload = 13;
inline constexpr uint32_t raw_payload(uint32_t codes) {
  return 5 + 3 * codes;
}

/// Wire bytes of the frames of one dwell of `n_avg` gyro conversions: DWELL, RAW blocks when
/// `raw`, and half a COMPENSATED (one per cycle of two dwells) when `compensate`, x 2 (so the
/// half frame stays an integer).
[[nodiscard]] constexpr uint32_t dwell_bytes_x2(uint32_t n_avg, bool raw, bool compensate) {
  uint32_t b = 2 * static_cast<uint32_t>(protocol::wire_bytes(dwell_payload));
  if (raw) {
    constexpr uint32_t per = protocol::raw_msg::max_codes;
    b += 2 * (n_avg / per) * static_cast<uint32_t>(protocol::wire_bytes(raw_payload(per)));
    if (n_avg % per != 0)
      b += 2 * static_cast<uint32_t>(protocol::wire_bytes(raw_payload(n_avg % per)));
  }
  if (compensate) b += static_cast<uint32_t>(protocol::wire_bytes(compensated_payload));
  return b;
}

/// The most bytes per second a configuration can send: every dwell as short as it can be (its
/// (n_avg + n_temp) conversions at `mclk_hz`, the turn after it at the top step rate without
/// the ramp, and the settling time), plus STATUS. Lower bounds of each time, so an upper bound
/// of the rate.
[[nodiscard]] constexpr uint32_t worst_bytes_per_s(const protocol::configure_msg& c,
                                                   uint32_t mclk_hz) {
  const uint64_t conv_mclk =
      ad7739::conversion_mclk((c.flags & protocol::cfg_chop) != 0, c.filter_word);
  const uint64_t conv_ns = conv_mclk * (uint64_t{c.n_avg} + c.n_temp) * 1000000000u / mclk_hz;
  const int32_t d = int32_t{c.pos_b_steps} - c.pos_a_steps;
  const uint64_t span = static_cast<uint64_t>(d < 0 ? -d : d);
  const uint64_t rest = c.steps_per_rev > span ? c.steps_per_rev - span : 0;
  const uint64_t steps = (c.flags & protocol::cfg_one_way) != 0 && rest < span ? rest : span;
  const uint64_t turn_ns = c.step_rate_sps == 0 ? 0 : steps * 1000000000u / c.step_rate_sps;
  const uint64_t dwell_ns = conv_ns + turn_ns + uint64_t{c.settle_ms} * 1000000u;
  const uint64_t x2 = dwell_bytes_x2(c.n_avg, (c.flags & protocol::cfg_raw) != 0,
                                     (c.flags & protocol::cfg_compensate) != 0);
  uint64_t bps =
      dwell_ns == 0 ? 0xFFFFFFFFu : (x2 * 1000000000u + 2 * dwell_ns - 1) / (2 * dwell_ns);
  if (c.status_period_ms != 0)
    bps += (uint64_t{protocol::wire_bytes(status_payload)} * 1000 + c.status_period_ms - 1) /
           c.status_period_ms;
  return bps > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<uint32_t>(bps);
}

}  // namespace gyroflip::fw
