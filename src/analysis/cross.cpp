/// \file
/// \brief GRADEV, GCODEV, the three-cornered hat and the dynamic Allan deviation (cross.hpp).
#include "gyroflip/analysis/cross.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <type_traits>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

#include <fmt/format.h>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/core/error.hpp"
#include "kernels.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis {
namespace {

status check_tau0(double tau0_s) {
  if (!(tau0_s >= phase_source::min_tau0_s && tau0_s <= phase_source::max_tau0_s))
    return parameter_error("tau0", fmt::format("sample interval {} s is not in [{}, {}] s", tau0_s,
                                               phase_source::min_tau0_s, phase_source::max_tau0_s));
  return ok();
}

// ---- Per-factor sums over the terms of lag 2m -------------------------------------------------
//
// GCODEV and GRADEV sum one term per i in [0, N - 2m) for each factor m, as OADEV does, and are
// organised as OADEV's sweep (sweep.hpp): blocks of 4096 terms summed in double by eight-lane
// kernels and added in long double (relative rounding ~1e-13 at any length), every factor of a
// block while the block's phase is in the cache, chunks of 2^16 terms on all cores, added in
// chunk order (the same sums for any number of threads). The phase is in memory (the inputs are
// spans): 1e6 rate samples, octave taus, GCODEV 51 -> ~7 ms CPU, GRADEV 35 -> ~4 ms
// (docs/PERFORMANCE.md, "Issue 23: GCODEV and GRADEV").

constexpr std::size_t block_terms = 4096;
constexpr std::size_t chunk_terms = std::size_t{1} << 16;

// For each factor m of `ms`: the V sums of block(m, i, n) over the blocks [i, i + n) of its
// terms. With `pair` (not std::nullptr_t): where factor 2m follows m and both have the whole
// block, pair(m, i, n) gives both factors' V sums at once (their points at i, i+m, i+2m, i+4m
// read once).
template <std::size_t V, class Block, class Pair = std::nullptr_t>
std::vector<std::array<long double, V>> term_sums(std::size_t n_points,
                                                  const std::vector<std::size_t>& ms, Block block,
                                                  Pair pair = nullptr) {
  const std::size_t nf = ms.size();
  std::size_t terms = 0;
  for (std::size_t m : ms)
    if (2 * m < n_points) terms = std::max(terms, n_points - 2 * m);
  const std::size_t chunks = (terms + chunk_terms - 1) / chunk_terms;
  std::vector<std::array<long double, V>> partial(chunks * nf, std::array<long double, V>{});
  detail::for_each_item(chunks, detail::worker_count(n_points), [&](std::size_t, std::size_t c) {
    const std::size_t c0 = c * chunk_terms;
    const std::size_t c1 = std::min(terms, c0 + chunk_terms);
    for (std::size_t b = c0; b < c1; b += block_terms)
      for (std::size_t f = 0; f < nf; ++f) {
        const std::size_t m = ms[f];
        if (2 * m >= n_points) continue;
        const std::size_t end = std::min(b + block_terms, c1);
        const std::size_t hi = std::min(n_points - 2 * m, end);
        if (b >= hi) continue;
        if constexpr (!std::is_same_v<Pair, std::nullptr_t>) {
          if (f + 1 < nf && ms[f + 1] == 2 * m && 4 * m < n_points && n_points - 4 * m >= hi) {
            const std::array<double, 2 * V> s = pair(m, b, hi - b);
            for (std::size_t v = 0; v < V; ++v) {
              partial[c * nf + f][v] += s[v];
              partial[c * nf + f + 1][v] += s[V + v];
            }
            ++f;
            continue;
          }
        }
        const std::array<double, V> s = block(m, b, hi - b);
        for (std::size_t v = 0; v < V; ++v) partial[c * nf + f][v] += s[v];
      }
  });
  std::vector<std::array<long double, V>> out(nf, std::array<long double, V>{});
  for (std::size_t c = 0; c < chunks; ++c)
    for (std::size_t f = 0; f < nf; ++f)
      for (std::size_t v = 0; v < V; ++v) out[f][v] += partial[c * nf + f][v];
  return out;
}

using detail::lanes4;

// Four doubles from p. Vectors by reference: a 32-byte vector passed or returned by value has
// another ABI in the AVX2 clones (kernels.hpp).
[[gnu::always_inline]] inline void load4(lanes4& v, const double* p) {
  std::memcpy(&v, p, sizeof v);
}

// The three points x_{i}, x_{i+m}, x_{i+2m} of a block's first term.
struct term_points {
  const double* x0;
  const double* x1;
  const double* x2;
};

term_points points_at(std::span<const double> x, std::size_t m, std::size_t i) {
  return {x.data() + i, x.data() + i + m, x.data() + i + 2 * m};
}

// The second differences x2 - 2 x1 + x0 of terms t..t+3 (SP1065 eqn 11), as OADEV's kernel.
[[gnu::always_inline]] inline void second_difference(lanes4& d, const term_points& x,
                                                     std::size_t t) {
  lanes4 x0, x1, x2;
  load4(x0, x.x0 + t);
  load4(x1, x.x1 + t);
  load4(x2, x.x2 + t);
  d = x2 - 2.0 * x1 + x0;
}

// The sum of the eight lanes of two accumulators.
[[gnu::always_inline]] inline double lane_sum(const lanes4& a, const lanes4& b) {
  return ((a[0] + a[1]) + (a[2] + a[3])) + ((b[0] + b[1]) + (b[2] + b[3]));
}

// GCODEV's block: sum over t < n of the products of the second differences of a and b, eight
// lanes side by side in two accumulators (one alone would wait on its adds: 3 cycles per four
// terms), the same bits with and without AVX2.
GYROFLIP_KERNEL_CLONES double sum_difference_products(const term_points& a, const term_points& b,
                                                      std::size_t n) {
  lanes4 acc0 = {0.0, 0.0, 0.0, 0.0};
  lanes4 acc1 = acc0;
  lanes4 da0, db0, da1, db1;
  std::size_t t = 0;
  for (; t + 8 <= n; t += 8) {
    second_difference(da0, a, t);
    second_difference(db0, b, t);
    second_difference(da1, a, t + 4);
    second_difference(db1, b, t + 4);
    acc0 += da0 * db0;
    acc1 += da1 * db1;
  }
  double rest = 0.0;
  for (; t < n; ++t)
    rest += (a.x2[t] - 2.0 * a.x1[t] + a.x0[t]) * (b.x2[t] - 2.0 * b.x1[t] + b.x0[t]);
  return lane_sum(acc0, acc1) + rest;
}

// GCODEV's block for factors m and 2m at once: the second differences at lags m and 2m from the
// points at i, i+m, i+2m, i+4m of each series, four reads per series for two terms instead of six
// (the loop is bound by its reads otherwise: 1e6 samples, octave taus, ~60 % of the call). Four
// lanes per factor.
GYROFLIP_KERNEL_CLONES std::array<double, 2> sum_difference_products_pair(const double* a,
                                                                          const double* b,
                                                                          std::size_t m,
                                                                          std::size_t n) {
  lanes4 acc1 = {0.0, 0.0, 0.0, 0.0};
  lanes4 acc2 = acc1;
  lanes4 a0, a1, a2, a4, b0, b1, b2, b4;
  std::size_t t = 0;
  for (; t + 4 <= n; t += 4) {
    load4(a0, a + t);
    load4(a1, a + t + m);
    load4(a2, a + t + 2 * m);
    load4(a4, a + t + 4 * m);
    load4(b0, b + t);
    load4(b1, b + t + m);
    load4(b2, b + t + 2 * m);
    load4(b4, b + t + 4 * m);
    acc1 += (a2 - 2.0 * a1 + a0) * (b2 - 2.0 * b1 + b0);
    acc2 += (a4 - 2.0 * a2 + a0) * (b4 - 2.0 * b2 + b0);
  }
  std::array<double, 2> out = {(acc1[0] + acc1[1]) + (acc1[2] + acc1[3]),
                               (acc2[0] + acc2[1]) + (acc2[2] + acc2[3])};
  for (; t < n; ++t) {
    out[0] += (a[t + 2 * m] - 2.0 * a[t + m] + a[t]) * (b[t + 2 * m] - 2.0 * b[t + m] + b[t]);
    out[1] +=
        (a[t + 4 * m] - 2.0 * a[t + 2 * m] + a[t]) * (b[t + 4 * m] - 2.0 * b[t + 2 * m] + b[t]);
  }
  return out;
}

// GRADEV's block on gappy phase: sum over t < n of k_t d_t^2 and of k_t, d_t the second
// difference and k_t (0 or 1) whether term t exists: exists(k, mark_t, mark_t+m, mark_t+2m) of
// the marks at its three points (on four lanes, and on single terms for the rest). Eight lanes in
// two accumulators each, as above.
template <class Exists>
[[gnu::always_inline]] inline std::array<double, 2> sum_existing_squares(const term_points& x,
                                                                         const term_points& mark,
                                                                         std::size_t n,
                                                                         Exists exists) {
  std::array<lanes4, 2> acc = {lanes4{0.0, 0.0, 0.0, 0.0}, lanes4{0.0, 0.0, 0.0, 0.0}};
  std::array<lanes4, 2> count = acc;
  lanes4 d, k, w0, w1, w2;
  std::size_t t = 0;
  for (; t + 8 <= n; t += 8)
    for (std::size_t h = 0; h < 2; ++h) {
      const std::size_t th = t + 4 * h;
      second_difference(d, x, th);
      load4(w0, mark.x0 + th);
      load4(w1, mark.x1 + th);
      load4(w2, mark.x2 + th);
      exists(k, w0, w1, w2);
      acc[h] += k * (d * d);
      count[h] += k;
    }
  std::array<double, 2> out = {lane_sum(acc[0], acc[1]), lane_sum(count[0], count[1])};
  for (; t < n; ++t) {
    const double dt = x.x2[t] - 2.0 * x.x1[t] + x.x0[t];
    double kt = 0.0;
    exists(kt, mark.x0[t], mark.x1[t], mark.x2[t]);
    out[0] += kt * (dt * dt);
    out[1] += kt;
  }
  return out;
}

// Angle input: a term exists when its three points do; the mark is 1 where the point exists,
// else 0 (and the point 0).
GYROFLIP_KERNEL_CLONES std::array<double, 2> sum_squares_of_existing_points(const term_points& x,
                                                                            const term_points& mark,
                                                                            std::size_t n) {
  return sum_existing_squares(
      x, mark, n,
      [](auto& k, const auto& w0, const auto& w1, const auto& w2) { k = w0 * w1 * w2; });
}

// Rate input: a term exists when no sample is missing between its first and last point; the
// mark is the number of missing samples before the point (a whole number, exact in double, that
// never decreases along the series), so g0 >= g2 means the same at both ends.
GYROFLIP_KERNEL_CLONES std::array<double, 2> sum_squares_within_runs(const term_points& x,
                                                                     const term_points& mark,
                                                                     std::size_t n) {
  return sum_existing_squares(x, mark, n, [](auto& k, const auto& g0, const auto&, const auto& g2) {
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(k)>, double>) {
      k = g0 >= g2 ? 1.0 : 0.0;
    } else {
      const lanes4 one = {1.0, 1.0, 1.0, 1.0};
      const lanes4 zero = {0.0, 0.0, 0.0, 0.0};
      k = g0 >= g2 ? one : zero;
    }
  });
}

