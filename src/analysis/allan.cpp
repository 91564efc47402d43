/// \file
/// \brief The Allan-deviation family on a phase series (see allan.hpp).
///
/// Each statistic is one pass over the phase per averaging factor. Squared differences are
/// summed in double within blocks of 4096 terms (4 interleaved accumulators, so the loop
/// pipelines) and the block sums in long double: the relative rounding error stays ~1e-12 for
/// any length, where one running double sum over 1e9 terms would lose ~1e-7.
#include "gyroflip/analysis/allan.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <thread>
#include <utility>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::analysis {
namespace {

constexpr std::size_t block_terms = 4096;

using progress_fn = std::function<void(std::size_t, std::size_t)>;

// Sum of f(i)^2 for i in [begin, end), blockwise (see the file comment).
template <class F>
long double sum_squares(std::size_t begin, std::size_t end, F f) {
  long double total = 0.0L;
  for (std::size_t b = begin; b < end; b += block_terms) {
    const std::size_t e = std::min(end, b + block_terms);
    double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
    std::size_t i = b;
    for (; i + 4 <= e; i += 4) {
      const double d0 = f(i), d1 = f(i + 1), d2 = f(i + 2), d3 = f(i + 3);
      a0 += d0 * d0;
      a1 += d1 * d1;
      a2 += d2 * d2;
      a3 += d3 * d3;
    }
    for (; i < e; ++i) {
      const double d = f(i);
      a0 += d * d;
    }
    total += static_cast<long double>((a0 + a1) + (a2 + a3));
  }
  return total;
}

double finish(long double sum_sq, long double denom) {
  return static_cast<double>(std::sqrt(sum_sq / denom));
}

raw_deviation adev_nonoverlapping(std::span<const double> x, double tau, std::size_t m) {
  const std::size_t groups = (x.size() - 1) / m;  // phase points at stride m, minus one
  if (groups < 2) return {};
  const std::size_t n = groups - 1;
  const auto s = sum_squares(
      0, n, [&](std::size_t k) { return x[(k + 2) * m] - 2.0 * x[(k + 1) * m] + x[k * m]; });
  return {finish(s, 2.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)), n};
}

raw_deviation oadev_at(std::span<const double> x, double tau, std::size_t m) {
  if (x.size() < 2 * m + 1) return {};
  const std::size_t n = x.size() - 2 * m;
  const double* p = x.data();
  const auto s =
      sum_squares(0, n, [p, m](std::size_t i) { return p[i + 2 * m] - 2.0 * p[i + m] + p[i]; });
  return {finish(s, 2.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)), n};
}

raw_deviation mdev_at(std::span<const double> x, double tau, std::size_t m) {
  if (x.size() < 3 * m) return {};
  const std::size_t n = x.size() - 3 * m + 1;
  const double* p = x.data();
  const auto d = [p, m](std::size_t i) { return p[i + 2 * m] - 2.0 * p[i + m] + p[i]; };
  // inner(j) = sum_{i=j}^{j+m-1} d(i) slides by one term per step. The slide is a dependency
  // chain, so the j range is cut into `lanes` segments run side by side, each started from an
  // exact sum. Rounding in a double slide grows like sqrt(steps) eps: ~1e-12 relative at 1e8.
  constexpr std::size_t lanes = 4;
  const std::size_t seg = (n + lanes - 1) / lanes;
  std::array<double, lanes> inner{};
  std::array<std::size_t, lanes> start{};
  std::array<std::size_t, lanes> len{};
  for (std::size_t l = 0; l < lanes; ++l) {
    start[l] = std::min(n, l * seg);
    len[l] = std::min(seg, n - start[l]);
    for (std::size_t i = 0; i < m && len[l] > 0; ++i) inner[l] += d(start[l] + i);
  }
  long double total = 0.0L;
  std::array<double, lanes> acc{};
  for (std::size_t t = 0; t < seg; ++t) {
    for (std::size_t l = 0; l < lanes; ++l) {
      if (t >= len[l]) continue;
      acc[l] += inner[l] * inner[l];
      const std::size_t j = start[l] + t;
      if (t + 1 < len[l]) inner[l] += d(j + m) - d(j);
    }
    if ((t + 1) % block_terms == 0) {
      for (double& a : acc) total += static_cast<long double>(std::exchange(a, 0.0));
    }
  }
  for (double a : acc) total += static_cast<long double>(a);
  const auto mm = static_cast<long double>(m);
  return {finish(total, 2.0L * mm * mm * static_cast<long double>(tau * tau) *
                            static_cast<long double>(n)),
          n};
}

