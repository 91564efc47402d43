/// \file
/// \brief Noise identification, EDF and chi-squared confidence bounds (see confidence.hpp).
#include "gyroflip/analysis/confidence.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "decimate.hpp"
#include "gyroflip/core/error.hpp"
#include "kernels.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis {
namespace {

// Regularised lower incomplete gamma P(a, x): series for x < a + 1, else the continued
// fraction for Q = 1 - P (modified Lentz).
double gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_prefix);
  }
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / tiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

// Greenhall's sw(t, alpha) (generalised autocovariance of the phase for noise alpha).
double sw(double t, int alpha) {
  const double at = std::abs(t);
  const double lg = at > 0.0 ? std::log(at) : 0.0;
  switch (alpha) {
    case 2:
      return -at;
    case 1:
      return t * t * lg;
    case 0:
      return at * at * at;
    case -1:
      return -(t * t) * (t * t) * lg;
    case -2:
      return -std::pow(at, 5.0);
    case -3:
      return std::pow(at, 6.0) * lg;
    default:
      return std::pow(at, 7.0);
  }
}

// sx: the filter of averaging over tau/F (F = 0 means F = infinity, the continuous limit).
double sx(double t, double f, int alpha) {
  if (f == 0.0) return sw(t, alpha + 2);
  return f * f * (2.0 * sw(t, alpha) - sw(t - 1.0 / f, alpha) - sw(t + 1.0 / f, alpha));
}

// sz: d-th difference of sx.
double sz(double t, double f, int alpha, int d) {
  const auto s = [&](double u) { return sx(u, f, alpha); };
  switch (d) {
    case 1:
      return 2.0 * s(t) - s(t - 1) - s(t + 1);
    case 2:
      return 6.0 * s(t) - 4.0 * (s(t - 1) + s(t + 1)) + s(t - 2) + s(t + 2);
    default:
      return 20.0 * s(t) - 15.0 * (s(t - 1) + s(t + 1)) + 6.0 * (s(t - 2) + s(t + 2)) -
             (s(t - 3) + s(t + 3));
  }
}

// Greenhall's basic sum: sz(0)^2 + (1 - J/M) sz(J/S)^2 + 2 sum_{j=1}^{J-1} (1 - j/M) sz(j/S)^2.
double basic_sum(double jj, double mm, double s, double f, int alpha, int d) {
  const double z0 = sz(0.0, f, alpha, d);
  double sum = z0 * z0;
  const double zj = sz(jj / s, f, alpha, d);
  sum += (1.0 - jj / mm) * zj * zj;
  const auto count = static_cast<std::size_t>(jj);
  for (std::size_t k = 1; k < count; ++k) {
    const auto j = static_cast<double>(k);
    const double z = sz(j / s, f, alpha, d);
    sum += 2.0 * (1.0 - j / mm) * z * z;
  }
  return sum;
}

// Greenhall & Riley, "Uncertainty of stability variances based on finite differences" (PTTI
// 2003), as Stable32 uses it: the basic sum directly while it has at most J_max = 100 terms,
// beyond that the large-r forms 1/edf = (a0 - a1/r)/r of their Tables 1-2 (Table 3 for flicker
// PM), or the basic sum of a reduced problem (m' = J_max/r) when r <= d + 1. So an EDF costs at
// most ~100 evaluations of sz whatever m and N (issue 13 item 16: the direct sums up to 20 000
// terms made `adev --taus all` spend 64 % of its time in log). Table values: Greenhall & Riley
// Tables 1-3 (docs/FACTS.md §6).
constexpr double j_max = 100.0;

struct table_ab {
  double a0, a1;
};
// Rows alpha = 2, 1, 0, -1, -2, -3, -4; columns d = 1, 2, 3 (Greenhall & Riley Tables 1-2; the same
// in W. J. Riley's CombinedEDF, T1/T2, and allantools' greenhall_table1/2). Only the entries with
// alpha + 2d > 1 are defined; the others are never read (greenhall_edf checks first).
constexpr std::size_t table_rows = 7;
using table_t = std::array<std::array<table_ab, 3>, table_rows>;
constexpr table_t table1 = {
    {// modified variances (case 1)
     {{{2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}, {22.0 / 25.0, 2.0 / 3.0}}},
     {{{0.840, 0.345}, {0.997, 0.616}, {1.141, 0.843}}},
     {{{1.079, 0.368}, {1.033, 0.607}, {1.184, 0.848}}},
     {{{0.0, 0.0}, {1.048, 0.534}, {1.180, 0.816}}},
     {{{0.0, 0.0}, {1.302, 0.535}, {1.175, 0.777}}},
     {{{0.0, 0.0}, {0.0, 0.0}, {1.194, 0.703}}},
     {{{0.0, 0.0}, {0.0, 0.0}, {1.489, 0.702}}}}};
constexpr table_t table2 = {
    {// unmodified variances (cases 2 and 3)
     {{{3.0 / 2.0, 1.0 / 2.0}, {35.0 / 18.0, 1.0}, {231.0 / 100.0, 3.0 / 2.0}}},
     {{{78.6, 25.2}, {790.0, 410.0}, {9950.0, 6520.0}}},
     {{{2.0 / 3.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 3.0}, {7.0 / 9.0, 1.0 / 2.0}}},
     {{{0.0, 0.0}, {0.852, 0.375}, {0.997, 0.617}}},
     {{{0.0, 0.0}, {1.079, 0.368}, {1.033, 0.607}}},
     {{{0.0, 0.0}, {0.0, 0.0}, {1.053, 0.553}}},
     {{{0.0, 0.0}, {0.0, 0.0}, {1.302, 0.535}}}}};
