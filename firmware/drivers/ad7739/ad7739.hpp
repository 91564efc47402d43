/// \file
/// \brief AD7739 driver at register level (regs.hpp; data sheet Rev. A): reset, revision,
/// channel setup, conversion time, self-calibration, single conversions, 24-bit data. It only
/// talks SPI through the HAL and never waits without a limit: every wait for RDY is bounded by
/// the caller's tick budget.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/drivers/ad7739/regs.hpp"
#include "firmware/hal/hal.hpp"

namespace gyroflip::ad7739 {

using fw::status;

class driver {
 public:
  constexpr explicit driver(const fw::hal& hw) : hw_(hw) {}

  /// Resets the part: 32 serial clocks with DIN high (regs.hpp reset_bytes).
  status reset();
  /// Reads the revision register (a part that is missing reads 0x00 or 0xFF).
  status read_revision(uint8_t* rev);
  /// Channel `ch` (0..7) as a differential input in range `rng` (a `range` value).
  status setup_channel(uint8_t ch, uint8_t rng);
  /// Channel conversion time: CHOP and the filter word (fw_min..fw_max).
  status set_conversion_time(uint8_t ch, bool chop, uint8_t fw);
  /// ADC zero-scale then full-scale self-calibration on channel `ch` (the data sheet's order),
  /// each waiting at most `timeout_ticks` for RDY; status::timeout when it does not come.
  status self_calibrate(uint8_t ch, uint32_t timeout_ticks);
  /// Starts one step of the self-calibration on channel `ch` without waiting: zero scale, or
  /// full scale (`full_scale`); /RDY falls when it is done (the data sheet's order: zero first).
  status start_calibration(uint8_t ch, bool full_scale);
  /// Starts one conversion on channel `ch`, 24-bit result, in dump mode (mode register MD = 010,
  /// 24/16 BIT and DUMP set): a data read then begins with the channel status.
  status start_single(uint8_t ch);
  /// Reads channel `ch`'s result in dump mode: the channel status byte (regs.hpp
  /// channel_status) and the 24-bit data register as a signed code (code - 2^23). Reading it
  /// clears the channel's RDY bit.
  status read_result(uint8_t ch, int32_t* code, uint8_t* channel_status);
  /// The /RDY pin is low: some channel has a result. Not proof that it is the conversion just
  /// started: the AD7739 drives /RDY high only in the scaling time at the end of a conversion,
  /// so a result nobody read keeps it low after a mode write (read_result's status says whose).
  [[nodiscard]] bool ready() const { return hw_.rdy_low(); }

  /// One register access: the communications byte, then `n` (at most 4) data bytes, MSB first.
  status write_reg(uint8_t addr, const uint8_t* data, uint8_t n);
  status read_reg(uint8_t addr, uint8_t* data, uint8_t n);

 private:
  status wait_ready(uint32_t timeout_ticks);
  const fw::hal& hw_;
};

}  // namespace gyroflip::ad7739
