/// \file
/// \brief AD7739 register map and bit fields (Analog Devices AD7739 data sheet Rev. A, register
/// descriptions; cross-checked against two public drivers, docs/HARDWARE.md "AD7739"). The one
/// place these facts live: the driver (ad7739.cpp) and the simulator's ADC model use them.
/// Freestanding: <stdint.h> only.
#pragma once

#include <stdint.h>

namespace gyroflip::ad7739 {

/// Communications register (every access starts with it): bit 6 = read, bits 5:0 = address.
inline constexpr uint8_t comm_read = 0x40;

/// Register addresses. Per-channel registers are at base + channel (0..7).
enum reg : uint8_t {
  reg_comm = 0x00,            ///< communications (write only)
  reg_io_port = 0x01,         ///< I/O port (P0, P1)
  reg_revision = 0x02,        ///< revision (read only)
  reg_test = 0x03,            ///< test (do not write)
  reg_adc_status = 0x04,      ///< ADC status: bit ch = RDY of channel ch
  reg_checksum = 0x05,        ///< checksum
  reg_adc_zero_cal = 0x06,    ///< ADC zero-scale calibration (24 bit)
  reg_adc_full_cal = 0x07,    ///< ADC full-scale calibration (24 bit)
  reg_data = 0x08,            ///< channel data (16 or 24 bit) + ch
  reg_zero_cal = 0x10,        ///< channel zero-scale calibration (24 bit) + ch
  reg_full_cal = 0x18,        ///< channel full-scale calibration (24 bit) + ch
  reg_channel_status = 0x20,  ///< channel status + ch
  reg_setup = 0x28,           ///< channel setup + ch
  reg_conv_time = 0x30,       ///< channel conversion time + ch
  reg_mode = 0x38,            ///< mode + ch
};

/// Mode register: MD2..0 in bits 7:5, then CLKDIS, DUMP, CONT RD, 24/16 BIT, CLAMP.
enum mode : uint8_t {
  mode_idle = 0x00,
  mode_continuous = 0x20,
  mode_single = 0x40,
  mode_power_down = 0x60,
  mode_adc_zero_self_cal = 0x80,
  mode_adc_full_self_cal = 0xA0,
  mode_ch_zero_system_cal = 0xC0,
  mode_ch_full_system_cal = 0xE0,
  mode_md_mask = 0xE0,
  mode_clkdis = 0x10,
  mode_dump = 0x08,
  mode_cont_read = 0x04,
  mode_24bit = 0x02,
  mode_clamp = 0x01,
};

/// Channel setup register: BUFOFF, COM1..0, STAT OPT, ENABLE, RNG2..0.
enum setup : uint8_t {
  setup_bufoff = 0x80,
  setup_com_differential =
      0x20,  ///< COM = 01: AIN(2k) - AIN(2k+1) differential [U, docs/HARDWARE.md]
  setup_stat_opt = 0x10,
  setup_enable = 0x08,
  setup_range_mask = 0x07,
};

/// Input ranges (RNG2..0).
enum range : uint8_t {
  range_bipolar_1v25 = 0,
  range_unipolar_1v25 = 1,
  range_bipolar_0v625 = 2,
  range_unipolar_0v625 = 3,
  range_bipolar_2v5 = 4,
  range_unipolar_2v5 = 5,
};

/// Channel status register (data sheet Rev. A, p. 17, Tables 21 and 22), also the first byte
/// of a data-register read in dump mode: CH2..CH0 in bits 7:5 (the channel), 0/P0, RDY/P1 (the
/// channel's RDY bit of the ADC status register while its setup's STAT OPT is 0), NOREF (the
/// reference was missing during the conversion), SIGN, OVR (over- or under-range).
inline constexpr uint8_t chst_channel_shift = 5;
inline constexpr uint8_t chst_rdy = 0x08;
inline constexpr uint8_t chst_noref = 0x04;
inline constexpr uint8_t chst_sign = 0x02;
inline constexpr uint8_t chst_ovr = 0x01;

/// Channel conversion-time register: CHOP in bit 7, the filter word FW in bits 6:0.
inline constexpr uint8_t conv_chop = 0x80;
inline constexpr uint8_t conv_fw_mask = 0x7F;

/// Writing at least 32 serial clocks with DIN high resets the whole part to its power-on state
/// (the family's serial-interface reset). The driver sends this many 0xFF bytes.
inline constexpr uint8_t reset_bytes = 4;

}  // namespace gyroflip::ad7739
