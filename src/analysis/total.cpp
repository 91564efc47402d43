/// \file
/// \brief The total variances MTOT/HTOT and Theo1 (see extended.hpp; derivation in
/// docs/ANALYSIS.md, "The extended statistics").
///
/// A window's total-variance energy E_i = sum_j d_j^2 is a quadratic form w^T G w of its detrended
/// points w: the 6m second differences of the reflected sequence rev(w) w rev(w) are one period of
/// a circular filter on the 6m-periodic even extension of w, which gives
/// G(a, b) = 2 kappa(|a - b|) + 2 kappa(rho(a + b + 1)), kappa the autocorrelation of the filter h
/// (m ones, m minus twos, m ones), rho(s) = min(s, 6m - s). Summed over a block of windows, the
/// Toeplitz part weighs each lagged product y_p y_{p+delta} by how many windows hold both points
/// (two correlations), and the Hankel part by Gamma(delta) = sum of 2 kappa(rho(u)) over
/// u = delta + 1, delta + 3, ..., 6m - 1 - delta except near the block's two ends (a convolution
/// and a correlation of each end's 3m - 1 points). The detrending adds w = y - s_i r: two more
/// correlations. Every correlation is one FFT, so a block of B windows costs O((B + m) log) instead
/// of O(B m).
#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "extended.hpp"
#include "fft.hpp"