// Memory for n doubles, not zeroed. Beyond 32 MB in transparent huge pages where the system
// gives them on request (Linux madvise): GCODEV of 1e7 rate samples first-touches 160 MB of
// phase, 40 960 page faults of 4 KiB otherwise, ~15 % of its CPU time; below, where the C
// library may hand back the memory of the last call (glibc's malloc keeps blocks up to 32 MB in
// its heap once one was freed), huge pages would be cleared afresh on every call (1e6 samples:
// ~11 % of the call). docs/PERFORMANCE.md, issue 23.
struct free_memory {
  void operator()(double* p) const noexcept { std::free(p); }
};
using doubles = std::unique_ptr<double[], free_memory>;

doubles uninitialised_doubles(std::size_t n) {
  n = std::max<std::size_t>(n, 1);  // malloc(0) may return null
  constexpr std::size_t huge_page = std::size_t{1} << 21;
  constexpr std::size_t huge_from = std::size_t{32} << 20;
  if (n * sizeof(double) <= huge_from) {
    auto* p = static_cast<double*>(std::malloc(n * sizeof(double)));
    if (p == nullptr) throw std::bad_alloc();
    return doubles(p);
  }
  const std::size_t bytes = (n * sizeof(double) + huge_page - 1) / huge_page * huge_page;
  auto* p = static_cast<double*>(std::aligned_alloc(huge_page, bytes));
  if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  ::madvise(p, bytes, MADV_HUGEPAGE);  // a hint: without it, 4 KiB pages
#endif
  return doubles(p);
}