raw_deviation hdev_nonoverlapping(std::span<const double> x, double tau, std::size_t m) {
  const std::size_t groups = (x.size() - 1) / m;
  if (groups < 3) return {};
  const std::size_t n = groups - 2;
  const auto s = sum_squares(0, n, [&](std::size_t k) {
    return x[(k + 3) * m] - 3.0 * x[(k + 2) * m] + 3.0 * x[(k + 1) * m] - x[k * m];
  });
  return {finish(s, 6.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)), n};
}

raw_deviation ohdev_at(std::span<const double> x, double tau, std::size_t m) {
  if (x.size() < 3 * m + 1) return {};
  const std::size_t n = x.size() - 3 * m;
  const double* p = x.data();
  const auto s = sum_squares(0, n, [p, m](std::size_t i) {
    return p[i + 3 * m] - 3.0 * p[i + 2 * m] + 3.0 * p[i + m] - p[i];
  });
  return {finish(s, 6.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)), n};
}

raw_deviation totdev_at(std::span<const double> x, double tau, std::size_t m) {
  const std::size_t big_n = x.size();
  if (big_n < 3 || m > big_n - 2) return {};
  const double* p = x.data();
  const double first = p[0];
  const double last = p[big_n - 1];
  // x*(k) with reflection at both ends (SP1065 eqn 25); k in [-(N-1), 2(N-1)].
  const auto xs = [=](std::ptrdiff_t k) {
    const auto nn = static_cast<std::ptrdiff_t>(big_n);
    if (k < 0) return 2.0 * first - p[-k];
    if (k >= nn) return 2.0 * last - p[2 * (nn - 1) - k];
    return p[k];
  };
  const auto mi = static_cast<std::ptrdiff_t>(m);
  // Centres i = 1..N-2; the middle range needs no reflection and runs branch-free.
  const std::size_t lo = std::max<std::size_t>(1, m);
  const std::size_t hi = std::min(big_n - 2, big_n - 1 - m);  // last centre with i + m <= N - 1
  long double s = 0.0L;
  const auto edge = [&](std::size_t i) {
    const auto ii = static_cast<std::ptrdiff_t>(i);
    const double d = xs(ii - mi) - 2.0 * p[i] + xs(ii + mi);
    return d;
  };
  if (lo <= hi) {
    s += sum_squares(1, lo, edge);
    s +=
        sum_squares(lo, hi + 1, [p, m](std::size_t i) { return p[i - m] - 2.0 * p[i] + p[i + m]; });
    s += sum_squares(hi + 1, big_n - 1, edge);
  } else {
    s += sum_squares(1, big_n - 1, edge);
  }
  const std::size_t n = big_n - 2;
  return {finish(s, 2.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)), n};
}

long double totdev_edges(std::span<const double> x, std::size_t m) {
  // Left centres i = 1..m-1 reach below 0 (x*_{i-m} = 2x_0 - x_{m-i}); right centres
  // i = N-m..N-2 reach past N-1 (x*_{i+m} = 2x_{N-1} - x_{2(N-1)-i-m}). Each side on its own,
  // so the loops have no branches.
  const std::size_t big_n = x.size();
  const double* p = x.data();
  const double first2 = 2.0 * p[0];
  const double last2 = 2.0 * p[big_n - 1];
  const std::size_t top = 2 * (big_n - 1);
  const long double left =
      sum_squares(1, m, [=](std::size_t i) { return (first2 - p[m - i]) - 2.0 * p[i] + p[i + m]; });
  const long double right = sum_squares(big_n - m, big_n - 1, [=](std::size_t i) {
    return p[i - m] - 2.0 * p[i] + (last2 - p[top - i - m]);
  });
  return left + right;
}

// Runs f(i) for i in [0, count) on `threads` threads (the caller's included), each taking the
// next index; f(i) may not touch another index's data.
template <class F>
void parallel_for(std::size_t count, std::size_t threads, F f) {
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) f(i);
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < std::min(threads, count); ++t) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
}