constexpr std::array<table_ab, 3> table3 = {
    {{6.0, 4.0}, {15.23, 12.0}, {47.8, 40.0}}};  // FPM b0 b1

// Whether Greenhall & Riley define an EDF for (alpha, d): d = 1, 2, 3, alpha = 2 .. -4 and
// alpha + 2d > 1 (the variance converges).
bool greenhall_defined(int alpha, int d) {
  return d >= 1 && d <= 3 && alpha >= -4 && alpha <= 2 && alpha + 2 * d > 1;
}

// The table entry of (alpha, d); an undefined (alpha, d) reads the zero entry, never past the
// table.
table_ab entry(const table_t& t, int alpha, int d) {
  if (!greenhall_defined(alpha, d)) return {0.0, 0.0};
  return t[static_cast<std::size_t>(2 - alpha)][static_cast<std::size_t>(d - 1)];
}

// Greenhall & Riley's EDF; 0 (no EDF) where they define none (greenhall_defined).
double greenhall_edf(int alpha, int d, std::size_t m_int, std::size_t n_phase, bool overlapping,
                     bool modified) {
  if (!greenhall_defined(alpha, d) || m_int == 0) return 0.0;
  const auto m = static_cast<double>(m_int);
  const auto n = static_cast<double>(n_phase);
  const double f = modified ? 1.0 : m;     // filter factor F
  const double s = overlapping ? m : 1.0;  // stride factor S
  const double l = m / f + m * d;          // phase samples one term spans
  const double big_m = 1.0 + std::floor(s * (n - l) / m);
  if (big_m < 1.0) return 0.0;
  const double j = std::min(big_m, (d + 1) * s);
  const double r = big_m / s;
  const auto from_sum = [&](double jj, double mm, double ss, double ff, double z0) {
    return 1.0 / (basic_sum(jj, mm, ss, ff, alpha, d) / (z0 * z0 * mm));
  };
  constexpr double inf = 0.0;  // sx's F = 0: the continuous limit (F = infinity)
  if (modified) {              // case 1
    if (j <= j_max) return from_sum(j, big_m, s, 1.0, sz(0.0, 1.0, alpha, d));
    if (r > d + 1) {
      const auto t = entry(table1, alpha, d);
      return 1.0 / ((t.a0 - t.a1 / r) / r);
    }
    return from_sum(j_max, j_max, j_max / r, 1.0, sz(0.0, 1.0, alpha, d));
  }
  if (alpha <= 0) {  // case 2
    if (j <= j_max) {
      const double fm = m * (d + 1) <= j_max ? m : inf;
      return from_sum(j, big_m, s, fm, sz(0.0, fm, alpha, d));
    }
    if (r > d + 1) {
      const auto t = entry(table2, alpha, d);
      return 1.0 / ((t.a0 - t.a1 / r) / r);
    }
    return from_sum(j_max, j_max, j_max / r, inf, sz(0.0, inf, alpha, d));
  }
  if (alpha == 1) {  // case 3
    if (j <= j_max) return from_sum(j, big_m, s, m, sz(0.0, m, alpha, d));
    const auto& b = table3[static_cast<std::size_t>(d - 1)];
    const double z0 = b.a0 + b.a1 * std::log(m);
    if (r > d + 1) {
      const auto t = entry(table2, alpha, d);
      return 1.0 / ((t.a0 - t.a1 / r) / (z0 * z0 * r));
    }
    return from_sum(j_max, j_max, j_max / r, j_max / r, z0);
  }
  // case 4, white PM: for r > d the closed form; else (a few terms) the basic sum.
  if (std::ceil(r) > d) {
    const double a0 = [d] {
      // binom(4d, 2d) / binom(2d, d)^2
      double num = 1.0, den = 1.0;
      for (int k = 1; k <= 2 * d; ++k) num *= static_cast<double>(2 * d + k) / k;
      for (int k = 1; k <= d; ++k) den *= static_cast<double>(d + k) / k;
      return num / (den * den);
    }();
    return 1.0 / ((a0 - 0.5 * d / r) / big_m);
  }
  return from_sum(std::min(j, j_max), std::min(big_m, j_max), s, m, sz(0.0, m, alpha, d));
}

// At most this many decimated points per factor: 2^20 pin r1 to ~1e-3, far finer than the 0.25
// decision steps; more would only cost time on long records (a 1e8-sample run at m = 1).
constexpr std::size_t max_points = std::size_t{1} << 20;
// Decimated points held at once while collecting them (128 MB): more factors take more passes.
constexpr std::size_t points_per_pass = std::size_t{1} << 24;

// The lag-1 identification on z (the phase decimated by m), which it differences in place.
constexpr std::size_t lag1_min_points = 30;  // Riley & Greenhall 2004: below, use B1 (SP1065 5.5)

// The lag-1 sums of z about its mean: num = sum_{i < n-1} (z_i - mean)(z_{i+1} - mean), den =
// sum_{i < n} (z_i - mean)^2, in four lanes each (one vector with AVX2): the sums of 2^20 points
// at up to seven factors were a tenth of HDEV's whole run on 1e8 samples in one chain each; the
// lanes change r1 by rounding only.
struct lag1_terms {
  double num = 0.0;
  double den = 0.0;
};