// The phase of gappy data and, per point, a second series for the test of a term: angle input,
// x with missing points as 0 and `mark` 1 where a point exists, else 0; rate input, x and `mark`
// the number of missing samples before each point (a term exists where it is the same at both
// ends).
struct gappy_phase {
  doubles x_data;
  doubles mark_data;
  std::size_t size = 0;
  [[nodiscard]] std::span<const double> x() const { return {x_data.get(), size}; }
  [[nodiscard]] std::span<const double> mark() const { return {mark_data.get(), size}; }
};

result<gappy_phase> phase_with_gaps(std::span<const double> data, input_kind in, double tau0_s) {
  gappy_phase p;
  p.size = data.size() + (in == input_kind::rate ? 1 : 0);
  p.x_data = uninitialised_doubles(p.size);
  p.mark_data = uninitialised_doubles(p.size);
  double* x = p.x_data.get();
  double* mark = p.mark_data.get();
  if (in == input_kind::angle) {
    for (std::size_t k = 0; k < data.size(); ++k) {
      const bool missing = std::isnan(data[k]);
      x[k] = missing ? 0.0 : data[k];
      mark[k] = missing ? 0.0 : 1.0;
    }
    return p;
  }
  // Rate input: a missing sample leaves the phase after it unknown by an offset, which no term
  // within a gap-free run depends on (nor on a linear trend). So the missing samples are given
  // the mean of the others (the phase does not drift across a gap) and the whole series is
  // integrated as OADEV integrates it (phase_source: mean removed, long-double carries, on all
  // cores); the terms across a gap, which the filling made up, are the ones left out.
  double sum = 0.0;
  std::size_t finite = 0;
  for (double v : data) {
    const bool missing = std::isnan(v);
    sum += missing ? 0.0 : v;
    finite += missing ? 0 : 1;
  }
  const double mean = finite > 0 ? sum / static_cast<double>(finite) : 0.0;
  const auto filled = uninitialised_doubles(data.size());
  std::size_t missing = 0;
  mark[0] = 0.0;
  for (std::size_t k = 0; k < data.size(); ++k) {
    const bool gap = std::isnan(data[k]);
    filled[k] = gap ? mean : data[k];
    missing += gap ? 1 : 0;
    mark[k + 1] = static_cast<double>(missing);
  }
  const span_samples samples(std::span<const double>(filled.get(), data.size()));
  const auto src = phase_source::make(samples, input_kind::rate, tau0_s);
  if (!src) return src.err();
  src->build(std::span<double>(x, p.size));
  return p;
}

