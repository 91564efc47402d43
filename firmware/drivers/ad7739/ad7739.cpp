/// \file
/// \brief AD7739 driver (ad7739.hpp).
#include "firmware/drivers/ad7739/ad7739.hpp"

namespace gyroflip::ad7739 {

status driver::write_reg(uint8_t addr, const uint8_t* data, uint8_t n) {
  uint8_t buf[5] = {static_cast<uint8_t>(addr & 0x3Fu), 0, 0, 0, 0};
  if (n > 4) return status::bad_arg;
  for (uint8_t i = 0; i < n; ++i) buf[1 + i] = data[i];
  hw_.spi_select(true);
  const status s = hw_.spi_transfer(buf, buf, size_t{1} + n);
  hw_.spi_select(false);
  return s;
}

status driver::read_reg(uint8_t addr, uint8_t* data, uint8_t n) {
  uint8_t buf[5] = {static_cast<uint8_t>(comm_read | (addr & 0x3Fu)), 0, 0, 0, 0};
  if (n > 4) return status::bad_arg;
  hw_.spi_select(true);
  const status s = hw_.spi_transfer(buf, buf, size_t{1} + n);
  hw_.spi_select(false);
  for (uint8_t i = 0; i < n; ++i) data[i] = buf[1 + i];
  return s;
}

status driver::reset() {
  uint8_t ones[reset_bytes];
  for (uint8_t& b : ones) b = 0xFF;
  hw_.spi_select(true);
  const status s = hw_.spi_transfer(ones, ones, reset_bytes);
  hw_.spi_select(false);
  return s;
}

status driver::read_revision(uint8_t* rev) {
  return read_reg(reg_revision, rev, 1);
}

status driver::setup_channel(uint8_t ch, uint8_t rng) {
  if (ch > 7 || rng > range_unipolar_2v5) return status::bad_arg;
  const uint8_t v = static_cast<uint8_t>(setup_com_differential | rng);
  return write_reg(static_cast<uint8_t>(reg_setup + ch), &v, 1);
}

status driver::set_conversion_time(uint8_t ch, bool chop, uint8_t fw) {
  if (ch > 7 || fw < fw_min || fw > fw_max) return status::bad_arg;
  const uint8_t v = static_cast<uint8_t>((chop ? conv_chop : 0u) | fw);
  return write_reg(static_cast<uint8_t>(reg_conv_time + ch), &v, 1);
}

status driver::wait_ready(uint32_t timeout_ticks) {
  const uint32_t t0 = hw_.ticks();
  while (!hw_.rdy_low()) {
    if (hw_.ticks() - t0 > timeout_ticks) return status::timeout;
    hw_.watchdog_kick();
    hw_.busy_wait();
  }
  return status::ok;
}

status driver::self_calibrate(uint8_t ch, uint32_t timeout_ticks) {
  if (ch > 7) return status::bad_arg;
  const uint8_t addr = static_cast<uint8_t>(reg_mode + ch);
  const uint8_t order[2] = {mode_adc_zero_self_cal, mode_adc_full_self_cal};
  for (const uint8_t md : order) {
    const uint8_t v = static_cast<uint8_t>(md | mode_24bit);
    if (const status s = write_reg(addr, &v, 1); s != status::ok) return s;
    if (const status s = wait_ready(timeout_ticks); s != status::ok) return s;
  }
  return status::ok;
}

status driver::start_calibration(uint8_t ch, bool full_scale) {
  if (ch > 7) return status::bad_arg;
  const uint8_t v = static_cast<uint8_t>(
      (full_scale ? mode_adc_full_self_cal : mode_adc_zero_self_cal) | mode_24bit);
  return write_reg(static_cast<uint8_t>(reg_mode + ch), &v, 1);
}

status driver::start_single(uint8_t ch) {
  if (ch > 7) return status::bad_arg;
  const uint8_t v = mode_single | mode_24bit | mode_dump;
  return write_reg(static_cast<uint8_t>(reg_mode + ch), &v, 1);
}

status driver::read_result(uint8_t ch, int32_t* code, uint8_t* channel_status) {
  if (ch > 7) return status::bad_arg;
  uint8_t b[4];
  const status s = read_reg(static_cast<uint8_t>(reg_data + ch), b, 4);
  *channel_status = b[0];
  const uint32_t raw =
      (static_cast<uint32_t>(b[1]) << 16) | (static_cast<uint32_t>(b[2]) << 8) | b[3];
  *code = to_signed(raw);
  return s;
}

}  // namespace gyroflip::ad7739