GYROFLIP_KERNEL_CLONES lag1_terms lag1_sums(const double* z, std::size_t n, double mean) {
  using detail::lanes4;
  const lanes4 mv = {mean, mean, mean, mean};
  lanes4 num = {0.0, 0.0, 0.0, 0.0}, den = num;
  std::size_t i = 0;
  lanes4 a, b;
  for (; i + 5 <= n; i += 4) {  // z_{i+4} exists
    std::memcpy(&a, z + i, sizeof a);
    std::memcpy(&b, z + i + 1, sizeof b);
    a -= mv;
    b -= mv;
    den += a * a;
    num += a * b;
  }
  lag1_terms t{(num[0] + num[1]) + (num[2] + num[3]), (den[0] + den[1]) + (den[2] + den[3])};
  for (; i < n; ++i) {
    t.den += (z[i] - mean) * (z[i] - mean);
    if (i + 1 < n) t.num += (z[i] - mean) * (z[i + 1] - mean);
  }
  return t;
}

std::optional<int> alpha_lag1(std::span<double> z) {
  for (int d = 0;; ++d) {
    if (z.size() < lag1_min_points) return std::nullopt;
    const double mean = detail::sum4(z.data(), z.size()) / static_cast<double>(z.size());
    const auto [num, den] = lag1_sums(z.data(), z.size(), mean);
    const double r1 = den > 0.0 ? num / den : 0.0;
    const double rho = r1 / (1.0 + r1);
    if (rho < 0.25 || d >= 2) {
      const int alpha = 2 - static_cast<int>(std::lround(2.0 * rho)) - 2 * d;
      return std::clamp(alpha, -2, 2);
    }
    for (std::size_t i = 0; i + 1 < z.size(); ++i) z[i] = z[i + 1] - z[i];
    z = z.first(z.size() - 1);
  }
}

// B1(N, mu): expected ratio of the standard variance of N frequency averages to their Allan
// variance for AVAR ~ tau^mu (Barnes; SP1065 eqn 67): N (1 - N^mu) / (2 (N - 1) (1 - 2^mu)),
// N ln N / (2 (N - 1) ln 2) at mu = 0.
double b1_theory(double n, int mu) {
  if (mu == 0) return n * std::log(n) / (2.0 * (n - 1.0) * std::log(2.0));
  const double m = mu;
  return n * (1.0 - std::pow(n, m)) / (2.0 * (n - 1.0) * (1.0 - std::pow(2.0, m)));
}

// Fewer than 5 decimated phase points (4 frequency averages) say nothing about the noise type.
constexpr std::size_t b1_min_points = 5;

// Stable32's B1 rule, as its tables show it (no published description; docs/ANALYSIS.md, "Noise
// identification"): the N of B1(N, mu) is the number of averages n for the non-overlapping ADEV
// and HDEV, and the number of frequency data (N phase points - 1) for every other kind, whose
// boundaries are then nearly the asymptotic ones (WFM/PM sqrt(2/3)); and a type is identified
// only up to half the largest factor of the kind's all-tau table (detail::max_factor: N/10 for
// ADEV and HDEV, N/8 for OADEV, MDEV, TDEV and OHDEV, N/6 for MTOTDEV, TTOTDEV and HTOTDEV, N/4
// for TOTDEV, N the span of the phase), the last type carried beyond. With both, our types are
// Stable32's on every B1 row of its nine PHASE.DAT all-tau tables (was 78-87 % of them;
// MTOTDEV/TTOTDEV 65 %).
std::size_t b1_theory_count(dev_kind k, std::size_t n_phase) {
  return k == dev_kind::adev || k == dev_kind::hdev ? 0 : n_phase - 1;
}

std::size_t identified_up_to(dev_kind k, std::size_t n_phase) {
  return n_phase > 1 ? detail::max_factor(k, n_phase) / 2 : 0;
}

// The B1 identification (SP1065 section 5.5, as Stable32 below 30 points): mu from the observed
// B1 = s^2 / AVAR of the n = z.size() - 1 averages at this tau, between the theoretical values
// B1(n_theory, mu) of mu = 1 (RWFM), 0 (FFM), -1 (WFM) and -2 (PM) with geometric-mean boundaries;
// alpha = -mu - 1, and PM (mu = -2) is returned as 2 for the caller to split with R(n). n_theory:
// see b1_theory_count.
std::optional<int> alpha_b1(std::span<const double> z, std::size_t n_theory) {
  if (z.size() < b1_min_points) return std::nullopt;
  const std::size_t n = z.size() - 1;
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) y[i] = z[i + 1] - z[i];
  double mean = 0.0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(n);
  double ss = 0.0;
  for (double v : y) ss += (v - mean) * (v - mean);
  double as = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) as += (y[i + 1] - y[i]) * (y[i + 1] - y[i]);
  const double var = ss / static_cast<double>(n - 1);
  const double avar = 0.5 * as / static_cast<double>(n - 1);
  if (!(avar > 0.0)) return std::nullopt;
  const double b1 = var / avar;
  const auto nn = static_cast<double>(n_theory > 1 ? n_theory : n);
  for (int mu = 1; mu > -2; --mu) {
    const double boundary = std::sqrt(b1_theory(nn, mu) * b1_theory(nn, mu - 1));
    if (b1 > boundary) return -mu - 1;
  }
  return 2;
}

// R(n) = MVAR/AVAR (SP1065 section 5.5; IEEE 1139) splits white PM (R = 1/m) from flicker PM
// (R = [3 ln(256/27)/(8 pi^2)] / [(1.038 + 3 ln(pi m))/(4 pi^2)], f_h = 1/(2 tau0)) with a
// geometric-mean boundary, from MDEV and OADEV at each m computed over the whole phase in one
// sweep for all the factors. Each costs a pass over the phase, so at most `max_rn` factors (the
// shortest) get it; the others are taken as flicker PM, the PM type with the smaller EDF (wider
// intervals). Only `--taus all` on a PM-dominated series reaches the limit.
constexpr std::size_t max_rn = 32;