// Whether data has a NaN (a missing sample; refused as phase_source::make refuses it unless
// `missing_allowed`); an error names the first infinite sample or one beyond the magnitude every
// deviation takes (phase_source::max_sample_magnitude). One vectorisable pass.
result<bool> check_samples(std::span<const double> data, bool missing_allowed) {
  bool gaps = false;
  bool bad = false;
  for (double v : data) {
    gaps |= std::isnan(v);
    bad |= std::abs(v) > phase_source::max_sample_magnitude;
  }
  for (std::size_t k = 0; (bad || (gaps && !missing_allowed)) && k < data.size(); ++k) {
    if (!missing_allowed && !std::isfinite(data[k]))
      return usage_error(fmt::format("sample {} (0-based) is not finite", k));
    if (std::isinf(data[k]))
      return runtime_error(
          fmt::format("sample {} (0-based) is infinite; a missing sample is NaN", k));
    if (std::abs(data[k]) > phase_source::max_sample_magnitude)
      return usage_error(
          fmt::format("sample {} (0-based) is {:g}, beyond +-{:g}, the largest "
                      "magnitude the analysis takes",
                      k, data[k], phase_source::max_sample_magnitude));
  }
  return gaps;
}

deviation_point point_of(std::size_t m, double tau0_s, std::size_t n, double var) {
  deviation_point d;
  d.m = m;
  d.tau_s = static_cast<double>(m) * tau0_s;
  d.n = n;
  d.dev = var < 0 ? -std::sqrt(-var) : std::sqrt(var);
  return d;
}

}  // namespace

