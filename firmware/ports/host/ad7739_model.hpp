/// \file
/// \brief A register-level model of the AD7739 (firmware/drivers/ad7739/regs.hpp, convert.hpp):
/// SPI bytes in, bytes out, a RDY line, conversions that take the data sheet's conversion time,
/// and codes from a source the user plugs in. It is a model, not the part: it keeps the
/// registers the driver uses (mode, setup, conversion time, data, revision, ADC status, channel
/// status), takes 4 bytes of 0xFF as the serial reset, and can withhold RDY for chosen
/// conversions (a fault to test).
///
/// RDY as the data sheet (Rev. A) describes it and as a driver must expect it: each channel has
/// a RDY bit in the ADC status register, set when a conversion (or, in this model, a
/// calibration) ends and cleared when the channel's data register is read; the /RDY pin is low
/// while any bit is set, except in the last 163 MCLK cycles of a conversion (its scaling time),
/// when the part drives it high whatever its state before. A mode write therefore does not
/// clear a pending ready: a result nobody read keeps /RDY low until the new conversion's
/// scaling time. In dump mode (the mode register's DUMP bit) a data-register read begins with
/// the channel status (CH2..0, RDY, NOREF, SIGN, OVR; regs.hpp channel_status).
/// Freestanding, so the Cortex-M3 image runs the same model in place of the chip.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::fw::model {

class ad7739_model {
 public:
  /// The signed code (code - 2^23; clamped to the 24-bit range by the model) of conversion
  /// `index` (counted per channel from 0) on channel `ch`.
  using source_fn = int32_t (*)(void* ctx, uint8_t ch, uint32_t index);

  /// A written register, for tests of the driver's write sequence.
  struct write_entry {
    uint8_t addr;
    uint32_t value;
  };
  static constexpr size_t log_capacity = 64;
  /// The revision byte this model answers (the real part's value is not assumed).
  static constexpr uint8_t revision = 0x29;

  ad7739_model(uint32_t tick_hz, uint32_t mclk_hz, source_fn source, void* ctx)
      : tick_hz_(tick_hz), mclk_hz_(mclk_hz), source_(source), ctx_(ctx) {
    regs8_[2] = revision;  // the revision register (regs.hpp reg_revision)
  }

  void select(bool on);
  /// One SPI byte at time `now` (ticks).
  uint8_t transfer(uint8_t in, uint32_t now);
  /// The RDY line is low at `now`.
  bool rdy_low(uint32_t now);

  /// The reference is missing (NOREF in every result's channel status) while true.
  bool noref = false;

  /// Conversions with a global index (over all channels, from 0) in [from, from + count) never
  /// finish: RDY stays high until the next mode write.
  void withhold_rdy(uint32_t from, uint32_t count) {
    miss_from_ = from;
    miss_count_ = count;
  }
  [[nodiscard]] uint32_t conversions(uint8_t ch) const { return done_[ch & 7u]; }
  [[nodiscard]] uint32_t resets() const { return resets_; }
  [[nodiscard]] const write_entry* log() const { return log_; }
  [[nodiscard]] size_t log_size() const { return log_n_; }
  void clear_log() { log_n_ = 0; }
  [[nodiscard]] uint8_t reg8(uint8_t addr) const { return regs8_[addr & 0x3Fu]; }
  /// The ADC status register's RDY bits (bit ch: channel ch has a result nobody read).
  [[nodiscard]] uint8_t rdy_bits() const { return rdy_bits_; }

 private:
  enum class op : uint8_t { none, convert, calibrate };
  [[nodiscard]] static uint8_t width(uint8_t addr);
  void commit(uint32_t now);
  void start(uint8_t ch, op what, uint32_t now);
  void reset_part();
  void update(uint32_t now);
  [[nodiscard]] uint8_t channel_status(uint8_t ch) const;

  uint32_t tick_hz_, mclk_hz_;
  source_fn source_;
  void* ctx_;
  uint8_t regs8_[64] = {};  // one-byte registers by address
  uint32_t data_[8] = {};   // channel data registers (offset binary)
  uint32_t done_[8] = {};   // finished conversions per channel
  uint32_t started_ = 0;    // conversions started, all channels
  uint32_t miss_from_ = 0xFFFFFFFFu, miss_count_ = 0;
  // the serial interface
  bool expect_comm_ = true;
  uint8_t addr_ = 0, pending_ = 0, ones_ = 0;
  bool reading_ = false;
  uint8_t io_[4] = {};
  uint8_t io_n_ = 0;
  // the conversion in progress
  op op_ = op::none;
  uint8_t op_ch_ = 0;
  uint32_t op_end_ = 0;
  uint32_t op_scaling_ = 0;  // the conversion's scaling time begins (ticks)
  bool op_stuck_ = false;
  uint8_t rdy_bits_ = 0;
  uint8_t status_[8] = {};  // NOREF, SIGN, OVR of each channel's last result
  uint32_t resets_ = 0;
  write_entry log_[log_capacity] = {};
  size_t log_n_ = 0;
};

}  // namespace gyroflip::fw::model