std::vector<int> alpha_rn(const phase_source& x, const std::vector<std::size_t>& ms) {
  std::vector<int> out(ms.size(), 1);
  if (ms.empty()) return out;
  const tau_spec list{tau_spec::set::list, ms};
  const auto a = deviation(dev_kind::oadev, x, list);
  const auto mo = deviation(dev_kind::mdev, x, list);
  if (!a || !mo) return out;
  constexpr double pi = 3.14159265358979323846;
  for (std::size_t i = 0; i < ms.size(); ++i) {
    const auto find = [&](const std::vector<deviation_point>& pts) {
      for (const auto& p : pts)
        if (p.m == ms[i]) return p.dev;
      return 0.0;
    };
    const double ad = find(*a);
    const double md = find(*mo);
    if (!(ad > 0.0)) continue;
    const double rn = (md * md) / (ad * ad);
    const double mm = static_cast<double>(ms[i]);
    const double r_wpm = 1.0 / mm;
    const double r_fpm = (3.0 * std::log(256.0 / 27.0) / (8.0 * pi * pi)) /
                         ((1.038 + 3.0 * std::log(pi * mm)) / (4.0 * pi * pi));
    out[i] = rn < std::sqrt(r_wpm * r_fpm) ? 2 : 1;
  }
  return out;
}

// Each factor's type on its own decimated series (series(i): z of factor i, made on the worker,
// differenced in place), the factors side by side on all cores (lag-1 on up to 2^20 points each:
// 0.3 s of 1e8 samples' octave taus on one core): lag-1 autocorrelation with 30 points or more, the
// B1 ratio with 5 to 29 (by_b1 set).
template <typename Series>
void classify(std::size_t count, std::size_t held_points, std::size_t n_theory, Series series,
              std::optional<int>* ids, char* by_b1) {
  detail::for_each_item(count, detail::worker_count(held_points), [&](std::size_t, std::size_t i) {
    const std::span<double> z = series(i);
    const bool b1 = z.size() < lag1_min_points;
    by_b1[i] = b1 ? 1 : 0;
    ids[i] = b1 ? alpha_b1(z, n_theory) : alpha_lag1(z);
  });
}

// Beyond identified_up_to(k) no type (the caller carries the last one); PM read by B1: white or
// flicker by R(n), for the first max_rn such factors.
void split_pm(dev_kind k, const phase_source& x, const std::vector<std::size_t>& ms,
              std::vector<std::optional<int>>& ids, std::vector<char>& by_b1) {
  const std::size_t up_to = identified_up_to(k, x.size());
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (ms[i] > up_to) {
      ids[i] = std::nullopt;
      by_b1[i] = 0;
    }
  std::vector<std::size_t> pm;
  std::vector<std::size_t> pm_m;
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (by_b1[i] != 0 && ids[i] == 2) {
      if (pm.size() < max_rn) {
        pm.push_back(i);
        pm_m.push_back(ms[i]);
      } else {
        ids[i] = 1;
      }
    }
  const auto rn = alpha_rn(x, pm_m);
  for (std::size_t j = 0; j < pm.size(); ++j) ids[pm[j]] = rn[j];
}

std::vector<std::optional<int>> identify(dev_kind k, const phase_source& x,
                                         const std::vector<std::size_t>& ms,
                                         const progress_fn& on_progress);

// Beyond identified_up_to(k) the nearest shorter listed tau's type is carried (Stable32's rule);
// when no listed tau lies at or below that limit there is none to carry, and the type identified
// at the limit factor itself (the last factor of the all-tau table that is identified) is used
// rather than a fixed default (issue 23 review R-M1: white FM was assumed).
void seed_beyond_limit(dev_kind k, const phase_source& x, const std::vector<std::size_t>& ms,
                       std::vector<std::optional<int>>& ids) {
  const std::size_t up_to = identified_up_to(k, x.size());
  if (up_to == 0 || ms.empty() ||
      std::any_of(ms.begin(), ms.end(), [up_to](std::size_t m) { return m <= up_to; }))
    return;
  const auto at_limit = identify(k, x, {up_to}, {})[0];
  if (at_limit) ids[0] = at_limit;  // carried on to the others by fill_intervals
}

// Noise identification at every factor: the decimated series of as many factors as fit in
// points_per_pass are collected in one pass over the phase, then classified.
std::vector<std::optional<int>> identify(dev_kind k, const phase_source& x,
                                         const std::vector<std::size_t>& ms,
                                         const progress_fn& on_progress) {
  std::vector<std::vector<std::size_t>> passes(1);
  std::size_t held = 0;
  for (std::size_t m : ms) {
    const std::size_t len = std::min(max_points, (x.size() - 1) / m + 1);
    if (held + len > points_per_pass && !passes.back().empty()) {
      passes.emplace_back();
      held = 0;
    }
    passes.back().push_back(m);
    held += len;
  }
  std::vector<std::optional<int>> ids(ms.size());
  std::vector<char> by_b1(ms.size());
  std::size_t first = 0;
  for (std::size_t p = 0; p < passes.size(); ++p) {
    auto z = detail::decimated_prefixes(x, passes[p], max_points,
                                        detail::part_progress(on_progress, p, passes.size()));
    std::size_t held_points = 0;
    for (const auto& v : z) held_points += v.size();
    classify(
        z.size(), held_points, b1_theory_count(k, x.size()),
        [&z](std::size_t i) { return std::span<double>(z[i]); }, ids.data() + first,
        by_b1.data() + first);
    first += z.size();
  }
  split_pm(k, x, ms, ids, by_b1);
  seed_beyond_limit(k, x, ms, ids);
  return ids;
}

