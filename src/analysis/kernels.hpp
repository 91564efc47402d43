/// \file
/// \brief Private to the analysis module: the inner loops of the Allan-family sums over a block of
/// at most a few thousand terms (squared second and third differences, MDEV's sliding sum).
///
/// Each loop keeps four independent accumulators (or lanes) so that it pipelines and the
/// compiler can use two-wide vector instructions; the block results are added in long double by
/// the callers, which keeps the relative rounding of a whole sum at ~1e-13 for any length.
#pragma once

#include <cstddef>

namespace gyroflip::analysis::detail {

/// Sum over t < n of f(t)^2 with four accumulators (t mod 4), the rest into the first. Always
/// inlined, so that it is compiled for its caller's target (the kernels' AVX2 clones below).
template <class F>
[[gnu::always_inline]] inline double sum_squares(std::size_t n, F f) {
  double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
  std::size_t t = 0;
  for (; t + 4 <= n; t += 4) {
    const double d0 = f(t), d1 = f(t + 1), d2 = f(t + 2), d3 = f(t + 3);
    a0 += d0 * d0;
    a1 += d1 * d1;
    a2 += d2 * d2;
    a3 += d3 * d3;
  }
  for (; t < n; ++t) {
    const double d = f(t);
    a0 += d * d;
  }
  return (a0 + a1) + (a2 + a3);
}

// The two difference kernels are compiled twice on x86-64 (SSE2 and AVX2, picked at load time by
// the CPU): twice the lanes where the CPU has them. The four accumulators stay four lanes either
// way and -ffp-contract=off keeps multiplies and adds apart, so the sums are bit-identical.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GYROFLIP_KERNEL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GYROFLIP_KERNEL_CLONES
#endif

/// Sum of squared second differences x2_t - 2 x1_t + x0_t over t < n (NIST SP1065 eqn 11 terms;
/// x_j points at x_{i + j m}).
GYROFLIP_KERNEL_CLONES inline double sum_second_differences(const double* x0, const double* x1,
                                                            const double* x2, std::size_t n) {
  return sum_squares(n, [=](std::size_t t) { return x2[t] - 2.0 * x1[t] + x0[t]; });
}

/// Sum of squared third differences x3_t - 3 x2_t + 3 x1_t - x0_t over t < n (SP1065 eqn 18).
GYROFLIP_KERNEL_CLONES inline double sum_third_differences(const double* x0, const double* x1,
                                                           const double* x2, const double* x3,
                                                           std::size_t n) {
  return sum_squares(n, [=](std::size_t t) { return x3[t] - 3.0 * x2[t] + 3.0 * x1[t] - x0[t]; });
}

/// Sum of p[0..n) with four accumulators.
inline double sum4(const double* p, std::size_t n) {
  double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
  std::size_t t = 0;
  for (; t + 4 <= n; t += 4) {
    a0 += p[t];
    a1 += p[t + 1];
    a2 += p[t + 2];
    a3 += p[t + 3];
  }
  for (; t < n; ++t) a0 += p[t];
  return (a0 + a1) + (a2 + a3);
}

/// MDEV's steps delta_t = d_{t+m} - d_t = x3_t - 3 x2_t + 3 x1_t - x0_t over t < n, as
/// (x3 - x0) - 3 (x2 - x1) (four operations), element by element (so the same bits at any width).
GYROFLIP_KERNEL_CLONES inline void mdev_steps(const double* x0, const double* x1, const double* x2,
                                              const double* x3, double* delta, std::size_t n) {
  for (std::size_t t = 0; t < n; ++t) delta[t] = (x3[t] - x0[t]) - 3.0 * (x2[t] - x1[t]);
}

/// MDEV's slide (SP1065 eqn 14): the inner sum s_t over m second differences moves by
/// delta_t = d_{t+m} - d_t per step. Returns sum_{t<n} s_t^2 with s_0 = `inner` and leaves s_n
/// in `inner`. The chain runs as four lanes side by side over quarters of the block, each
/// started from `inner` plus the (four-accumulator) sums of the deltas before it, so the adds
/// overlap instead of waiting on one another; the lanes are two-wide vectors (GCC/Clang vector
/// types: SSE2 on x86-64, plain code elsewhere), each lane computed exactly as alone.
inline double slide(double& inner, const double* delta, std::size_t n) {
  using pair = double __attribute__((vector_size(16)));
  const std::size_t q = n / 4;
  const double s1 = inner + sum4(delta, q);
  const double s2 = s1 + sum4(delta + q, q);
  pair lo = {inner, s1};                        // lanes 0 and 1
  pair hi = {s2, s2 + sum4(delta + 2 * q, q)};  // lanes 2 and 3
  pair acc_lo = {0.0, 0.0};
  pair acc_hi = {0.0, 0.0};
  for (std::size_t t = 0; t < q; ++t) {
    acc_lo += lo * lo;
    acc_hi += hi * hi;
    lo += pair{delta[t], delta[q + t]};
    hi += pair{delta[2 * q + t], delta[3 * q + t]};
  }
  double s3 = hi[1];
  double acc3 = acc_hi[1];
  for (std::size_t t = 4 * q; t < n; ++t) {  // the last lane takes the remainder
    acc3 += s3 * s3;
    s3 += delta[t];
  }
  inner = s3;
  return (acc_lo[0] + acc_lo[1]) + (acc_hi[0] + acc3);
}

}  // namespace gyroflip::analysis::detail
