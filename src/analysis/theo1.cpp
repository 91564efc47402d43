/// \file
/// \brief Theo1 (SP1065 eqn 30) at many factors (see extended.hpp): prefix sums of x^2, one
/// autocorrelation of the whole phase, and per factor the autocorrelations of its first and last
/// m points and two weighted triangle sums, each by FFT: O(N log N + m log^2 m) per factor instead
/// of the direct (N - m) m / 2 terms. docs/ANALYSIS.md, "Theo1 by FFT", derives it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "extended.hpp"
#include "fft.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis::detail {
namespace {

// Factors below this are summed directly (theo1_sum: (N - m) m / 2 terms cost less than FFTs).
constexpr std::size_t fft_from = 128;
// Triangles of at most this many points a side are summed term by term.
constexpr std::size_t leaf = 128;
// The FFT path's rounding bound must stay below this fraction of its sum, else the direct sum.
constexpr double trusted = 1e-9;

// sum over i, j >= 0 with i + j < n of k(D + j - i) z_{a+i} z_{b+j}, D = b - a, k(d) = kern[d]
// for 0 <= d < kern.size() and 0 elsewhere. Split into the square i, j < ceil(n/2) (one
// cross-correlation by FFT, then a dot product with the kernel) and the two triangles beside it.
class triangle {
 public:
  triangle(const std::vector<double>& z, const std::vector<double>& kern, Eigen::FFT<double>& fft)
      : z_(z), kern_(kern), fft_(fft) {}

  long double sum(std::size_t a, std::size_t b, std::size_t n) {
    const auto d0 = static_cast<std::ptrdiff_t>(b) - static_cast<std::ptrdiff_t>(a);
    const auto nn = static_cast<std::ptrdiff_t>(n);
    // d = D + j - i lies in [D - (n - 1), D + (n - 1)]: nothing when that misses the kernel.
    if (n == 0 || d0 + nn - 1 < 0 || d0 - (nn - 1) >= kn()) return 0.0L;
    if (n <= leaf) return direct(a, b, n);
    const std::size_t s = (n + 1) / 2;
    return square(a, b, s) + sum(a + s, b, n - s) + sum(a, b + s, n - s);
  }

 private:
  [[nodiscard]] std::ptrdiff_t kn() const { return static_cast<std::ptrdiff_t>(kern_.size()); }

  [[nodiscard]] long double direct(std::size_t a, std::size_t b, std::size_t n) const {
    const auto d0 = static_cast<std::ptrdiff_t>(b) - static_cast<std::ptrdiff_t>(a);
    const auto nn = static_cast<std::ptrdiff_t>(n);
    long double total = 0.0L;
    for (std::ptrdiff_t i = 0; i < nn; ++i) {
      const std::ptrdiff_t j0 = std::max<std::ptrdiff_t>(0, i - d0);
      const std::ptrdiff_t j1 = std::min(nn - i, kn() + i - d0);
      double acc = 0.0;
      for (std::ptrdiff_t j = j0; j < j1; ++j)
        acc += kern_[static_cast<std::size_t>(d0 + j - i)] * z_[b + static_cast<std::size_t>(j)];
      total += static_cast<long double>(acc * z_[a + static_cast<std::size_t>(i)]);
    }
    return total;
  }

  long double square(std::size_t a, std::size_t b, std::size_t s) {
    const auto d0 = static_cast<std::ptrdiff_t>(b) - static_cast<std::ptrdiff_t>(a);
    const auto ss = static_cast<std::ptrdiff_t>(s);
    const std::ptrdiff_t t0 = std::max(-(ss - 1), -d0);
    const std::ptrdiff_t t1 = std::min(ss - 1, kn() - 1 - d0);
    if (t1 < t0) return 0.0L;
    const std::size_t p = fft_size(2 * s);
    const auto at = [&](std::size_t o) { return z_.begin() + static_cast<std::ptrdiff_t>(o); };
    const auto c = correlation(fft_, spectrum(fft_, at(a), at(a + s), p),
                               spectrum(fft_, at(b), at(b + s), p), p);
    const auto pp = static_cast<std::ptrdiff_t>(p);
    long double total = 0.0L;
    for (std::ptrdiff_t t = t0; t <= t1; ++t)
      total += static_cast<long double>(kern_[static_cast<std::size_t>(d0 + t)] *
                                        c[static_cast<std::size_t>(t >= 0 ? t : pp + t)]);
    return total;
  }