// As identify, the decimated series made from the block sums a deviation kept (heads; rate
// input): the same points x_{km}, k < min(max_points, (N-1)/m + 1), to rounding, without a read.
std::vector<std::optional<int>> identify_from_heads(dev_kind k, const phase_source& x,
                                                    const std::vector<std::size_t>& ms,
                                                    detail::block_heads& heads) {
  std::vector<std::size_t> levels;  // each level once (a factor may be asked for twice)
  for (std::size_t m : ms) levels.push_back(static_cast<std::size_t>(std::countr_zero(m)));
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  std::size_t held_points = 0;
  for (std::size_t j : levels) held_points += heads.counts[j] + 1;
  std::vector<std::optional<int>> level_ids(levels.size());
  std::vector<char> level_b1(levels.size());
  classify(
      levels.size(), held_points, b1_theory_count(k, x.size()),
      [&](std::size_t i) {
        return detail::decimated_from_heads(heads, levels[i], x.rate_mean(), x.tau0_s());
      },
      level_ids.data(), level_b1.data());
  std::vector<std::optional<int>> ids;
  std::vector<char> by_b1;
  for (std::size_t m : ms) {
    const auto i =
        static_cast<std::size_t>(std::lower_bound(levels.begin(), levels.end(),
                                                  static_cast<std::size_t>(std::countr_zero(m))) -
                                 levels.begin());
    ids.push_back(level_ids[i]);
    by_b1.push_back(level_b1[i]);
  }
  heads.sums.clear();
  split_pm(k, x, ms, ids, by_b1);
  seed_beyond_limit(k, x, ms, ids);
  return ids;
}

// SP1065 Table 5 (NIST TN 1337 Table 12-4): the simple OADEV EDF for N phase points, alpha 2 ..
// -2 (alpha below -2 as -2). Stable32 uses it for the Hadamard total deviation where Howe's fit
// does not apply (docs/ANALYSIS.md, "Intervals of the total family").
double edf_table5(int alpha, std::size_t m_int, std::size_t n_phase) {
  const auto n = static_cast<double>(n_phase);
  const auto m = static_cast<double>(m_int);
  switch (std::clamp(alpha, -2, 2)) {
    case 2:
      return (n + 1.0) * (n - 2.0 * m) / (2.0 * (n - m));
    case 1: {
      const double a = std::log((n - 1.0) / (2.0 * m));
      const double b = std::log((2.0 * m + 1.0) * (n - 1.0) / 4.0);
      return a > 0.0 && b > 0.0 ? std::exp(std::sqrt(a * b)) : 0.0;
    }
    case 0:
      return (3.0 * (n - 1.0) / (2.0 * m) - 2.0 * (n - 2.0) / n) * 4.0 * m * m /
             (4.0 * m * m + 5.0);
    case -1:
      return m == 1.0 ? 2.0 * (n - 2.0) * (n - 2.0) / (2.3 * n - 4.9)
                      : 5.0 * n * n / (4.0 * m * (n + 3.0 * m));
    default:
      return (n - 2.0) / (m * (n - 3.0) * (n - 3.0)) *
             ((n - 1.0) * (n - 1.0) - 3.0 * m * (n - 1.0) + 4.0 * m * m);
  }
}

// MTOTDEV/TTOTDEV as Stable32 computes them: up to m = 8 the MDEV EDF (Greenhall & Riley); beyond,
// b (T/tau) - c with T/tau = N/m (N phase points) and D. A. Howe's revised coefficients of
// 2000-05-20 (WPM 2.16, 2.28; FPM 1.73, 2.99; WFM 1.33, 1.89; FFM 0.92, 0.76; RWFM 0.79, 0.37),
// which replaced SP1065 Table 8's (1.90, 2.1 ... 0.75, 0.31) in Stable32 (W. J. Riley's EDF
// functions for Stable32, ModTotvarEDF). At least 1. PHASE.DAT: bounds within 5.2e-4 of
// Stable32 1.60's (docs/ANALYSIS.md).
constexpr std::size_t mtot_greenhall_max_m = 8;

double edf_modified_total(int alpha, std::size_t m, std::size_t n_phase) {
  if (m <= mtot_greenhall_max_m)
    return greenhall_edf(std::clamp(alpha, -2, 2), 2, m, n_phase, true, true);
  constexpr double b[5] = {2.16, 1.73, 1.33, 0.92, 0.79};  // alpha 2 .. -2
  constexpr double c[5] = {2.28, 2.99, 1.89, 0.76, 0.37};
  const auto row = static_cast<std::size_t>(2 - std::clamp(alpha, -2, 2));
  const double e = b[row] * static_cast<double>(n_phase) / static_cast<double>(m) - c[row];
  return e > 1.0 ? e : 1.0;
}

// HTOTDEV as Stable32 computes it: for frequency noise (alpha <= 0) from m = 16 on, Howe et al.'s
// fit (T/tau) / (b0 + b1 tau/T), T/tau = N/m ("A total estimator of the Hadamard function used
// for GPS operations", PTTI 2000: WFM 0.559, 1.004; FFM 0.868, 1.140; RWFM 0.938, 1.696; FWFM
// 0.974, 2.554; RRFM 1.276, 3.149); otherwise (shorter taus, phase noise) SP1065 Table 5's
// overlapping-Allan EDF, as Stable32's HTOT code does. At least 1.
constexpr std::size_t htot_fit_min_m = 16;