result<std::vector<deviation_point>> gradev(std::span<const double> data, input_kind in,
                                            double tau0_s, const tau_spec& taus) {
  if (auto s = check_tau0(tau0_s); !s) return s.err();
  const auto gaps = check_samples(data, true);
  if (!gaps) return gaps.err();
  const std::size_t n_phase = data.size() + (in == input_kind::rate ? 1 : 0);
  if (n_phase < 3)
    return runtime_error(
        fmt::format("{} phase points are too few for an Allan deviation", n_phase));
  // Without a gap every term exists: GRADEV is OADEV (SP1065 eqn 11), computed as OADEV is.
  if (!*gaps) return deviation(dev_kind::oadev, data, in, tau0_s, taus);
  const auto gappy = phase_with_gaps(data, in, tau0_s);
  if (!gappy) return gappy.err();
  const auto& p = *gappy;
  const auto ms = averaging_factors(taus, dev_kind::oadev, n_phase);
  const auto sums = term_sums<2>(n_phase, ms, [&](std::size_t m, std::size_t i, std::size_t n) {
    const auto x = points_at(p.x(), m, i);
    const auto mark = points_at(p.mark(), m, i);
    return in == input_kind::angle ? sum_squares_of_existing_points(x, mark, n)
                                   : sum_squares_within_runs(x, mark, n);
  });
  std::vector<deviation_point> out;
  for (std::size_t f = 0; f < ms.size(); ++f) {
    const auto n = static_cast<std::size_t>(sums[f][1]);
    if (n == 0) continue;
    const long double tau = static_cast<long double>(ms[f]) * tau0_s;
    out.push_back(
        point_of(ms[f], tau0_s, n, static_cast<double>(sums[f][0] / (2.0L * n * tau * tau))));
  }
  if (out.empty()) return runtime_error("no averaging time has a complete term between the gaps");
  return out;
}

result<std::vector<deviation_point>> gcodev(std::span<const double> a, std::span<const double> b,
                                            input_kind in, double tau0_s, const tau_spec& taus) {
  if (a.size() != b.size())
    return runtime_error(
        fmt::format("the two series have {} and {} samples; GCODEV needs "
                    "simultaneous samples of one length",
                    a.size(), b.size()));
  // Each series' checks (finite, magnitude, tau0) are OADEV's: the phase source's for rate
  // input, which then builds each phase once on all cores (phase_source::build, the bits OADEV
  // sums; not zeroed first: build() writes every point, each thread the pages it built); angle
  // samples are the phase.
  if (auto s = check_tau0(tau0_s); !s) return s.err();
  const std::size_t n_phase = a.size() + (in == input_kind::rate ? 1 : 0);
  doubles built;
  std::span<const double> xa = a;
  std::span<const double> xb = b;
  if (in == input_kind::rate) {
    const span_samples sa(a);
    const span_samples sb(b);
    const auto pa = phase_source::make(sa, in, tau0_s);
    if (!pa) return pa.err();
    const auto pb = phase_source::make(sb, in, tau0_s);
    if (!pb) return pb.err();
    built = uninitialised_doubles(2 * n_phase);
    const std::span<double> ba(built.get(), n_phase);
    const std::span<double> bb(built.get() + n_phase, n_phase);
    pa->build(ba);
    pb->build(bb);
    xa = ba;
    xb = bb;
  } else {
    for (const auto x : {a, b})
      if (auto c = check_samples(x, false); !c) return c.err();
  }
  if (n_phase < 3)
    return runtime_error(
        fmt::format("{} phase points are too few for an Allan deviation", n_phase));
  const auto ms = averaging_factors(taus, dev_kind::oadev, n_phase);
  const auto sums = term_sums<1>(
      n_phase, ms,
      [&](std::size_t m, std::size_t i, std::size_t n) {
        return std::array<double, 1>{
            sum_difference_products(points_at(xa, m, i), points_at(xb, m, i), n)};
      },
      [&](std::size_t m, std::size_t i, std::size_t n) {
        return sum_difference_products_pair(xa.data() + i, xb.data() + i, m, n);
      });
  std::vector<deviation_point> out;
  for (std::size_t f = 0; f < ms.size(); ++f) {
    const std::size_t m = ms[f];
    if (2 * m >= n_phase) continue;
    const std::size_t n = n_phase - 2 * m;
    const long double tau = static_cast<long double>(m) * tau0_s;
    out.push_back(point_of(m, tau0_s, n, static_cast<double>(sums[f][0] / (2.0L * n * tau * tau))));
  }
  if (out.empty())
    return runtime_error("no averaging time fits the data (series too short for the taus asked)");
  return out;
}