// Sums of the OADEV terms (x_{i+2m} - 2x_{i+m} + x_i)^2 over all i, for many averaging factors
// in one sweep: the phase is walked in cache-sized blocks and every factor's terms for that block
// are summed while the block is hot, so x_{i+m} and x_{i+2m} come from cache for every m up to
// about half a block. Only the largest octaves still stream from memory: ~4x less memory
// traffic than one pass per factor (1e8, octave). Threads split the index range.
std::vector<long double> oadev_sums(std::span<const double> x, const std::vector<std::size_t>& ms,
                                    std::size_t threads, const progress_fn& on_tau) {
  const std::size_t big_n = x.size();
  const double* p = x.data();
  constexpr std::size_t block = std::size_t{1} << 15;  // 256 KB of phase
  std::vector<std::vector<long double>> partial(threads, std::vector<long double>(ms.size(), 0.0L));
  const auto sweep = [&](std::size_t t) {
    const std::size_t lo = big_n * t / threads;
    const std::size_t hi = big_n * (t + 1) / threads;
    for (std::size_t b = lo; b < hi; b += block) {
      // Thread 0 reports its share done as a fraction of the factors (for a progress line).
      if (t == 0 && on_tau)
        on_tau((b - lo) * ms.size() / std::max<std::size_t>(hi - lo, 1), ms.size());
      const std::size_t be = std::min(hi, b + block);
      for (std::size_t k = 0; k < ms.size(); ++k) {
        const std::size_t m = ms[k];
        if (big_n < 2 * m + 1) continue;
        const std::size_t end = std::min(be, big_n - 2 * m);
        if (end <= b) continue;
        partial[t][k] += sum_squares(
            b, end, [p, m](std::size_t i) { return p[i + 2 * m] - 2.0 * p[i + m] + p[i]; });
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(sweep, t);
  sweep(0);
  for (auto& th : pool) th.join();
  std::vector<long double> out(ms.size(), 0.0L);
  for (std::size_t t = 0; t < threads; ++t)
    for (std::size_t k = 0; k < ms.size(); ++k) out[k] += partial[t][k];
  return out;
}

// OADEV (eqn 11) and TOTDEV (eqn 25) from the fused sums. TOTDEV's centres i = m..N-1-m need no
// reflection, and their terms are exactly all OADEV terms; only the m - 1 reflected centres at
// each end are added (totdev_edges).
std::vector<raw_deviation> fused(dev_kind k, std::span<const double> x, double tau0_s,
                                 const std::vector<std::size_t>& ms, std::size_t threads,
                                 const progress_fn& on_tau) {
  const auto sums = oadev_sums(x, ms, threads, on_tau);
  const std::size_t big_n = x.size();
  std::vector<raw_deviation> out(ms.size());
  parallel_for(ms.size(), threads, [&](std::size_t i) {
    const std::size_t m = ms[i];
    const double tau = static_cast<double>(m) * tau0_s;
    if (k == dev_kind::oadev) {
      if (big_n < 2 * m + 1) return;
      const std::size_t n = big_n - 2 * m;
      out[i] = {
          finish(sums[i], 2.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)),
          n};
    } else if (big_n >= 2 * m + 1) {  // totdev with at least one unreflected centre
      const std::size_t n = big_n - 2;
      out[i] = {finish(sums[i] + totdev_edges(x, m),
                       2.0L * static_cast<long double>(tau * tau) * static_cast<long double>(n)),
                n};
    } else {
      out[i] = totdev_at(x, tau, m);
    }
  });
  return out;
}

// The curve from per-factor results, dropping factors without terms.
result<std::vector<deviation_point>> collect(const std::vector<std::size_t>& factors,
                                             const std::vector<raw_deviation>& raw, double tau0_s) {
  std::vector<deviation_point> out;
  for (std::size_t i = 0; i < factors.size(); ++i) {
    if (raw[i].n == 0) continue;
    deviation_point p;
    p.m = factors[i];
    p.tau_s = static_cast<double>(factors[i]) * tau0_s;
    p.dev = raw[i].dev;
    p.n = raw[i].n;
    out.push_back(p);
  }
  if (out.empty())
    return runtime_error("no averaging time fits the data (series too short for the taus asked)");
  return out;
}

std::size_t max_factor(dev_kind k, std::size_t n_phase) {
  const std::size_t span = n_phase - 1;
  switch (k) {
    case dev_kind::adev:
    case dev_kind::hdev:
      return span / 5;
    case dev_kind::totdev:
      return span / 2;
    default:
      return span / 4;
  }
}

}  // namespace

std::string_view to_string(dev_kind k) noexcept {
  switch (k) {
    case dev_kind::adev:
      return "adev";
    case dev_kind::oadev:
      return "oadev";
    case dev_kind::mdev:
      return "mdev";
    case dev_kind::tdev:
      return "tdev";
    case dev_kind::hdev:
      return "hdev";
    case dev_kind::ohdev:
      return "ohdev";
    case dev_kind::totdev:
      return "totdev";
  }
  return "?";
}

std::optional<dev_kind> parse_dev_kind(std::string_view name) noexcept {
  for (dev_kind k : {dev_kind::adev, dev_kind::oadev, dev_kind::mdev, dev_kind::tdev,
                     dev_kind::hdev, dev_kind::ohdev, dev_kind::totdev})
    if (to_string(k) == name) return k;
  return std::nullopt;
}

result<tau_spec> parse_tau_spec(std::string_view text) {
  if (text == "octave") return tau_spec{tau_spec::set::octave, {}};
  if (text == "decade") return tau_spec{tau_spec::set::decade, {}};
  if (text == "all") return tau_spec{tau_spec::set::all, {}};
  tau_spec s{tau_spec::set::list, {}};
  std::string_view rest = text;
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    const std::string_view part = rest.substr(0, comma);
    std::size_t m = 0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), m);
    if (ec != std::errc{} || end != part.data() + part.size() || m == 0)
      return usage_error(
          fmt::format("--taus '{}': expected octave, decade, all or averaging factors "
                      "like 1,2,10 (whole numbers >= 1); '{}' is not one",
                      text, part));
    s.factors.push_back(m);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (s.factors.empty()) return usage_error("--taus: empty list");
  std::sort(s.factors.begin(), s.factors.end());
  s.factors.erase(std::unique(s.factors.begin(), s.factors.end()), s.factors.end());
  return s;
}