double edf_hadamard_total(int alpha, std::size_t m, std::size_t n_phase) {
  double e = 0.0;
  if (alpha <= 0 && m >= htot_fit_min_m) {
    constexpr double b0[5] = {0.559, 0.868, 0.938, 0.974, 1.276};  // alpha 0 .. -4
    constexpr double b1[5] = {1.004, 1.140, 1.696, 2.554, 3.149};
    const auto row = static_cast<std::size_t>(-std::clamp(alpha, -4, 0));
    const double ratio = static_cast<double>(n_phase) / static_cast<double>(m);
    e = ratio / (b0[row] + b1[row] / ratio);
  } else {
    e = edf_table5(alpha, m, n_phase);
  }
  return e > 1.0 ? e : 1.0;
}

// TOTDEV's EDF (SP1065 section 5.2.11): Table 11's b (T/tau) - c for white, flicker and random-walk
// FM (T/tau = (N-1)/m); Table 5's flicker-PM formula exp(sqrt(ln((N-1)/(2m)) ln((2m+1)(N-1)/4)))
// with alpha = 1 and the OADEV EDF with white PM, which is what Stable32 prints (GPS set: 6e-4).
// Beyond m = (N-1)/2 the fits are not defined (the first logarithm turns negative, Greenhall's
// term count to zero): at least 1 there, a wide interval rather than none.
double edf_totdev(int alpha, std::size_t m, std::size_t n_phase) {
  const double span = static_cast<double>(n_phase - 1);
  const double mm = static_cast<double>(m);
  const double t_over_tau = span / mm;
  double e = 0.0;
  if (alpha == 0) {
    e = 1.500 * t_over_tau;
  } else if (alpha == -1) {
    e = 1.168 * t_over_tau - 0.222;
  } else if (alpha <= -2) {
    e = 0.927 * t_over_tau - 0.358;
  } else if (alpha == 1) {
    e = edf_table5(1, m, n_phase);
  } else {
    e = greenhall_edf(alpha, 2, m, n_phase, true, false);
  }
  return e > 1.0 ? e : 1.0;
}

// Theo1's EDF: the fits of Howe & Peppler (EFTF/IFCS 2003), in SP1065's Theo1 section, in
// r = 0.75 m (Theo1's effective averaging factor) and N phase points, per power-law noise. Fits
// to simulations, checked here the same way: against Monte Carlo EDFs of white PM, white FM and
// random-walk FM (Confidence.Theo1EdfMatchesMonteCarlo: within 25 % where the EDF is above 5).
// Stable32's Theo1 tables print no bounds, so none to compare with. At least 1.
double edf_theo1(int alpha, std::size_t m, std::size_t n_phase) {
  const double n = static_cast<double>(n_phase);
  const double r = 0.75 * static_cast<double>(m);
  double e = 1.0;
  if (alpha >= 2) {
    e = 0.86 * (n + 1.0) * (n - 4.0 * r / 3.0) / (n - r) * (r / (r + 1.14));
  } else if (alpha == 1) {
    e = (4.798 * n * n - 6.374 * n * r + 12.387 * r) / (std::sqrt(r + 36.6) * (n - r)) *
        (r / (r + 0.3));
  } else if (alpha == 0) {
    const double r15 = r * std::sqrt(r);
    e = ((4.1 * n + 0.8) / r - (3.1 * n + 6.5) / n) * (r15 / (r15 + 5.2));
  } else if (alpha == -1) {
    e = (2.0 * n * n - 1.3 * n * r - 3.5 * r) / (n * r) * (r * r * r / (r * r * r + 2.3));
  } else {
    const double a = 4.4 * n - 1.0;
    e = (4.4 * n - 2.0) / (2.9 * r) *
        ((a * a - 8.6 * r * a + 11.4 * r * r) / ((a - 2.0) * (a - 2.0)));
  }
  return e > 1.0 ? e : 1.0;
}

// The guarded EDF at point i (edf_rule::guarded): no more than the types identified at the two
// neighbouring taus give at this m, nor the frequency-noise type carried on past a PM reading at
// a longer tau than one that showed frequency noise (PM's AVAR falls as tau^-2, so PM dominates
// only at short taus: a PM reading there is a misreading of a few points).
double guarded_edf(dev_kind k, const std::vector<int>& alpha, std::size_t i, std::size_t m,
                   std::size_t n_phase, double own) {
  int plausible = alpha[0];
  for (std::size_t j = 1; j <= i; ++j)
    plausible = alpha[j] >= 1 && plausible <= 0 ? plausible : alpha[j];
  double e = own;
  for (const int a :
       {plausible, i > 0 ? alpha[i - 1] : alpha[i], i + 1 < alpha.size() ? alpha[i + 1] : alpha[i]})
    if (a != alpha[i]) e = std::min(e, edf(k, a, m, n_phase));
  return e;
}

}  // namespace

double chi2_cdf(double x, double dof) {
  if (!(dof > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return gamma_p(0.5 * dof, 0.5 * x);
}

double chi2_quantile(double p, double dof) {
  const double a = 0.5 * dof;
  // Wilson-Hilferty start, then Newton on P(a, x/2) = p, kept inside a bracket.
  const double z = std::sqrt(2.0) * [p] {
    // inverse erf via a rational start + Newton on erf
    double x = 0.0;
    const double q = 2.0 * p - 1.0;
    for (int i = 0; i < 60; ++i) {
      const double e = std::erf(x) - q;
      x -= e / (2.0 / std::sqrt(3.141592653589793) * std::exp(-x * x));
      if (std::abs(e) < 1e-16) break;
    }
    return x;
  }();
  const double c = 2.0 / (9.0 * dof);
  double x = std::max(1e-300, dof * std::pow(1.0 - c + z * std::sqrt(c), 3.0));
  double lo = 0.0;
  double hi = std::max(4.0 * dof, 100.0);
  while (gamma_p(a, hi / 2.0) < p) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double g = gamma_p(a, x / 2.0) - p;
    if (g < 0.0)
      lo = x;
    else
      hi = x;
    // density of chi2 at x
    const double logpdf = (a - 1.0) * std::log(x / 2.0) - x / 2.0 - std::lgamma(a) - std::log(2.0);
    double next = x - g / std::exp(logpdf);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-13 * x) return next;
    x = next;
  }
  return x;
}

