/// \file
/// \brief AD7739 conversion time and set-up (formulas in ad7739.hpp).
#include "gyroflip/rig/ad7739.hpp"

#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "gyroflip/core/error.hpp"

namespace gyroflip::rig {

double conversion_time_s(const ad7739_config& c) noexcept {
  const double fw = c.filter_word;
  return c.chop ? (128.0 * fw + 249.0) / c.mclk_hz : (64.0 * fw + 206.0) / c.mclk_hz;
}

result<ad7739> ad7739::make(const ad7739_config& c, std::uint64_t seed) {
  if (c.filter_word < 2 || c.filter_word > 127)
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
  constexpr double magic = 6755399441055744.0;  // round_even's 1.5 * 2^52
  std::size_t i = 0;
#if defined(__SSE2__)
  // NOLINTBEGIN(portability-simd-intrinsics): guarded, with the portable loop below as fallback
  // Two conversions per step with SSE2's min/max (GCC vectorises the scalar clamp below as a
  // compare-and-blend of 8 instructions); the same operations in the same order.
  const __m128d off = _mm_set1_pd(offset_v_), nv = _mm_set1_pd(noise_v_);
  const __m128d inv = _mm_set1_pd(inv_lsb_), mg = _mm_set1_pd(magic);
  const __m128d lo2 = _mm_set1_pd(lo), hi2 = _mm_set1_pd(hi);
  const __m128d lsb = _mm_set1_pd(lsb_), sc = _mm_set1_pd(scale);
  for (; i + 2 <= n; i += 2) {
    const __m128d v = _mm_add_pd(_mm_add_pd(_mm_loadu_pd(v_diff + i), off),
                                 _mm_mul_pd(nv, _mm_loadu_pd(noise + i)));
    __m128d c = _mm_sub_pd(_mm_add_pd(_mm_mul_pd(v, inv), mg), mg);
    c = _mm_max_pd(_mm_min_pd(c, hi2), lo2);  // per lane: c < hi ? c : hi, then c > lo ? c : lo
    _mm_storeu_pd(out + i, _mm_mul_pd(_mm_mul_pd(c, lsb), sc));
  }
  // NOLINTEND(portability-simd-intrinsics)
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