result<std::array<std::vector<deviation_point>, 3>> three_cornered_hat(
    dev_kind k, std::span<const double> ab, std::span<const double> bc, std::span<const double> ca,
    input_kind in, double tau0_s, const tau_spec& taus) {
  if (ab.size() != bc.size() || ab.size() != ca.size())
    return runtime_error(
        fmt::format("the comparisons have {}, {} and {} samples; the "
                    "three-cornered hat needs three of one length",
                    ab.size(), bc.size(), ca.size()));
  std::array<std::vector<deviation_point>, 3> pair;
  const std::array<std::span<const double>, 3> data{ab, bc, ca};
  for (std::size_t i = 0; i < 3; ++i) {
    auto d = deviation(k, data[i], in, tau0_s, taus);
    if (!d) return d.err();
    pair[i] = std::move(*d);
  }
  // var_A = (AB + CA - BC)/2, var_B = (AB + BC - CA)/2, var_C = (BC + CA - AB)/2.
  std::array<std::vector<deviation_point>, 3> out;
  for (std::size_t j = 0; j < pair[0].size(); ++j) {
    const double vab = pair[0][j].dev * pair[0][j].dev;
    const double vbc = pair[1][j].dev * pair[1][j].dev;
    const double vca = pair[2][j].dev * pair[2][j].dev;
    const double var[3] = {0.5 * (vab + vca - vbc), 0.5 * (vab + vbc - vca),
                           0.5 * (vbc + vca - vab)};
    for (std::size_t c = 0; c < 3; ++c) {
      deviation_point p = pair[0][j];
      p.dev = var[c] > 0.0 ? std::sqrt(var[c]) : 0.0;
      out[c].push_back(p);
    }
  }
  return out;
}

result<std::pair<std::size_t, std::size_t>> dynamic_samples(double window_s,
                                                            std::optional<double> step_s,
                                                            double tau0_s, std::size_t n_samples) {
  const double step = step_s.value_or(window_s / 4.0);
  const std::string_view step_name = step_s ? "step" : "step (a quarter window)";
  if (!(window_s > 0.0) || !std::isfinite(window_s))
    return parameter_error("window_s", "the window must be a positive number of seconds");
  if (!(step > 0.0) || !std::isfinite(step))
    return parameter_error("step_s", "the step must be a positive number of seconds");
  const double length_s = static_cast<double>(n_samples) * tau0_s;
  // Compared in seconds before any conversion: a length beyond the series has no size_t.
  if (window_s > length_s)
    return parameter_error("window_s", fmt::format("a window of {:g} s is longer than the series "
                                                   "({} samples, {:g} s)",
                                                   window_s, n_samples, length_s));
  if (step > length_s)
    return parameter_error("step_s", fmt::format("a {} of {:g} s is longer than the series ({} "
                                                 "samples, {:g} s)",
                                                 step_name, step, n_samples, length_s));
  // Halves up, the same for every caller (Python's round() would take halves to even).
  const auto samples = [tau0_s](double s) {
    return static_cast<std::size_t>(std::floor(s / tau0_s + 0.5));
  };
  if (samples(step) < 1)
    return parameter_error("step_s", fmt::format("a {} of {:g} s is shorter than one sample "
                                                 "interval ({:g} s)",
                                                 step_name, step, tau0_s));
  return std::pair{samples(window_s), samples(step)};
}

result<std::vector<dynamic_window>> dynamic_deviation(dev_kind k, std::span<const double> data,
                                                      input_kind in, double tau0_s,
                                                      std::size_t window, std::size_t step,
                                                      const tau_spec& taus,
                                                      const progress_fn& on_progress,
                                                      std::optional<double> level) {
  if (window < 3 || window > data.size())
    return parameter_error("window", fmt::format("a window of {} samples does not fit {} samples "
                                                 "(at least 3, at most all)",
                                                 window, data.size()));
  if (step == 0)
    return parameter_error("step", "the step between windows must be at least 1 sample");
  const std::size_t count = (data.size() - window) / step + 1;
  std::vector<result<std::vector<deviation_point>>> curves(count, runtime_error("not computed"));
  // Windows on all cores, each a short series on its own (one thread each).
  detail::for_each_item(
      count, detail::worker_count(data.size()),
      [&](std::size_t, std::size_t w) {
        const auto part = data.subspan(w * step, window);
        if (!level) {
          curves[w] = deviation(k, part, in, tau0_s, taus);
          return;
        }
        const span_samples s(part);
        auto src = phase_source::make(s, in, tau0_s);
        curves[w] = src ? deviation_with_confidence(k, *src, taus, *level)
                        : result<std::vector<deviation_point>>(src.err());
      },
      on_progress);
  std::vector<dynamic_window> out;
  for (std::size_t w = 0; w < count; ++w) {
    if (!curves[w]) return curves[w].err();
    out.push_back({static_cast<double>(w * step) * tau0_s, std::move(*curves[w])});
  }
  return out;
}

}  // namespace gyroflip::analysis