namespace {

// Continued fraction of the incomplete beta (A&S 26.5.8), modified Lentz's method.
double beta_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  d = 1.0 / (std::abs(d) < tiny ? tiny : d);
  double h = d;
  for (int m = 1; m <= 400; ++m) {
    const double md = m;
    for (const double num : {md * (b - md) * x / ((a + 2 * md - 1) * (a + 2 * md)),
                             -(a + md) * (a + b + md) * x / ((a + 2 * md) * (a + 2 * md + 1))}) {
      d = 1.0 + num * d;
      d = 1.0 / (std::abs(d) < tiny ? tiny : d);
      c = 1.0 + num / c;
      if (std::abs(c) < tiny) c = tiny;
      h *= d * c;
    }
    if (std::abs(d * c - 1.0) < 1e-15) break;
  }
  return h;
}

// Regularised incomplete beta I_x(a, b).
double beta_i(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  // The fraction converges fast for x < (a + 1)/(a + b + 2); else use the symmetry.
  if (x < (a + 1.0) / (a + b + 2.0)) return front * beta_fraction(a, b, x) / a;
  return 1.0 - front * beta_fraction(b, a, 1.0 - x) / b;
}

// P(T <= t) for t >= 0, Student's t with nu degrees of freedom (A&S 26.7.1).
double student_t_cdf(double t, double nu) {
  return 1.0 - 0.5 * beta_i(0.5 * nu, 0.5, nu / (nu + t * t));
}

}  // namespace

