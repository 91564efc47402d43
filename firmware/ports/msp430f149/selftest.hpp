/// \file
/// \brief The MSP430 self-test image's mailbox (selftest.cpp; tests/firmware/test_msp430_sim.cpp):
/// the host writes records of operations and operands to simulator memory, the image computes
/// each with the very compiler, flags and runtime helpers of the shipped image and writes the
/// results beside them; the host compares them bit for bit with the same computation on the
/// host. The mailbox lies in memory that the MSP430 simulator has and the F149 does not (the
/// simulator's 64 KB are all RAM): this image runs only there. Freestanding.
#pragma once

#include <stdint.h>

#include "firmware/core/device.hpp"
#include "firmware/core/processing.hpp"
#include "firmware/core/timebase.hpp"
#include "firmware/drivers/stepper/stepper.hpp"
#include "firmware/protocol/budget.hpp"
#include "firmware/util/intmath.hpp"

namespace gyroflip::fw::selftest {

/// The image's code ends below in_addr (the test checks it).
/// Input: u16 count, then `count` records of in_record_bytes: u8 op, u8 0, u64 a, u64 b (LE).
inline constexpr uint16_t in_addr = 0x5800;
inline constexpr uint16_t in_record_bytes = 18;
/// Output: a record of out_record_bytes per input record: u64 r0, u64 r1 (LE).
inline constexpr uint16_t out_addr = 0xA000;
inline constexpr uint16_t out_record_bytes = 16;
inline constexpr uint16_t max_records = 1000;
static_assert(in_addr + 2 + uint32_t{in_record_bytes} * max_records <= out_addr &&
              out_addr + uint32_t{out_record_bytes} * max_records <= 0xFFE0);

/// What a record asks for. a and b are the operands, reinterpreted as the operation's types
/// (the low bits for narrower ones); results go to r0 (and r1), sign- or zero-extended.
enum class op : uint8_t {
  // runtime helpers (the compiler calls them for these C++ operators)
  mul16 = 1,  ///< u16 a * b
  divu16,     ///< u16 a / b
  remu16,     ///< u16 a % b
  divi16,     ///< i16 a / b
  remi16,     ///< i16 a % b
  mul32,      ///< u32 a * b
  divu32,
  remu32,
  divi32,
  remi32,
  mul64,  ///< u64 a * b
  divu64,
  remu64,
  divi64,
  remi64,
  shl32,  ///< u32 a << b
  shr32,  ///< u32 a >> b
  sar32,  ///< i32 a >> b
  shl64,
  shr64,
  sar64,
  // the firmware's own arithmetic
  mean_q8,        ///< mean_q8(i64 a, u32 b)
  make_cycle,     ///< make_cycle(i32 a, i32 b): r0 rate, r1 bias
  compensate,     ///< saturate(i32 a - i32 b): r = y - dN as COMPENSATED carries it
  isqrt,          ///< isqrt(u64 a)
  div_round,      ///< div_round(i64 a, u64 b)
  cal_begin,      ///< calibrator.begin(u16 a)
  cal_add,        ///< calibrator.add(i32 a, u8 b): r0 = 1 when complete
  cal_result,     ///< r0 = delta_n_q8 (i32) | cycles << 32; r1 = std_q8 | flags << 32
  step_interval,  ///< step_interval({a u16, a>>16 u16, a>>32 u16}, b u32, b>>32 u32, 32768)
  ms_to_ticks,    ///< ms_to_ticks(u32 a, u32 b)
  mclk_to_ticks,  ///< mclk_to_ticks(u32 a, u32 b, u32 a >> 32)
  link_budget,    ///< worst_bytes_per_s of CONFIGURE{n_avg a, n_temp a>>16, filter_word a>>24,
                  ///< flags a>>32, settle_ms a>>40, step_rate b, pos_b b>>16, status b>>32}
                  ///< at the nominal MCLK; r1 = check_config's status
};

struct results {
  uint64_t r0 = 0;
  uint64_t r1 = 0;
  bool operator==(const results&) const = default;
};

namespace detail {

constexpr uint64_t sx(int64_t v) {
  return static_cast<uint64_t>(v);
}

// The runtime helpers' operations. Written to mean the same on the MSP430 (16-bit int) and on
// the host (32-bit int): 16-bit products go through `unsigned` (16 bits there: the 16-bit
// helper; 32 bits here: no signed overflow), narrower results are cast back. The caller keeps
// to what C++ defines (no division by 0, no most-negative / -1, shifts below the width).
inline results helper(op o, uint64_t a, uint64_t b) {
  const auto a16 = static_cast<uint16_t>(a), b16 = static_cast<uint16_t>(b);
  const auto a32 = static_cast<uint32_t>(a), b32 = static_cast<uint32_t>(b);
  const auto i16a = static_cast<int16_t>(a16), i16b = static_cast<int16_t>(b16);
  const auto i32a = static_cast<int32_t>(a32), i32b = static_cast<int32_t>(b32);
  const auto i64a = static_cast<int64_t>(a), i64b = static_cast<int64_t>(b);
  switch (o) {
    case op::mul16:
      return {static_cast<uint16_t>(static_cast<unsigned>(a16) * static_cast<unsigned>(b16))};
    case op::divu16:
      return {static_cast<uint16_t>(a16 / b16)};
    case op::remu16:
      return {static_cast<uint16_t>(a16 % b16)};
    case op::divi16:
      return {sx(static_cast<int16_t>(i16a / i16b))};
    case op::remi16:
      return {sx(static_cast<int16_t>(i16a % i16b))};
    case op::mul32:
      return {static_cast<uint32_t>(a32 * b32)};
    case op::divu32:
      return {a32 / b32};
    case op::remu32:
      return {a32 % b32};
    case op::divi32:
      return {sx(i32a / i32b)};
    case op::remi32:
      return {sx(i32a % i32b)};
    case op::mul64:
      return {a * b};
    case op::divu64:
      return {a / b};
    case op::remu64:
      return {a % b};
    case op::divi64:
      return {sx(i64a / i64b)};
    case op::remi64:
      return {sx(i64a % i64b)};
    case op::shl32:
      return {static_cast<uint32_t>(a32 << b16)};
    case op::shr32:
      return {a32 >> b16};
    case op::sar32:
      return {sx(i32a >> b16)};
    case op::shl64:
      return {a << b16};
    case op::shr64:
      return {a >> b16};
    case op::sar64:
      return {sx(i64a >> b16)};
    default:
      return {};
  }
}

}  // namespace detail

/// The answer to one record: the same source on the MSP430 (selftest.cpp) and on the host (the
/// test), so that any difference is the compiler's, the runtime helpers' or the machine's.
inline results compute(op o, uint64_t a, uint64_t b, calibrator& cal) {
  using detail::sx;
  const auto a32 = static_cast<uint32_t>(a), b32 = static_cast<uint32_t>(b);
  switch (o) {
    case op::mean_q8:
      return {sx(mean_q8(static_cast<int64_t>(a), b32))};
    case op::make_cycle: {
      const cycle_q8 c = make_cycle(static_cast<int32_t>(a32), static_cast<int32_t>(b32));
      return {sx(c.rate_q8), sx(c.bias_q8)};
    }
    case op::compensate:
      return {sx(saturate(int64_t{static_cast<int32_t>(a32)} - static_cast<int32_t>(b32)))};
    case op::isqrt:
      return {fw::isqrt(a)};
    case op::div_round:
      return {sx(fw::div_round(static_cast<int64_t>(a), b))};
    case op::cal_begin:
      cal.begin(static_cast<uint16_t>(a));
      return {};
    case op::cal_add:
      return {cal.add(static_cast<int32_t>(a32), static_cast<uint8_t>(b)) ? 1u : 0u};
    case op::cal_result: {
      const protocol::cal_result_msg m = cal.result();
      return {static_cast<uint32_t>(m.delta_n_q8) | (uint64_t{m.cycles} << 32),
              m.std_q8 | (uint64_t{m.flags} << 32)};
    }
    case op::step_interval: {
      const stepper::ramp r{static_cast<uint16_t>(a), static_cast<uint16_t>(a >> 16),
                            static_cast<uint16_t>(a >> 32)};
      return {stepper::step_interval(r, b32, static_cast<uint32_t>(b >> 32), 32768)};
    }
    case op::ms_to_ticks:
      return {fw::ms_to_ticks(a32, b32)};
    case op::mclk_to_ticks:
      return {fw::mclk_to_ticks(a32, b32, static_cast<uint32_t>(a >> 32))};
    case op::link_budget: {
      protocol::configure_msg c;
      c.n_avg = static_cast<uint16_t>(a);
      c.n_temp = static_cast<uint8_t>(a >> 16);
      c.filter_word = static_cast<uint8_t>(a >> 24);
      c.flags = static_cast<uint8_t>(a >> 32);
      c.settle_ms = static_cast<uint16_t>(a >> 40);
      c.step_rate_sps = static_cast<uint16_t>(b);
      c.pos_steps[1] = static_cast<int16_t>(b >> 16);
      c.status_period_ms = static_cast<uint16_t>(b >> 32);
      return {protocol::worst_bytes_per_s(c, ad7739::mclk_hz_nominal),
              static_cast<uint8_t>(protocol::check_configure(c, ad7739::mclk_hz_nominal))};
    }
    default:
      return detail::helper(o, a, b);
  }
}

}  // namespace gyroflip::fw::selftest