std::vector<double> phase_from_rate(std::span<const double> rate, double tau0_s,
                                    const std::function<void(std::size_t, std::size_t)>& consumed) {
  // Sums in double within blocks of block_terms samples and carries the block totals in long
  // double: within a block the partial sum of (y - ybar) stays small, so double keeps it to
  // ~1e-16 relative, and the slow x87 arithmetic runs once per block instead of per sample.
  constexpr std::size_t release_step = std::size_t{1} << 20;  // samples per `consumed` call
  const std::size_t n = rate.size();
  long double total = 0.0L;
  for (std::size_t b = 0; b < n; b += block_terms) {
    double part = 0.0;
    for (std::size_t i = b; i < std::min(n, b + block_terms); ++i) part += rate[i];
    total += static_cast<long double>(part);
    if (consumed && (b + block_terms) % release_step == 0)
      consumed(b + block_terms - release_step, b + block_terms);
  }
  if (consumed) consumed(n / release_step * release_step, n);
  const double mean =
      static_cast<double>(total / static_cast<long double>(std::max<std::size_t>(n, 1)));
  // Filled by push_back, not zero-filled: pages become resident only as they are written, so
  // with a caller that releases consumed input the two arrays are never resident together.
  std::vector<double> x;
  x.reserve(n + 1);
  x.push_back(0.0);          // x_0 = 0
  long double carry = 0.0L;  // sum of (y - mean) before the current block
  for (std::size_t b = 0; b < n; b += block_terms) {
    const std::size_t e = std::min(n, b + block_terms);
    const auto base = static_cast<double>(carry);
    const double base_err = static_cast<double>(carry - static_cast<long double>(base));
    double part = 0.0;
    for (std::size_t i = b; i < e; ++i) {
      part += rate[i] - mean;
      x.push_back((base + (part + base_err)) * tau0_s);
    }
    carry += static_cast<long double>(part);
    if (consumed && e % release_step == 0) consumed(e - release_step, e);
  }
  if (consumed) consumed(n / release_step * release_step, n);
  return x;
}