double student_t_quantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (p == 0.5) return 0.0;
  if (p < 0.5) return -student_t_quantile(1.0 - p, dof);
  double lo = 0.0;
  double hi = 1.0;
  while (student_t_cdf(hi, dof) < p && hi < 1e300) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (student_t_cdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double t_one_sigma(double dof) {
  if (!(dof > 0.0)) return 1.0;
  return student_t_quantile(0.5 * (1.0 + std::erf(1.0 / std::sqrt(2.0))), dof);
}

std::optional<int> noise_alpha_lag1(std::span<const double> phase, std::size_t m) {
  if (m == 0 || phase.empty()) return std::nullopt;
  std::vector<double> z;
  for (std::size_t i = 0; i < phase.size(); i += m) z.push_back(phase[i]);
  return alpha_lag1(z);
}

std::optional<int> noise_alpha(std::span<const double> phase, std::size_t m, dev_kind k) {
  const span_samples samples(phase);
  const auto src = phase_source::make(samples, input_kind::angle, 1.0);
  if (!src || src->size() == 0 || m == 0) return std::nullopt;
  return identify(k, *src, {m}, {})[0];
}

std::optional<double> edf_greenhall(int alpha, int d, std::size_t m, std::size_t n_phase,
                                    bool overlapping, bool modified) {
  if (!greenhall_defined(alpha, d) || m == 0) return std::nullopt;
  return greenhall_edf(alpha, d, m, n_phase, overlapping, modified);
}

double edf(dev_kind k, int alpha, std::size_t m, std::size_t n_phase) {
  switch (k) {
    case dev_kind::adev:
      return greenhall_edf(alpha, 2, m, n_phase, false, false);
    case dev_kind::oadev:
      return greenhall_edf(alpha, 2, m, n_phase, true, false);
    case dev_kind::mdev:
    case dev_kind::tdev:
      return greenhall_edf(alpha, 2, m, n_phase, true, true);
    case dev_kind::hdev:
      return greenhall_edf(alpha, 3, m, n_phase, false, false);
    case dev_kind::ohdev:
      return greenhall_edf(alpha, 3, m, n_phase, true, false);
    case dev_kind::totdev:
      return edf_totdev(alpha, m, n_phase);
    case dev_kind::mtotdev:
    case dev_kind::ttotdev:
      return edf_modified_total(alpha, m, n_phase);
    case dev_kind::htotdev:
      return edf_hadamard_total(alpha, m, n_phase);
    case dev_kind::theo1:
      return edf_theo1(alpha, m, n_phase);
    default:
      return 0.0;
  }
}

bool has_edf(dev_kind k) noexcept {
  return facts(k).edf;
}

void correct_total_bias(std::vector<deviation_point>& points, dev_kind k) {
  for (auto& p : points) {
    double b = 1.0;
    if (k == dev_kind::mtotdev || k == dev_kind::ttotdev) {
      constexpr double table[5] = {0.94, 0.83, 0.73, 0.70, 0.69};  // alpha 2 .. -2
      b = table[static_cast<std::size_t>(2 - std::clamp(p.alpha, -2, 2))];
    } else if (k == dev_kind::htotdev && p.m > 1 && p.alpha <= 0) {
      constexpr double table[5] = {0.995, 0.851, 0.771, 0.717, 0.679};  // alpha 0 .. -4
      b = table[static_cast<std::size_t>(-std::clamp(p.alpha, -4, 0))];
    }
    const double f = 1.0 / std::sqrt(b);
    p.dev *= f;
    p.ci_lo *= f;
    p.ci_hi *= f;
  }
}

status check_confidence_level(double level) {
  if (level > 0.0 && level < 1.0) return ok();
  return parameter_error(
      "level", fmt::format("the confidence level must be a probability in (0, 1), e.g. 0.683; "
                           "got {}",
                           level));
}

void add_confidence(std::vector<deviation_point>& points, dev_kind k, std::span<const double> phase,
                    double level, edf_rule rule) {
  // The phase as a source; tau0 matters for neither the noise type nor the EDF.
  const span_samples samples(phase);
  if (const auto src = phase_source::make(samples, input_kind::angle, 1.0))
    add_confidence(points, k, *src, level, {}, rule);
}

namespace {

// Theo1 lives at taus where fewer than lag1_min_points decimated points are left to identify the
// noise on; there B1 (with Stable32's N, b1_theory_count) cannot reach random-walk FM and often
// reads flicker FM as white FM or PM: intervals held the truth only ~50 % of the time at 68.3 %
// (issue 23 review R-H1; 300 records of 513 points). Stable32 prints no Theo1 bounds to follow,
// so ours take the smallest EDF of the type read and the three FM types there: wider, never
// narrower than the type's own (Confidence.Theo1BoundsCoverRandomWalkFm). A white-PM reading
// keeps its own EDF: there frequency noise is not read as white PM (bench/theo1_coverage.py, 300
// records of 513 and of 10 001 points per FM type, 7 factors each: none), flicker PM seldom (0-8
// of 300), and random-walk FM's EDF (a few) made white PM's bounds up to 7x too wide where its
// own is thousands (review E-M1; Confidence.Theo1WhitePmBoundsStayNarrow).
double theo1_few_point_edf(int alpha, std::size_t m, std::size_t n_phase) {
  double e = edf(dev_kind::theo1, alpha, m, n_phase);
  if (alpha >= 2 || (n_phase - 1) / m + 1 >= lag1_min_points) return e;
  for (const int fm : {0, -1, -2}) e = std::min(e, edf(dev_kind::theo1, fm, m, n_phase));
  return e;
}

// Fills the intervals of `points` from the types identified at their factors (ids, in order);
// `given`: the types are the caller's (add_confidence with alpha), not identified.
void fill_intervals(std::vector<deviation_point>& points, dev_kind k, std::size_t n_phase,
                    const std::vector<std::optional<int>>& ids, double level, edf_rule rule,
                    bool given = false) {
  // Too few points at a tau for any identification: the nearest shorter tau's type.
  std::vector<int> alpha(points.size());
  std::optional<int> last;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (ids[i]) last = ids[i];
    alpha[i] = ids[i] ? *ids[i] : last.value_or(0);
  }
  const double p_lo = 0.5 * (1.0 - level);
  for (std::size_t i = 0; i < points.size(); ++i) {
    auto& p = points[i];
    p.alpha = alpha[i];
    p.edf = k == dev_kind::theo1 && !given ? theo1_few_point_edf(alpha[i], p.m, n_phase)
                                           : edf(k, alpha[i], p.m, n_phase);
    if (rule == edf_rule::guarded) p.edf = guarded_edf(k, alpha, i, p.m, n_phase, p.edf);
    if (!(p.edf > 0.0)) {
      p.ci_lo = p.ci_hi = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    p.ci_lo = p.dev * std::sqrt(p.edf / chi2_quantile(1.0 - p_lo, p.edf));
    p.ci_hi = p.dev * std::sqrt(p.edf / chi2_quantile(p_lo, p.edf));
  }
}

std::vector<std::size_t> factors_of(const std::vector<deviation_point>& points) {
  std::vector<std::size_t> ms;
  ms.reserve(points.size());
  for (const auto& p : points) ms.push_back(p.m);
  return ms;
}

}  // namespace

void add_confidence(std::vector<deviation_point>& points, dev_kind k, std::size_t n_phase,
                    double level, int alpha) {
  fill_intervals(points, k, n_phase, std::vector<std::optional<int>>(points.size(), alpha), level,
                 edf_rule::stable32, true);
}

status check_noise_alpha(int alpha) {
  if (alpha >= -2 && alpha <= 2) return ok();
  return parameter_error("alpha", fmt::format("the noise type alpha must be 2 (white PM), 1 "
                                              "(flicker PM), 0 (white FM), -1 (flicker FM) or -2 "
                                              "(random-walk FM); got {}",
                                              alpha));
}

void add_confidence(std::vector<deviation_point>& points, dev_kind k, const phase_source& x,
                    double level, const progress_fn& on_progress, edf_rule rule) {
  const auto ms = factors_of(points);
  const auto ids =
      x.size() > 0 ? identify(k, x, ms, on_progress) : std::vector<std::optional<int>>(ms.size());
  fill_intervals(points, k, x.size(), ids, level, rule);
}

result<std::vector<deviation_point>> deviation_with_confidence(dev_kind k, const phase_source& x,
                                                               const tau_spec& taus, double level,
                                                               const progress_fn& on_progress,
                                                               edf_rule rule) {
  // ADEV/HDEV of rate samples at octave factors: the block sums' pass keeps the decimated
  // series' sums too (one read of the samples for the curve and the noise types).
  if (x.size() >= 3) {
    detail::block_heads heads;
    heads.cap = max_points - 1;
    if (auto r = detail::deviation_from_block_sums(k, x.samples(), x.kind(), x.tau0_s(), taus,
                                                   on_progress, &heads)) {
      if (*r)
        fill_intervals(**r, k, x.size(), identify_from_heads(k, x, factors_of(**r), heads), level,
                       rule);
      return std::move(*r);
    }
  }
  auto points = deviation(k, x, taus, detail::part_progress(on_progress, 0, 2));
  if (points) add_confidence(*points, k, x, level, detail::part_progress(on_progress, 1, 2), rule);
  return points;
}

}  // namespace gyroflip::analysis
