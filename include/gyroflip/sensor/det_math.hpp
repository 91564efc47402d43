/// \file
/// \brief `det_exp` and `det_log`: exp and log from IEEE-754 +, -, *, / only, so that the
/// simulator's random numbers and decay factors are bit-identical on every machine.
///
/// libm's exp/log are not required to round the same way everywhere; the simulator promises
/// "same seed -> byte-identical recording", so its transcendental functions on the sample path
/// (ziggurat tables and tails, Gauss-Markov decay factors) use these instead. They are not
/// faster than libm and need not be: they run at set-up, in rare ziggurat branches and on the
/// slow bias grid. Requires strict IEEE double evaluation (no -ffast-math; C++20 without
/// extensions does not contract a*b+c into FMA on GCC).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace gyroflip::sensor {

/// Rounds to the nearest integer, ties to even, for |x| < 2^51: (x + 1.5 2^52) - 1.5 2^52 in
/// IEEE round-to-nearest. Same result as std::nearbyint in the default rounding mode, but
/// inlined without SSE4.1 (nearbyint is a libm call on baseline x86-64).
[[nodiscard]] inline double round_even(double x) noexcept {
  constexpr double magic = 6755399441055744.0;  // 1.5 * 2^52
  return (x + magic) - magic;                   // not folded: strict IEEE semantics forbid it
}

/// e^x (dimensionless). Range reduction x = k ln2 + r, |r| <= ln2/2, with ln2 split in a
/// 32-bit-exact high part and a low part (Cody & Waite), then the Taylor series of e^r to
/// r^14/14! (truncation < 1e-17 for |r| <= 0.347) in Horner form with the coefficients 1/n!
/// rounded to nearest (multiplies and adds only: a division per term made the ziggurat's wedge
/// test, which calls this, a ~300-cycle dependency chain), and an exact scaling by 2^k.
/// Rel. error ~3e-16. x < -745 gives 0, x > 709 gives +inf, NaN gives NaN.
[[nodiscard]] inline double det_exp(double x) noexcept {
  if (x != x) return x;  // NaN propagates
  if (x < -745.0) return 0.0;
  if (x > 709.7) return std::numeric_limits<double>::infinity();
  constexpr double log2e = 1.4426950408889634;
  constexpr double ln2_hi = 6.93147180369123816490e-01;  // 0x3fe62e42fee00000
  constexpr double ln2_lo = 1.90821492927058770002e-10;
  const double kd = round_even(x * log2e);
  const double r = (x - kd * ln2_hi) - kd * ln2_lo;
  // 1/n!, n = 0..14, correctly rounded (Python: float(Fraction(1, factorial(n))).hex()).
  constexpr double inv_fact[15] = {0x1p+0,
                                   0x1p+0,
                                   0x1p-1,
                                   0x1.5555555555555p-3,
                                   0x1.5555555555555p-5,
                                   0x1.1111111111111p-7,
                                   0x1.6c16c16c16c17p-10,
                                   0x1.a01a01a01a01ap-13,
                                   0x1.a01a01a01a01ap-16,
                                   0x1.71de3a556c734p-19,
                                   0x1.27e4fb7789f5cp-22,
                                   0x1.ae64567f544e4p-26,
                                   0x1.1eed8eff8d898p-29,
                                   0x1.6124613a86d09p-33,
                                   0x1.93974a8c07c9dp-37};
  double p = inv_fact[14];
  for (int n = 13; n >= 0; --n) p = p * r + inv_fact[n];
  // Scale by 2^k: one multiply by a power of two built from its bits (exact, no libm call);
  // two steps keep 2^k representable near the ends of the range.
  const auto k = static_cast<std::int64_t>(kd);
  const std::int64_t k1 = k / 2;
  const std::int64_t k2 = k - k1;
  const auto pow2 = [](std::int64_t e) {
    return std::bit_cast<double>(static_cast<std::uint64_t>(e + 1023) << 52);
  };
  return p * pow2(k1) * pow2(k2);
}

/// ln x (dimensionless), x > 0. x = m 2^e with m in [sqrt(1/2), sqrt(2)) (exact frexp), then
/// ln m = 2 atanh(s), s = (m-1)/(m+1), |s| <= 0.1716, summed to s^27 (truncation < 1e-20),
/// plus e ln2. Relative error ~2e-16. x = 0 gives -inf, x < 0 or NaN gives NaN.
[[nodiscard]] inline double det_log(double x) noexcept {
  if (!(x > 0.0))
    return x == 0.0 ? -std::numeric_limits<double>::infinity()
                    : std::numeric_limits<double>::quiet_NaN();
  if (x == std::numeric_limits<double>::infinity()) return x;
  int e = 0;
  double m = std::frexp(x, &e);  // m in [0.5, 1)
  if (m < 0.70710678118654752) {
    m *= 2.0;
    --e;
  }
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double sum = 0.0;
  for (int k = 13; k >= 0; --k) sum = 1.0 / static_cast<double>(2 * k + 1) + s2 * sum;
  constexpr double ln2 = 6.93147180559945309417e-01;
  return 2.0 * s * sum + static_cast<double>(e) * ln2;
}

}  // namespace gyroflip::sensor