  const std::vector<double>& z_;
  const std::vector<double>& kern_;
  Eigen::FFT<double>& fft_;
};

// x less its least-squares line (Theo1 ignores a linear function added to the phase: the term
// x_i - x_{i+k} - x_{i+m-k} + x_{i+m} takes it out), so that the products below are small.
std::vector<double> detrended(std::span<const double> x) {
  const std::size_t n = x.size();
  long double st = 0.0L, sx = 0.0L, stt = 0.0L, stx = 0.0L;
  for (std::size_t t = 0; t < n; ++t) {
    const auto tt = static_cast<long double>(t);
    st += tt;
    sx += x[t];
    stt += tt * tt;
    stx += tt * x[t];
  }
  const auto nn = static_cast<long double>(n);
  const long double den = nn * stt - st * st;
  const long double slope = den > 0.0L ? (nn * stx - st * sx) / den : 0.0L;
  const long double offset = (sx - slope * st) / nn;
  std::vector<double> out(n);
  for (std::size_t t = 0; t < n; ++t)
    out[t] = static_cast<double>(x[t] - (offset + slope * static_cast<long double>(t)));
  return out;
}

// What every factor shares: the detrended phase, the prefix sums of its squares and its
// autocorrelation r(l), l <= the largest factor.
struct shared_sums {
  std::vector<double> x;
  std::vector<long double> sq;  // sq[t] = sum_{j<t} x_j^2
  std::vector<double> r;
  double fft_log2 = 0.0;  // log2 of the largest transform (the rounding bound's growth)
  [[nodiscard]] long double q(std::size_t a, std::size_t b) const { return sq[b] - sq[a]; }
};

// Theo1's sum at m by FFT (docs/ANALYSIS.md), with the bound of its rounding.
struct fft_sum {
  long double sum = 0.0L;
  double bound = 0.0;
};

fft_sum theo1_fft(const shared_sums& sh, std::size_t m, Eigen::FFT<double>& fft) {
  const std::vector<double>& x = sh.x;
  const std::size_t n = x.size();
  const std::size_t h = m / 2;
  const std::size_t len = n - m;  // L, the number of i
  // Autocorrelations of the first m points (f) and the last m points (e), lags < m.
  const std::size_t p = fft_size(2 * m);
  const auto first = spectrum(fft, x.begin(), x.begin() + static_cast<std::ptrdiff_t>(m), p);
  const auto last = spectrum(fft, x.end() - static_cast<std::ptrdiff_t>(m), x.end(), p);
  const auto f = correlation(fft, first, first, m);
  const auto e = correlation(fft, last, last, m);
  const auto& r = sh.r;
  long double total = 0.0L;
  double harmonic = 0.0;
  for (std::size_t k = 1; k <= h; ++k) {
    const long double t = sh.q(0, len) + sh.q(k, k + len) + sh.q(m - k, m - k + len) + sh.q(m, n) -
                          4.0L * r[k] - 4.0L * r[m - k] + 2.0L * r[m] + 2.0L * r[m - 2 * k] +
                          2.0L * (e[k] + e[m - k] + f[k] + f[m - k]);
    total += t / static_cast<long double>(k);
    harmonic += 1.0 / static_cast<double>(k);
  }
  // The pairs (p, q) of the x_{i+k} x_{i+m-k} products that the full autocorrelation counts
  // beyond the window of i: p + q <= m - 2 among the first m - 1 points, and the same among the
  // last m - 1 read backwards; weight 1/k = 2/(m - d) at lag d = q - p = m - 2k.
  std::vector<double> kern(m - 1, 0.0);
  for (std::size_t d = 0; d + 2 <= m; d += 2) kern[d] = 2.0 / static_cast<double>(m - d);
  const std::vector<double> head(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(m - 1));
  const std::vector<double> tail(x.rbegin(), x.rbegin() + static_cast<std::ptrdiff_t>(m - 1));
  total -= 2.0L * triangle(head, kern, fft).sum(0, 0, m - 1);
  total -= 2.0L * triangle(tail, kern, fft).sum(0, 0, m - 1);
  // Each correlation value is off by at most ~eps log2(size) sum x^2; the sum weighs about 30 of
  // them (12 of r, 8 of e and f, the triangles' levels) by 1/k each.
  const double energy = static_cast<double>(sh.sq[n]);
  const double bound =
      64.0 * std::numeric_limits<double>::epsilon() * sh.fft_log2 * energy * harmonic;
  return {total, bound};
}

}  // namespace

std::vector<sum_terms> theo1_sums(std::span<const double> x, std::span<const std::size_t> ms,
                                  const progress_fn& progress) {
  const std::size_t n = x.size();
  std::vector<sum_terms> out(ms.size());
  std::vector<std::size_t> by_fft;  // indices into ms, largest factor first
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const std::size_t m = ms[i];
    if (m < 2 || m % 2 != 0 || m >= n) continue;
    if (m < fft_from) {
      out[i] = theo1_sum(x, m);
    } else {
      by_fft.push_back(i);
    }
  }
  if (by_fft.empty()) return out;
  std::sort(by_fft.begin(), by_fft.end(),
            [&](std::size_t a, std::size_t b) { return ms[a] > ms[b]; });
  shared_sums sh;
  sh.x = detrended(x);
  sh.sq.assign(n + 1, 0.0L);
  for (std::size_t t = 0; t < n; ++t)
    sh.sq[t + 1] = sh.sq[t] + static_cast<long double>(sh.x[t]) * sh.x[t];
  const std::size_t top = ms[by_fft.front()];
  // Real series: half spectra (less memory than full ones).
  const auto half = [](Eigen::FFT<double>& f) { f.SetFlag(Eigen::FFT<double>::HalfSpectrum); };
  {
    Eigen::FFT<double> fft;
    half(fft);
    const std::size_t s = fft_size(n + top + 1);
    sh.fft_log2 = std::log2(static_cast<double>(s));
    const auto xs = spectrum(fft, sh.x, s);
    sh.r = correlation(fft, xs, xs, top + 1);
  }
  std::vector<fft_sum> sums(by_fft.size());
  std::vector<Eigen::FFT<double>> ffts(std::max<std::size_t>(1, worker_count(n)));
  for (auto& f : ffts) half(f);
  for_each_item(
      by_fft.size(), ffts.size(),
      [&](std::size_t w, std::size_t j) { sums[j] = theo1_fft(sh, ms[by_fft[j]], ffts[w]); },
      progress);
  for (std::size_t j = 0; j < by_fft.size(); ++j) {
    const std::size_t m = ms[by_fft[j]];
    if (sums[j].bound <= trusted * static_cast<double>(sums[j].sum)) {
      out[by_fft[j]] = {sums[j].sum, (n - m) * (m / 2)};
    } else {
      out[by_fft[j]] = theo1_sum(sh.x, m);  // large terms against a small sum: term by term
    }
  }
  return out;
}

}  // namespace gyroflip::analysis::detail
