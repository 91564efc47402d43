#!/usr/bin/env python3
"""Correlation of two overlapping Allan-variance estimates of the same series at averaging
factors m and 2^d m, for large N (standard library only). Used by the noise fit's interval
(src/analysis/noise_fit.cpp, table `octave_correlation`).

For a stationary Gaussian process the overlapping estimate s_m = (1/n) sum_i d_m(i)^2 of
AVAR(m tau0) (d_m = x_{i+2m} - 2x_{i+m} + x_i, SP1065 eqn 11) has, for n >> m,
    Cov(s_a, s_b) = (2/n) sum_k c_ab(k)^2,   c_ab(k) = Cov(d_a(i), d_b(i+k))
(Isserlis' theorem). With d_m = g_m * w for white driving noise w, c_ab is the cross-correlation
of the two kernels, and corr(s_a, s_b) = S_ab / sqrt(S_aa S_bb), S_ab = sum_k c_ab(k)^2; the
common factors (2/n, the noise level) cancel. Kernels on the driving noise:
  white PM  (alpha = +2, x white):           delta_0 - 2 delta_m + delta_2m
  white FM  (alpha =  0, y white):           -1 on [0, m), +1 on [m, 2m)
  random-walk FM (alpha = -2, y = sum w):    triangle u on [0, m], 2m - u on [m, 2m)
Flicker FM and PM have no finite kernel; the table takes flicker FM from a Monte Carlo of the
project's own flicker generator (400 series of 2^16 samples, sensor::flicker_bank: 0.68, 0.30,
0.12 at d = 1, 2, 3; +-0.05) and flicker PM as the mean of white PM and white FM.
Prints the table for d = 1..6 with m = 32 (the values change by < 0.01 from m = 16 to 64).
"""


def kernel(kind, m):
    if kind == "wpm":
        g = [0.0] * (2 * m + 1)
        g[0], g[m], g[2 * m] = 1.0, -2.0, 1.0
        return g
    if kind == "wfm":
        return [-1.0] * m + [1.0] * m
    return [float(u) for u in range(m)] + [float(2 * m - u) for u in range(m, 2 * m)]


def xcorr_sq_sum(a, b):
    # sum over all lags k of (sum_u a[u] b[u + k])^2
    total = 0.0
    for k in range(-len(a) + 1, len(b)):
        s = 0.0
        for u in range(max(0, -k), min(len(a), len(b) - k)):
            s += a[u] * b[u + k]
        total += s * s
    return total


def corr(kind, m, d):
    a, b = kernel(kind, m), kernel(kind, m << d)
    return xcorr_sq_sum(a, b) / (xcorr_sq_sum(a, a) * xcorr_sq_sum(b, b)) ** 0.5


if __name__ == "__main__":
    m = 32
    for kind in ("wpm", "wfm", "rwfm"):
        print(kind, " ".join(f"{corr(kind, m, d):.3f}" for d in range(1, 7)))
