/// \file
/// \brief Private to the analysis module: the inner loops of the Allan-family sums over a block of
/// at most a few thousand terms (squared second and third differences, MDEV's sliding sum).
///
/// Each loop keeps four independent accumulators (or lanes) so that it pipelines and the
/// compiler can use two-wide vector instructions; the block results are added in long double by
/// the callers, which keeps the relative rounding of a whole sum at ~1e-13 for any length.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

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

/// Four doubles as one vector (GCC/Clang vector types: AVX2 in the clones below, SSE2 pairs or
/// plain code elsewhere).
using lanes4 = double __attribute__((vector_size(32)));

// Lanes picked from a (0-3) and b (4-7), as one shuffle instruction where the CPU has it.
#if defined(__clang__)
#define GYROFLIP_PICK4(a, b, i, j, k, l) __builtin_shufflevector(a, b, i, j, k, l)
#else
using picks4 = std::int64_t __attribute__((vector_size(32)));
#define GYROFLIP_PICK4(a, b, i, j, k, l) __builtin_shuffle(a, b, picks4{i, j, k, l})
#endif

/// Rows a, b, c, d of a 4 x 4 tile become its columns: unpack low and high pairs, then swap
/// halves (four and four shuffles). By reference: a 32-byte vector passed by value has another
/// ABI in the AVX2 clones.
[[gnu::always_inline]] inline void transpose4(lanes4& a, lanes4& b, lanes4& c, lanes4& d) {
  const lanes4 t0 = GYROFLIP_PICK4(a, b, 0, 4, 2, 6);  // a0 b0 a2 b2
  const lanes4 t1 = GYROFLIP_PICK4(a, b, 1, 5, 3, 7);  // a1 b1 a3 b3
  const lanes4 t2 = GYROFLIP_PICK4(c, d, 0, 4, 2, 6);  // c0 d0 c2 d2
  const lanes4 t3 = GYROFLIP_PICK4(c, d, 1, 5, 3, 7);  // c1 d1 c3 d3
  a = GYROFLIP_PICK4(t0, t2, 0, 1, 4, 5);
  b = GYROFLIP_PICK4(t1, t3, 0, 1, 4, 5);
  c = GYROFLIP_PICK4(t0, t2, 2, 3, 6, 7);
  d = GYROFLIP_PICK4(t1, t3, 2, 3, 6, 7);
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
/// in `inner`. The chain runs as eight lanes side by side over eighths of the block, each
/// started from `inner` plus the (four-accumulator) sums of the deltas before it, so the adds
/// overlap instead of waiting on one another. The lanes are two four-wide vectors, fed four steps
/// at a time by turning 4 x 4 tiles of deltas (four steps of four lanes) into rows; each lane
/// computed exactly as alone, so the AVX2 clone and the plain code give the same bits.
GYROFLIP_KERNEL_CLONES inline double slide(double& inner, const double* delta, std::size_t n) {
  const std::size_t q = n / 8;
  std::array<double, 8> start{};
  start[0] = inner;
  for (std::size_t l = 1; l < 8; ++l) start[l] = start[l - 1] + sum4(delta + (l - 1) * q, q);
  lanes4 lo = {start[0], start[1], start[2], start[3]};  // lanes 0-3
  lanes4 hi = {start[4], start[5], start[6], start[7]};  // lanes 4-7
  lanes4 acc_lo = {0.0, 0.0, 0.0, 0.0};
  lanes4 acc_hi = {0.0, 0.0, 0.0, 0.0};
  const double* d = delta;
  // One step of all eight lanes: square, then move by the lanes' deltas.
  const auto step = [&](const lanes4& da, const lanes4& db) {
    acc_lo += lo * lo;
    acc_hi += hi * hi;
    lo += da;
    hi += db;
  };
  std::size_t t = 0;
  lanes4 a0, a1, a2, a3, b0, b1, b2, b3;  // rows: deltas t .. t+3 of lanes 0-3 and 4-7
  for (; t + 4 <= q; t += 4) {
    std::memcpy(&a0, d + t, sizeof a0);
    std::memcpy(&a1, d + q + t, sizeof a1);
    std::memcpy(&a2, d + 2 * q + t, sizeof a2);
    std::memcpy(&a3, d + 3 * q + t, sizeof a3);
    std::memcpy(&b0, d + 4 * q + t, sizeof b0);
    std::memcpy(&b1, d + 5 * q + t, sizeof b1);
    std::memcpy(&b2, d + 6 * q + t, sizeof b2);
    std::memcpy(&b3, d + 7 * q + t, sizeof b3);
    transpose4(a0, a1, a2, a3);  // a_k: step t + k of lanes 0-3
    transpose4(b0, b1, b2, b3);
    step(a0, b0);
    step(a1, b1);
    step(a2, b2);
    step(a3, b3);
  }
  for (; t < q; ++t)
    step(lanes4{d[t], d[q + t], d[2 * q + t], d[3 * q + t]},
         lanes4{d[4 * q + t], d[5 * q + t], d[6 * q + t], d[7 * q + t]});
  double s7 = hi[3];
  double acc7 = acc_hi[3];
  for (t = 8 * q; t < n; ++t) {  // the last lane takes the remainder
    acc7 += s7 * s7;
    s7 += delta[t];
  }
  inner = s7;
  return ((acc_lo[0] + acc_lo[1]) + (acc_lo[2] + acc_lo[3])) +
         ((acc_hi[0] + acc_hi[1]) + (acc_hi[2] + acc7));
}

}  // namespace gyroflip::analysis::detail
