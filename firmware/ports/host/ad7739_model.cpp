/// \file
/// \brief AD7739 register-level model (ad7739_model.hpp).
#include "firmware/ports/host/ad7739_model.hpp"

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/drivers/ad7739/regs.hpp"

namespace gyroflip::fw::model {

namespace a = gyroflip::ad7739;

uint8_t ad7739_model::width(uint8_t addr) {
  if (addr == a::reg_checksum) return 2;
  if (addr == a::reg_test || addr == a::reg_adc_zero_cal || addr == a::reg_adc_full_cal) return 3;
  if (addr >= a::reg_data && addr < a::reg_channel_status) return 3;  // data, zero and full cal
  return 1;
}

void ad7739_model::reset_part() {
  for (uint8_t& r : regs8_) r = 0;
  regs8_[a::reg_revision] = revision;
  op_ = op::none;
  rdy_bits_ = 0;
  ++resets_;
}

uint8_t ad7739_model::channel_status(uint8_t ch) const {
  return static_cast<uint8_t>((static_cast<unsigned>(ch) << a::chst_channel_shift) |
                              (((rdy_bits_ >> ch) & 1u) != 0 ? a::chst_rdy : 0u) | status_[ch]);
}

void ad7739_model::select(bool on) {
  // A new chip-select frame starts with a communications byte.
  if (on) {
    expect_comm_ = true;
    pending_ = 0;
  }
}

void ad7739_model::start(uint8_t ch, op what, uint32_t now) {
  const uint8_t ct = regs8_[a::reg_conv_time + ch];
  const uint8_t fw = static_cast<uint8_t>(ct & a::conv_fw_mask);
  const uint64_t mclk =
      a::conversion_mclk((ct & a::conv_chop) != 0, fw < a::fw_min ? a::fw_min : fw);
  op_ = what;
  op_ch_ = ch;
  op_end_ = now + static_cast<uint32_t>((mclk * tick_hz_ + mclk_hz_ - 1) / mclk_hz_);
  // The scaling time: the last 163 MCLK cycles (AD7732 data sheet, the family's timing).
  constexpr uint64_t scaling_mclk = 163;
  op_scaling_ =
      op_end_ - static_cast<uint32_t>((scaling_mclk * tick_hz_ + mclk_hz_ - 1) / mclk_hz_);
  op_stuck_ = what == op::convert && started_ - miss_from_ < miss_count_;
  if (what == op::convert) ++started_;
}

void ad7739_model::commit(uint32_t now) {
  const uint32_t v = (uint32_t{io_[0]} << 16) | (uint32_t{io_[1]} << 8) | io_[2];
  const uint8_t n = width(addr_);
  const uint32_t value = n == 1 ? io_[0] : v;
  if (log_n_ < log_capacity) log_[log_n_++] = {addr_, value};
  if (addr_ == a::reg_revision || addr_ == a::reg_adc_status) return;  // read only
  if (n == 1) regs8_[addr_] = io_[0];
  if (addr_ >= a::reg_mode && addr_ < a::reg_mode + 8) {
    const uint8_t ch = static_cast<uint8_t>(addr_ - a::reg_mode);
    const uint8_t md = static_cast<uint8_t>(io_[0] & a::mode_md_mask);
    if (md == a::mode_single || md == a::mode_continuous) start(ch, op::convert, now);
    if (md == a::mode_adc_zero_self_cal || md == a::mode_adc_full_self_cal)
      start(ch, op::calibrate, now);
  }
}

uint8_t ad7739_model::transfer(uint8_t in, uint32_t now) {
  if (expect_comm_) {
    if (in == 0xFF) {  // DIN high: 32 of them reset the part
      if (++ones_ == a::reset_bytes) {
        ones_ = 0;
        reset_part();
      }
      return 0xFF;
    }
    ones_ = 0;
    addr_ = static_cast<uint8_t>(in & 0x3Fu);
    reading_ = (in & a::comm_read) != 0;
    pending_ = width(addr_);
    io_n_ = 0;
    expect_comm_ = false;
    if (reading_) {
      update(now);
      uint32_t v = regs8_[addr_];
      if (addr_ == a::reg_adc_status) v = rdy_bits_;
      if (addr_ >= a::reg_channel_status && addr_ < a::reg_channel_status + 8)
        v = channel_status(static_cast<uint8_t>(addr_ - a::reg_channel_status));
      uint8_t k = 0;
      if (addr_ >= a::reg_data && addr_ < a::reg_data + 8) {
        const auto ch = static_cast<uint8_t>(addr_ - a::reg_data);
        v = data_[ch];
        // Dump mode: the channel status first, then the data.
        if ((regs8_[a::reg_mode + ch] & a::mode_dump) != 0) {
          io_[k++] = channel_status(ch);
          ++pending_;
        }
        rdy_bits_ = static_cast<uint8_t>(rdy_bits_ & ~(1u << ch));  // the read clears its RDY
      }
      if (width(addr_) == 3) {
        io_[k++] = static_cast<uint8_t>(v >> 16);
        io_[k++] = static_cast<uint8_t>(v >> 8);
      }
      io_[k] = static_cast<uint8_t>(v);
    }
    return 0xFF;
  }
  if (pending_ == 0) {
    expect_comm_ = true;
    return transfer(in, now);
  }
  uint8_t out = 0xFF;
  if (reading_) {
    out = io_[io_n_++];
  } else {
    io_[io_n_++] = in;
  }
  if (--pending_ == 0) {
    if (!reading_) commit(now);
    expect_comm_ = true;
  }
  return out;
}

void ad7739_model::update(uint32_t now) {
  if (op_ == op::none || op_stuck_) return;
  // The scaling time of a conversion: its channel's old result goes (the data register is
  // about to change).
  if (op_ == op::convert && static_cast<int32_t>(now - op_scaling_) >= 0)
    rdy_bits_ = static_cast<uint8_t>(rdy_bits_ & ~(1u << op_ch_));
  if (static_cast<int32_t>(now - op_end_) < 0) return;
  if (op_ == op::convert) {
    int32_t code = source_(ctx_, op_ch_, done_[op_ch_]);
    const bool over = code < -a::code_zero || code > a::code_zero - 1;
    if (code < -a::code_zero) code = -a::code_zero;
    if (code > a::code_zero - 1) code = a::code_zero - 1;
    data_[op_ch_] = static_cast<uint32_t>(code + a::code_zero);
    status_[op_ch_] = static_cast<uint8_t>(
        (noref ? a::chst_noref : 0u) | (code < 0 ? a::chst_sign : 0u) | (over ? a::chst_ovr : 0u));
    ++done_[op_ch_];
  }
  regs8_[a::reg_mode + op_ch_] =
      static_cast<uint8_t>(regs8_[a::reg_mode + op_ch_] & ~a::mode_md_mask);
  op_ = op::none;
  rdy_bits_ = static_cast<uint8_t>(rdy_bits_ | (1u << op_ch_));
}

bool ad7739_model::rdy_low(uint32_t now) {
  update(now);
  // Driven high in a conversion's scaling time, whatever else is pending.
  if (op_ == op::convert && !op_stuck_ && static_cast<int32_t>(now - op_scaling_) >= 0)
    return false;
  return rdy_bits_ != 0;
}

}  // namespace gyroflip::fw::model
