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
  rdy_ = false;
  ++resets_;
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
  op_stuck_ = what == op::convert && started_ - miss_from_ < miss_count_;
  if (what == op::convert) ++started_;
  rdy_ = false;
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
      uint32_t v = regs8_[addr_];
      if (addr_ >= a::reg_data && addr_ < a::reg_data + 8) {
        v = data_[addr_ - a::reg_data];
        rdy_ = false;  // reading the data register clears the channel's RDY
      }
      if (pending_ == 3) {
        io_[0] = static_cast<uint8_t>(v >> 16);
        io_[1] = static_cast<uint8_t>(v >> 8);
        io_[2] = static_cast<uint8_t>(v);
      } else {
        io_[0] = static_cast<uint8_t>(v);
      }
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

bool ad7739_model::rdy_low(uint32_t now) {
  if (op_ != op::none && !op_stuck_ && static_cast<int32_t>(now - op_end_) >= 0) {
    if (op_ == op::convert) {
      int32_t code = source_(ctx_, op_ch_, done_[op_ch_]);
      if (code < -a::code_zero) code = -a::code_zero;
      if (code > a::code_zero - 1) code = a::code_zero - 1;
      data_[op_ch_] = static_cast<uint32_t>(code + a::code_zero);
      ++done_[op_ch_];
    }
    regs8_[a::reg_mode + op_ch_] =
        static_cast<uint8_t>(regs8_[a::reg_mode + op_ch_] & ~a::mode_md_mask);
    op_ = op::none;
    rdy_ = true;
  }
  return rdy_;
}

}  // namespace gyroflip::fw::model