std::vector<std::size_t> averaging_factors(const tau_spec& spec, dev_kind k, std::size_t n_phase) {
  std::vector<std::size_t> out;
  if (n_phase < 3) return out;
  const std::size_t limit = std::max<std::size_t>(1, max_factor(k, n_phase));
  switch (spec.kind) {
    case tau_spec::set::octave:
      for (std::size_t m = 1; m <= limit; m *= 2) out.push_back(m);
      break;
    case tau_spec::set::decade:
      for (std::size_t d = 1; d <= limit; d *= 10)
        for (std::size_t f : {1u, 2u, 4u})
          if (f * d <= limit) out.push_back(f * d);
      break;
    case tau_spec::set::all:
      for (std::size_t m = 1; m <= limit; ++m) out.push_back(m);
      break;
    case tau_spec::set::list:
      for (std::size_t m : spec.factors)
        if (m < n_phase) out.push_back(m);
      break;
  }
  return out;
}

raw_deviation deviation_at(dev_kind k, std::span<const double> x, double tau0_s, std::size_t m) {
  const double tau = static_cast<double>(m) * tau0_s;
  switch (k) {
    case dev_kind::adev:
      return adev_nonoverlapping(x, tau, m);
    case dev_kind::oadev:
      return oadev_at(x, tau, m);
    case dev_kind::mdev:
      return mdev_at(x, tau, m);
    case dev_kind::tdev: {
      const auto r = mdev_at(x, tau, m);
      return {tau * r.dev / std::sqrt(3.0), r.n};
    }
    case dev_kind::hdev:
      return hdev_nonoverlapping(x, tau, m);
    case dev_kind::ohdev:
      return ohdev_at(x, tau, m);
    case dev_kind::totdev:
      return totdev_at(x, tau, m);
  }
  return {};
}

result<std::vector<deviation_point>> deviation_of_phase(
    dev_kind k, std::span<const double> x, double tau0_s, const tau_spec& taus,
    const std::function<void(std::size_t, std::size_t)>& on_tau) {
  if (!(tau0_s > 0.0) || !std::isfinite(tau0_s))
    return usage_error(fmt::format("sample interval {} s must be positive and finite", tau0_s));
  if (x.size() < 3)
    return runtime_error(
        fmt::format("{} phase points are too few for an Allan deviation", x.size()));
  const auto factors = averaging_factors(taus, k, x.size());
  const std::size_t threads =
      x.size() < (std::size_t{1} << 16)
          ? 1
          : std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), 8);
  if (k == dev_kind::oadev || k == dev_kind::totdev) {
    const auto raw = fused(k, x, tau0_s, factors, threads, on_tau);
    if (on_tau) on_tau(factors.size(), factors.size());
    return collect(factors, raw, tau0_s);
  }
  std::vector<raw_deviation> raw(factors.size());
  // Each averaging time is an independent pass over the phase: spread them over the cores
  // (the passes are memory-bound, so two threads on two cores nearly halve the time).
  std::atomic<std::size_t> done{0};
  const auto caller = std::this_thread::get_id();  // only the caller's thread reports progress
  parallel_for(factors.size(), threads, [&](std::size_t i) {
    raw[i] = deviation_at(k, x, tau0_s, factors[i]);
    const std::size_t d = ++done;
    if (on_tau && std::this_thread::get_id() == caller) on_tau(d, factors.size());
  });
  if (on_tau) on_tau(done.load(), factors.size());
  return collect(factors, raw, tau0_s);
}

result<std::vector<deviation_point>> deviation(dev_kind k, std::span<const double> data,
                                               input_kind in, double tau0_s, const tau_spec& taus) {
  if (!(tau0_s > 0.0) || !std::isfinite(tau0_s))
    return usage_error(fmt::format("sample interval {} s must be positive and finite", tau0_s));
  for (double v : data)
    if (!std::isfinite(v)) return usage_error("data contain a non-finite value");
  if (in == input_kind::angle) return deviation_of_phase(k, data, tau0_s, taus);
  return deviation_of_phase(k, phase_from_rate(data, tau0_s), tau0_s, taus);
}

result<std::vector<deviation_point>> oadev(std::span<const double> data, input_kind in,
                                           double tau0_s, const tau_spec& taus) {
  return deviation(dev_kind::oadev, data, in, tau0_s, taus);
}

}  // namespace gyroflip::analysis
