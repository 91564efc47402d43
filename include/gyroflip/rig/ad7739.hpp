/// \file
/// \brief The AD7739 24-bit sigma-delta ADC as the paper configured it (Tab. 1): +-2.5 V
/// differential with chopping, single conversions of ~2 ms, ~2 uV rms noise.
///
/// The part's facts (register map, conversion time in MCLK cycles, code format) live once, in
/// firmware/drivers/ad7739/regs.hpp and convert.hpp, shared with the firmware's driver:
///   chop on:  t = (128 FW + 249) / f_MCLK     chop off:  t = (64 FW + 206) / f_MCLK
/// with f_MCLK = 6.144 MHz (convert.hpp cites the data sheet and the family's timing). FW = 94
/// with chop gives 1.99886 ms (500.3 Hz), the paper's "2 ms"; FW = 127 gives 2.686 ms. This
/// header adds the noise model.
///
/// Conversion: v_in = (V_sensor - V_ref) + offset + sigma_n n, sigma_n = noise_uv_rms_at_2ms
/// sqrt(2 ms / t) (white-noise scaling of the 2-uV figure: an assumption), code =
/// clamp(round(v_in / LSB) + 2^23, 0, 2^24 - 1) offset binary, LSB = 5 V / 2^24 = 0.298 uV;
/// inputs beyond +-2.5 V clip to the end codes. Chopping removes the offset; without it the
/// offset `offset_uv_chop_off` (assumption) remains.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/ad7739/convert.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/sensor/det_math.hpp"
#include "gyroflip/sensor/random.hpp"

namespace gyroflip::rig {

/// The part: its clock, range and noise (what the rig's settings do not choose).
struct ad7739_part {
  double mclk_hz = 6.144e6;          ///< master clock (Hz)
  double range_v = 2.5;              ///< +-range of the differential input (V)
  double noise_uv_rms_at_2ms = 2.0;  ///< paper Tab. 1 (uV rms); 0 = noiseless
  double offset_uv_chop_off = 20.0;  ///< residual offset without chopping (uV, assumption)
};

/// The part with its settings (a simulation takes these from rig::rig_config).
struct ad7739_config : ad7739_part {
  int filter_word = 94;  ///< FW, fw_min..fw_max (2..127)
  bool chop = true;      ///< CHOP bit
};

/// Conversion time (s) from FW and CHOP (formula above).
[[nodiscard]] double conversion_time_s(const ad7739_config& c) noexcept;

class ad7739 {
 public:
  static constexpr std::int32_t code_max = gyroflip::ad7739::code_max;
  static constexpr std::int32_t code_zero = gyroflip::ad7739::code_zero;

  /// Errors: FW outside 2..127, non-positive clock or range, negative noise.
  [[nodiscard]] static result<ad7739> make(const ad7739_config& c, std::uint64_t seed);

  /// One conversion of the differential input `v_diff` (V).
  std::int32_t convert(double v_diff) noexcept {
    return convert(v_diff, noise_on_ ? noise_.next() : 0.0);
  }
  /// The same with the noise deviate `n` ~ N(0,1) drawn by the caller from noise_stream().
  std::int32_t convert(double v_diff, double n) noexcept {
    const double v = v_diff + offset_v_ + noise_v_ * n;
    const double c = sensor::round_even(v * inv_lsb_) + code_zero;
    return c <= 0.0 ? 0 : (c >= code_max ? code_max : static_cast<std::int32_t>(c));
  }
  /// `n` conversions at once, as volts times `scale`: out[i] = volts(convert(v_diff[i],
  /// noise[i])) * scale, bit for bit for finite input (the code offset 2^23 cancels, so the
  /// clamp runs on round(v / LSB) in [-2^23, 2^23 - 1] and the loop stays in doubles, which
  /// vectorises). The recorder passes 1 / SF_nominal and gets deg/s.
  void convert_block(const double* v_diff, const double* noise, double* out, double scale,
                     std::size_t n) const noexcept;
  /// The voltage (V) a code stands for: (code - 2^23) LSB.
  [[nodiscard]] double volts(std::int32_t code) const noexcept {
    return static_cast<double>(code - code_zero) * lsb_;
  }
  [[nodiscard]] double conversion_time_s() const noexcept { return t_conv_s_; }
  [[nodiscard]] double lsb_v() const noexcept { return lsb_; }
  [[nodiscard]] double noise_v_rms() const noexcept { return noise_v_; }
  [[nodiscard]] bool noise_on() const noexcept { return noise_on_; }
  [[nodiscard]] sensor::normal_stream& noise_stream() noexcept { return noise_; }

 private:
  ad7739(const ad7739_config& c, std::uint64_t seed);
  double t_conv_s_, lsb_, inv_lsb_, noise_v_, offset_v_;
  bool noise_on_;
  sensor::normal_stream noise_;
};

}  // namespace gyroflip::rig