namespace gyroflip::analysis::detail {
namespace {

// Factors below this are summed window by window (direct_energy), the others by FFT blocks.
constexpr std::size_t direct_below = 8;

// What a total-variance pass needs for one m: the kernel and its cumulative sums.
struct total_kernel {
  std::size_t m = 0;
  std::size_t len = 0;        // L = 3m, the window
  std::vector<double> kappa;  // kappa(l), l < L: autocorrelation of h
  std::vector<double> g;      // g(u) = 2 kappa(rho(u)), u in [0, 2L]
  std::vector<double> kc;     // Kc(u) = g(u) + g(u - 2) + ..., stored at u + 1, u in [-1, 2L]
  std::vector<double> u;      // G r, r_b = b
  double r_g_r = 0.0;         // r^T G r
  [[nodiscard]] double cum(std::ptrdiff_t v) const {  // Kc(v), 0 below 1
    if (v < 1) return 0.0;
    return kc[static_cast<std::size_t>(v) + 1];
  }
  [[nodiscard]] double gamma(std::size_t d) const {  // the Hankel weight of lag d, unclipped
    const auto l = static_cast<std::ptrdiff_t>(len);
    const auto dd = static_cast<std::ptrdiff_t>(d);
    return cum(2 * l - 1 - dd) - cum(dd - 1);
  }
};

total_kernel make_kernel(std::size_t m, Eigen::FFT<double>& fft) {
  total_kernel k;
  k.m = m;
  k.len = 3 * m;
  const std::size_t l = k.len;
  // kappa(lag) = sum over the filter's three pieces p, q (values 1, -2, 1) of c_p c_q times the
  // overlap of piece p with piece q shifted back by lag.
  const double c[3] = {1.0, -2.0, 1.0};
  k.kappa.assign(l, 0.0);
  for (std::size_t lag = 0; lag < l; ++lag) {
    double s = 0.0;
    for (std::size_t p = 0; p < 3; ++p)
      for (std::size_t q = 0; q < 3; ++q) {
        const auto lo = std::max<std::ptrdiff_t>(
            static_cast<std::ptrdiff_t>(p * m),
            static_cast<std::ptrdiff_t>(q * m) - static_cast<std::ptrdiff_t>(lag));
        const auto hi = std::min<std::ptrdiff_t>(
            static_cast<std::ptrdiff_t>((p + 1) * m),
            static_cast<std::ptrdiff_t>((q + 1) * m) - static_cast<std::ptrdiff_t>(lag));
        if (hi > lo) s += c[p] * c[q] * static_cast<double>(hi - lo);
      }
    k.kappa[lag] = s;
  }
  k.g.assign(2 * l + 1, 0.0);
  for (std::size_t v = 1; v < 2 * l; ++v) {
    const std::size_t rho = std::min(v, 2 * l - v);
    if (rho < l) k.g[v] = 2.0 * k.kappa[rho];
  }
  k.kc.assign(2 * l + 2, 0.0);  // index u + 1
  for (std::size_t v = 1; v <= 2 * l; ++v) k.kc[v + 1] = k.g[v] + (v >= 2 ? k.kc[v - 1] : 0.0);
  // u = G r: the Toeplitz part a convolution of 2 kappa(|d|) with r, the Hankel part a
  // correlation of r with g.
  std::vector<double> r(l), k2(2 * l - 1);
  for (std::size_t b = 0; b < l; ++b) r[b] = static_cast<double>(b);
  for (std::size_t d = 0; d < 2 * l - 1; ++d) {
    const std::size_t lag = d >= l - 1 ? d - (l - 1) : (l - 1) - d;
    k2[d] = 2.0 * k.kappa[lag];
  }
  const std::size_t s = fft_size(4 * l + 2);
  const auto rs = spectrum(fft, r, s);
  const auto toeplitz = convolution(fft, spectrum(fft, k2, s), rs, 2 * l - 1);
  const auto hankel = correlation(fft, rs, spectrum(fft, k.g, s), l + 1);
  k.u.assign(l, 0.0);
  for (std::size_t a = 0; a < l; ++a) {
    k.u[a] = toeplitz[a + l - 1] + hankel[a + 1];
    k.r_g_r += r[a] * k.u[a];
  }
  return k;
}

// sum over windows i < b of E_i on y (b + L - 1 points).
long double block_energy(const total_kernel& k, std::vector<double> y, std::size_t b,
                         Eigen::FFT<double>& fft) {
  const std::size_t l = k.len;
  const std::size_t n = b + l - 1;
  // The statistic ignores a linear function added to the series (the per-window detrending
  // removes its slope, the filter its offset): take out the block's own line so that the sums
  // below work on its fluctuations only.
  {
    const double y0 = y[0];
    const double slope = n > 1 ? (y[n - 1] - y0) / static_cast<double>(n - 1) : 0.0;
    for (std::size_t t = 0; t < n; ++t) y[t] -= y0 + slope * static_cast<double>(t);
  }
  const std::size_t s = fft_size(n + l + 1);
  std::vector<double> ay(n), cy(n);
  for (std::size_t p = 0; p < n; ++p) {
    ay[p] = static_cast<double>(std::min(b, p + 1)) * y[p];
    cy[p] = static_cast<double>(p + 1 >= l ? p + 1 - l : 0) * y[p];
  }
  const auto ys = spectrum(fft, y, s);
  const auto corr_a = correlation(fft, spectrum(fft, ay, s), ys, l);
  const auto corr_c = correlation(fft, ys, spectrum(fft, cy, s), l);
  const auto auto_y = correlation(fft, ys, ys, l);
  long double total = 0.0L;
  for (std::size_t d = 0; d < l; ++d) {
    const double both = d == 0 ? 1.0 : 2.0;  // (p, q) and (q, p)
    total += static_cast<long double>(both * 2.0 * k.kappa[d] * (corr_a[d] - corr_c[d]));
    total += static_cast<long double>(both * k.gamma(d) * auto_y[d]);
  }
  // The Hankel weights of the pairs among the first and among the last L - 1 points, where the
  // windows that hold both are cut by the block's ends.
  const std::size_t e = l - 1;
  if (e > 0) {
    const std::size_t se = fft_size(2 * e + 1);
    const std::vector<double> head(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(e));
    const std::vector<double> tail(y.end() - static_cast<std::ptrdiff_t>(e), y.end());
    const auto hs = spectrum(fft, head, se);
    const auto ts = spectrum(fft, tail, se);
    const auto conv_h = convolution(fft, hs, hs, 2 * e - 1);
    const auto conv_t = convolution(fft, ts, ts, 2 * e - 1);
    const auto acorr_h = correlation(fft, hs, hs, e);
    const auto acorr_t = correlation(fft, ts, ts, e);
    const auto ll = static_cast<std::ptrdiff_t>(l);
    for (std::size_t sg = 0; sg < 2 * e - 1; ++sg) {
      const double w = k.cum(static_cast<std::ptrdiff_t>(sg) + 1);
      total += static_cast<long double>(w * (conv_h[sg] - conv_t[sg]));
    }
    for (std::size_t d = 0; d < e; ++d) {
      const double both = d == 0 ? 1.0 : 2.0;
      const auto dd = static_cast<std::ptrdiff_t>(d);
      total -= static_cast<long double>(both * k.cum(2 * ll - 1 - dd) * acorr_h[d]);
      total += static_cast<long double>(both * k.cum(dd - 1) * acorr_t[d]);
    }
  }
  // Detrending: w_i = y_win - s_i r, s_i the slope between the means of the first and last
  // floor(L/2) points, D apart.
  const std::size_t half = l / 2;
  const double dist = l % 2 == 0 ? static_cast<double>(l) / 2.0 : static_cast<double>(l + 1) / 2.0;
  std::vector<long double> pre(n + 1, 0.0L);
  for (std::size_t t = 0; t < n; ++t) pre[t + 1] = pre[t] + static_cast<long double>(y[t]);
  const auto t_i = correlation(fft, spectrum(fft, k.u, s), ys, b);
  long double cross = 0.0L, sq = 0.0L;
  for (std::size_t i = 0; i < b; ++i) {
    const long double m1 = (pre[i + half] - pre[i]) / static_cast<long double>(half);
    const long double m2 = (pre[i + l] - pre[i + l - half]) / static_cast<long double>(half);
    const long double slope = (m2 - m1) / static_cast<long double>(dist);
    cross += slope * static_cast<long double>(t_i[i]);
    sq += slope * slope;
  }
  total += -2.0L * cross + static_cast<long double>(k.r_g_r) * sq;
  return total;
}

// Small factors: each window directly (O(m) with its reflected prefix sums), cheaper than FFTs
// of a few points and free of their cancellation.
long double direct_energy(std::span<const double> v, std::size_t m, std::size_t windows) {
  const std::size_t l = 3 * m;
  const std::size_t half = l / 2;
  const double dist = l % 2 == 0 ? static_cast<double>(l) / 2.0 : static_cast<double>(l + 1) / 2.0;
  std::vector<double> w(l), pre(3 * l + 1);
  long double total = 0.0L;
  for (std::size_t i = 0; i < windows; ++i) {
    const double* x = v.data() + i;
    double m1 = 0.0, m2 = 0.0;
    for (std::size_t t = 0; t < half; ++t) {
      m1 += x[t] - x[0];
      m2 += x[l - half + t] - x[0];
    }
    const double slope = (m2 - m1) / static_cast<double>(half) / dist;
    for (std::size_t t = 0; t < l; ++t) w[t] = (x[t] - x[0]) - slope * static_cast<double>(t);
    // Prefix sums of rev(w) w rev(w).
    pre[0] = 0.0;
    for (std::size_t t = 0; t < 3 * l; ++t) {
      const std::size_t seg = t / l, off = t % l;
      pre[t + 1] = pre[t] + (seg == 1 ? w[off] : w[l - 1 - off]);
    }
    double e = 0.0;
    for (std::size_t j = 0; j < 2 * l; ++j) {
      const double d = pre[j] - 3.0 * pre[j + m] + 3.0 * pre[j + 2 * m] - pre[j + 3 * m];
      e += d * d;
    }
    total += static_cast<long double>(e);
  }
  return total;
}

}  // namespace

sum_terms total_sum(std::span<const double> v, std::size_t m) {
  const std::size_t l = 3 * m;
  if (m == 0 || v.size() < l) return {};
  const std::size_t windows = v.size() - l + 1;
  if (m < direct_below) return {direct_energy(v, m, windows), windows};
  Eigen::FFT<double> fft;
  const auto k = make_kernel(m, fft);
  // Blocks of a few window lengths: the lagged products a block's sums weigh then span a few
  // times the statistic's own scale, so that their cancellation stays small (a block of 2^15
  // windows at m = 1 lost 5e-8 on a random walk); where a block is shorter than L - 1, the two
  // end corrections overlap and add up to the weights of pairs cut at both ends.
  const std::size_t block = std::max<std::size_t>(4 * l, 1024);
  long double sum = 0.0L;
  for (std::size_t i0 = 0; i0 < windows; i0 += block) {
    const std::size_t b = std::min(block, windows - i0);
    const std::size_t n = b + l - 1;
    sum += block_energy(k,
                        std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(i0),
                                            v.begin() + static_cast<std::ptrdiff_t>(i0 + n)),
                        b, fft);
  }
  return {sum, windows};
}

}  // namespace gyroflip::analysis::detail
