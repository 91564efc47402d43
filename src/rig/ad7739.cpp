/// \file
/// \brief AD7739 conversion time and set-up (formulas in ad7739.hpp).
#include "gyroflip/rig/ad7739.hpp"

#include <cmath>
#include <cstring>

#include "gyroflip/core/error.hpp"

namespace gyroflip::rig {

double conversion_time_s(const ad7739_config& c) noexcept {
  const auto fw = static_cast<std::uint8_t>(c.filter_word);  // checked by make()
  return static_cast<double>(gyroflip::ad7739::conversion_mclk(c.chop, fw)) / c.mclk_hz;
}

result<ad7739> ad7739::make(const ad7739_config& c, std::uint64_t seed) {
  if (c.filter_word < gyroflip::ad7739::fw_min || c.filter_word > gyroflip::ad7739::fw_max)
    return usage_error("AD7739 filter word must be 2..127");
  if (!(c.mclk_hz > 0.0) || !(c.range_v > 0.0) || !(c.noise_uv_rms_at_2ms >= 0.0) ||
      !std::isfinite(c.mclk_hz + c.range_v + c.noise_uv_rms_at_2ms + c.offset_uv_chop_off)) {
    return usage_error("AD7739: clock and range must be > 0, noise >= 0");
  }
  return ad7739(c, seed);
}

void ad7739::convert_block(const double* __restrict v_diff, const double* __restrict noise,
                           double* __restrict out, double scale, std::size_t n) const noexcept {
  constexpr double lo = -static_cast<double>(code_zero);
  constexpr double hi = static_cast<double>(code_max - code_zero);
  std::size_t i = 0;
#if defined(__SSE2__) && defined(__GNUC__)
  // Two conversions per step in GCC/Clang vector types, the clamp with SSE2's min and max (GCC
  // vectorises the portable loop's clamp as an 8-instruction compare-and-blend: ~6 instructions
  // more per conversion). minpd(c, hi) = c < hi ? c : hi and maxpd(c, lo) = c > lo ? c : lo
  // per lane, so the results equal the portable loop's for every finite input.
  using v2 = double __attribute__((vector_size(16)));
  const auto splat = [](double x) { return v2{x, x}; };
  const v2 off = splat(offset_v_), nv = splat(noise_v_), inv = splat(inv_lsb_);
  const v2 mg = splat(6755399441055744.0), lo2 = splat(lo), hi2 = splat(hi);
  const v2 lsb = splat(lsb_), sc = splat(scale);
  for (; i + 2 <= n; i += 2) {
    v2 a;
    v2 b;
    std::memcpy(&a, v_diff + i, sizeof a);
    std::memcpy(&b, noise + i, sizeof b);
    const v2 v = (a + off) + nv * b;
    v2 c = (v * inv + mg) - mg;  // round_even, lane-wise
    c = __builtin_ia32_maxpd(__builtin_ia32_minpd(c, hi2), lo2);
    const v2 r = c * lsb * sc;
    std::memcpy(out + i, &r, sizeof r);
  }
#endif
  // Zero noise deviates when the noise is off (noise_v_ = 0 then), so no branch per sample.
  for (; i < n; ++i) {
    const double v = v_diff[i] + offset_v_ + noise_v_ * noise[i];
    double c = sensor::round_even(v * inv_lsb_);
    c = c < hi ? c : hi;
    c = c > lo ? c : lo;
    out[i] = c * lsb_ * scale;
  }
}

ad7739::ad7739(const ad7739_config& c, std::uint64_t seed)
    : t_conv_s_(rig::conversion_time_s(c)),
      lsb_(2.0 * c.range_v / 16777216.0),
      inv_lsb_(16777216.0 / (2.0 * c.range_v)),
      noise_v_(1e-6 * c.noise_uv_rms_at_2ms * std::sqrt(2e-3 / t_conv_s_)),
      offset_v_(c.chop ? 0.0 : 1e-6 * c.offset_uv_chop_off),
      noise_on_(noise_v_ > 0.0),
      noise_(seed, sensor::stream::adc_noise) {}

}  // namespace gyroflip::rig
