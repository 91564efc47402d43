/// \file
/// \brief The Allan-deviation family (see allan.hpp): tau sets, each statistic from the sweeps
/// over a phase source (sweep.hpp, decimate.hpp), and the span-based entry points on top.
#include "gyroflip/analysis/allan.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "decimate.hpp"
#include "extended.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "parallel.hpp"
#include "sweep.hpp"

namespace gyroflip::analysis {
namespace {

using detail::term_range;

// sqrt(sum / (c tau^2 n)): the deviation from its sum of squared differences, with `c` the
// statistic's constant (2 for the Allan variances, 6 for the Hadamard ones, 2 m^2 for MDEV).
raw_deviation finish(long double sum_sq, long double c, double tau_s, std::size_t n) {
  if (n == 0) return {};
  const long double denom =
      c * static_cast<long double>(tau_s * tau_s) * static_cast<long double>(n);
  return {static_cast<double>(std::sqrt(sum_sq / denom)), n};
}

// Term counts of the overlapping statistics for N phase points (0: m too large).
std::size_t oadev_terms(std::size_t n, std::size_t m) {
  return n >= 2 * m + 1 ? n - 2 * m : 0;
}
std::size_t ohdev_terms(std::size_t n, std::size_t m) {
  return n >= 3 * m + 1 ? n - 3 * m : 0;
}
std::size_t mdev_terms(std::size_t n, std::size_t m) {
  return n >= 3 * m ? n - 3 * m + 1 : 0;
}
// TOTDEV's reflected series x* reaches N - 2 points beyond either end, so every m up to N - 1
// has its N - 2 terms (Stable32 and allantools compute m = N - 1 too).
std::size_t totdev_terms(std::size_t n, std::size_t m) {
  return n >= 3 && m <= n - 1 ? n - 2 : 0;
}

// Term ranges [0, terms) of a sweep whose terms start at i = 0.
std::vector<term_range> from_zero(const std::vector<std::size_t>& ms, std::size_t n,
                                  std::size_t (*terms)(std::size_t, std::size_t)) {
  std::vector<term_range> r;
  r.reserve(ms.size());
  for (std::size_t m : ms) r.push_back({m, 0, static_cast<std::ptrdiff_t>(terms(n, m))});
  return r;
}

// TOTDEV (eqn 25) centres c = 1..N-2 as OADEV-like terms at i = c - m on the reflected phase.
std::vector<term_range> totdev_ranges(const std::vector<std::size_t>& ms, std::size_t n) {
  std::vector<term_range> r;
  for (std::size_t m : ms) {
    const auto mi = static_cast<std::ptrdiff_t>(m);
    const auto ni = static_cast<std::ptrdiff_t>(n);
    r.push_back(totdev_terms(n, m) > 0 ? term_range{m, 1 - mi, ni - 1 - mi} : term_range{m, 0, 0});
  }
  return r;
}

// The sums of statistic k for every factor, and each factor's term count.
std::vector<long double> sums_of(dev_kind k, const phase_source& x,
                                 const std::vector<std::size_t>& ms, const progress_fn& p) {
  const std::size_t n = x.size();
  switch (k) {
    case dev_kind::adev:
      return detail::decimated_sums(x, 2, ms, p);
    case dev_kind::hdev:
      return detail::decimated_sums(x, 3, ms, p);
    case dev_kind::oadev:
      return detail::difference_sums(x, 2, false, from_zero(ms, n, oadev_terms), p);
    case dev_kind::ohdev:
      return detail::difference_sums(x, 3, false, from_zero(ms, n, ohdev_terms), p);
    case dev_kind::totdev:
      return detail::difference_sums(x, 2, true, totdev_ranges(ms, n), p);
    case dev_kind::mdev:
    case dev_kind::tdev:
      return detail::mdev_sums(x, ms, p);
    default:  // the extended kinds: extended_at
      return std::vector<long double>(ms.size(), 0.0L);
  }
}

raw_deviation from_sum(dev_kind k, long double sum, std::size_t n, std::size_t m, double tau0_s) {
  const double tau = static_cast<double>(m) * tau0_s;
  const auto mm = static_cast<long double>(m);
  switch (k) {
    case dev_kind::adev:
      return finish(sum, 2.0L, tau, detail::decimated_terms(n, m, 2));
    case dev_kind::hdev:
      return finish(sum, 6.0L, tau, detail::decimated_terms(n, m, 3));
    case dev_kind::oadev:
      return finish(sum, 2.0L, tau, oadev_terms(n, m));
    case dev_kind::ohdev:
      return finish(sum, 6.0L, tau, ohdev_terms(n, m));
    case dev_kind::totdev:
      return finish(sum, 2.0L, tau, totdev_terms(n, m));
    case dev_kind::mdev:
      return finish(sum, 2.0L * mm * mm, tau, mdev_terms(n, m));
    case dev_kind::tdev: {  // TDEV = tau MDEV / sqrt(3) (SP1065 eqn 15)
      const auto r = finish(sum, 2.0L * mm * mm, tau, mdev_terms(n, m));
      return {tau * r.dev / std::sqrt(3.0), r.n};
    }
    default:  // the extended kinds: extended_at
      return {};
  }
}

// Theo1 from its sum at m on n phase points (SP1065 eqn 30).
raw_deviation theo1_from(const detail::sum_terms& s, std::size_t n, std::size_t m, double tau0_s) {
  if (s.n == 0) return {};
  const auto tau = static_cast<long double>(m) * tau0_s;
  return {
      static_cast<double>(std::sqrt(s.sum / (0.75L * static_cast<long double>(n - m) * tau * tau))),
      s.n};
}

// One extended statistic at factor m on the phase x in memory (allan.hpp gives the formulas).
raw_deviation extended_at(dev_kind k, std::span<const double> x, std::size_t m, double tau0_s) {
  const double tau = static_cast<double>(m) * tau0_s;
  const auto mm = static_cast<long double>(m);
  switch (k) {
    case dev_kind::mtotdev:
    case dev_kind::ttotdev: {
      const auto s = detail::total_sum(x, m);
      auto r = finish(s.sum, 6.0L * mm * mm * mm * 2.0L, tau, s.n);
      if (k == dev_kind::ttotdev) r.dev *= tau / std::sqrt(3.0);  // SP1065 eqn 28
      return r;
    }
    case dev_kind::htotdev: {
      if (m == 1) return deviation_at(dev_kind::ohdev, x, tau0_s, 1);  // Stable32's choice
      // The frequency y_i = (x_{i+1} - x_i) / tau0: finish's tau^2 takes the tau0^2 back.
      std::vector<double> y(x.size() - 1);
      for (std::size_t i = 0; i + 1 < x.size(); ++i) y[i] = x[i + 1] - x[i];
      const auto s = detail::total_sum(y, m);
      return finish(s.sum, 36.0L * mm * mm * mm, tau0_s, s.n);
    }
    case dev_kind::theo1: {
      const std::size_t one[] = {m};
      return theo1_from(detail::theo1_sums(x, one).front(), x.size(), m, tau0_s);
    }
    case dev_kind::pdev: {
      if (m == 1) return deviation_at(dev_kind::oadev, x, tau0_s, 1);  // PDEV = OADEV at m = 1
      const auto s = detail::pdev_sum(x, m);
      return finish(72.0L * s.sum, mm * mm * mm * mm, tau, s.n);
    }
    case dev_kind::mtie: {
      const auto s = detail::mtie_value(x, m);
      return {static_cast<double>(s.sum), s.n};
    }
    case dev_kind::tierms: {
      const auto s = detail::tie_sum(x, m);
      if (s.n == 0) return {};
      return {static_cast<double>(std::sqrt(s.sum / static_cast<long double>(s.n))), s.n};
    }
    default:
      return {};
  }
}

std::vector<raw_deviation> raw_deviations(dev_kind k, const phase_source& x,
                                          const std::vector<std::size_t>& ms,
                                          const progress_fn& p) {
  std::vector<raw_deviation> out;
  if (is_extended(k)) {
    // The whole phase in memory (8 bytes a point), then each factor by its own algorithm.
    phase_reader r(x);
    const auto all = r.read(0, x.size());
    std::vector<double> phase(all.begin(), all.end());
    // The time errors are of x itself (ITU-T G.810): a constant rate offset (a gyro's bias) adds
    // ybar tau to every TIE, so MTIE and TIE rms of rate samples take back the mean the phase
    // source removed (review M4: rate and angle input of one record then agree). Every other
    // statistic differences it away.
    if ((k == dev_kind::mtie || k == dev_kind::tierms) && x.rate_mean() != 0.0)
      for (std::size_t i = 0; i < phase.size(); ++i)
        phase[i] += x.rate_mean() * x.tau0_s() * static_cast<double>(i);
    out.resize(ms.size());
    if (k == dev_kind::theo1) {  // shares one autocorrelation of the phase among its factors
      const auto sums = detail::theo1_sums(phase, ms, p);
      for (std::size_t i = 0; i < ms.size(); ++i)
        out[i] = theo1_from(sums[i], phase.size(), ms[i], x.tau0_s());
      return out;
    }
    // The factors side by side on all cores.
    detail::for_each_item(
        ms.size(), detail::worker_count(x.size()),
        [&](std::size_t, std::size_t i) { out[i] = extended_at(k, phase, ms[i], x.tau0_s()); }, p);
    return out;
  }
  const auto sums = sums_of(k, x, ms, p);
  for (std::size_t i = 0; i < ms.size(); ++i)
    out.push_back(from_sum(k, sums[i], x.size(), ms[i], x.tau0_s()));
  return out;
}

// The curve from per-factor results, dropping factors without terms.
result<std::vector<deviation_point>> collect(dev_kind k, const std::vector<std::size_t>& factors,
                                             const std::vector<raw_deviation>& raw, double tau0_s) {
  std::vector<deviation_point> out;
  for (std::size_t i = 0; i < factors.size(); ++i) {
    if (raw[i].n == 0) continue;
    deviation_point p;
    p.m = factors[i];
    // Theo1's tau is 0.75 m tau0 (SP1065 eqn 30; Stable32's "Theo1 Tau").
    p.tau_s = facts(k).tau_factor * static_cast<double>(factors[i]) * tau0_s;
    p.dev = raw[i].dev;
    p.n = raw[i].n;
    out.push_back(p);
  }
  if (out.empty())
    return runtime_error("no averaging time fits the data (series too short for the taus asked)");
  return out;
}

}  // namespace

namespace detail {

std::size_t max_factor(dev_kind k, std::size_t n_phase) {
  return (n_phase - 1) / facts(k).span_divisor;
}

std::optional<result<std::vector<deviation_point>>> deviation_from_block_sums(
    dev_kind k, const sample_source& samples, input_kind in, double tau0_s, const tau_spec& taus,
    const progress_fn& on_progress, block_heads* heads) {
  if (in != input_kind::rate || (k != dev_kind::adev && k != dev_kind::hdev)) return std::nullopt;
  const std::size_t n_phase = samples.size() + 1;
  const auto factors = averaging_factors(taus, k, n_phase);
  if (factors.empty()) return std::nullopt;
  const auto sums =
      octave_block_sums(samples, tau0_s, k == dev_kind::adev ? 2 : 3, factors, on_progress, heads);
  if (!sums) return std::nullopt;
  std::vector<raw_deviation> raw;
  for (std::size_t i = 0; i < factors.size(); ++i)
    raw.push_back(from_sum(k, (*sums)[i], n_phase, factors[i], tau0_s));
  return collect(k, factors, raw, tau0_s);
}

}  // namespace detail

namespace {

// The table is indexed by kind: its rows must stay in dev_kind's order.
constexpr bool table_in_kind_order() {
  constexpr std::size_t rows = sizeof(dev_table) / sizeof(dev_table[0]);
  if (rows != sizeof(all_dev_kinds) / sizeof(all_dev_kinds[0])) return false;
  std::size_t i = 0;
  for (const dev_facts& f : dev_table) {
    if (static_cast<std::size_t>(f.kind) != i || all_dev_kinds[i] != f.kind) return false;
    ++i;
  }
  return true;
}
static_assert(table_in_kind_order(), "dev_table's rows must be in dev_kind's order");

}  // namespace

std::string dev_kind_names(std::string_view sep) {
  std::string out;
  for (const auto& f : dev_table) {
    if (!out.empty()) out += sep;
    out += f.name;
  }
  return out;
}

std::optional<dev_kind> parse_dev_kind(std::string_view name) noexcept {
  for (dev_kind k : all_dev_kinds)
    if (to_string(k) == name) return k;
  return std::nullopt;
}

result<tau_spec> parse_tau_spec(std::string_view text) {
  if (text == "octave") return tau_spec{tau_spec::set::octave, {}};
  if (text == "decade") return tau_spec{tau_spec::set::decade, {}};
  if (text == "all") return tau_spec{tau_spec::set::all, {}};
  tau_spec s{tau_spec::set::list, {}};
  for (const auto& part : text::split(text, ',')) {
    const auto m = text::to_unsigned(part.text);
    if (!m || *m == 0)
      return parameter_error("taus",
                             fmt::format("'{}': expected octave, decade, all or averaging factors "
                                         "like 1,2,10 (whole numbers >= 1); '{}' is not one",
                                         printable(text, 80), printable(part.text, 40)));
    s.factors.push_back(static_cast<std::size_t>(*m));
  }
  if (s.factors.empty()) return parameter_error("taus", "empty list of averaging factors");
  std::sort(s.factors.begin(), s.factors.end());
  s.factors.erase(std::unique(s.factors.begin(), s.factors.end()), s.factors.end());
  return s;
}

std::vector<std::size_t> averaging_factors(const tau_spec& spec, dev_kind k, std::size_t n_phase) {
  std::vector<std::size_t> out;
  if (n_phase < 3) return out;
  const std::size_t limit = std::max<std::size_t>(1, detail::max_factor(k, n_phase));
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
  // Theo1 is defined for even factors only (SP1065 eqn 30).
  if (facts(k).even_m_only) std::erase_if(out, [](std::size_t m) { return m % 2 != 0; });
  return out;
}

raw_deviation deviation_at(dev_kind k, std::span<const double> x, double tau0_s, std::size_t m) {
  const span_samples samples(x);
  const auto src = phase_source::make(samples, input_kind::angle, tau0_s);
  if (!src || m == 0) return {};
  return raw_deviations(k, *src, {m}, {})[0];
}

result<std::vector<deviation_point>> deviation(dev_kind k, const phase_source& x,
                                               const tau_spec& taus,
                                               const progress_fn& on_progress) {
  if (x.size() < 3)
    return runtime_error(
        fmt::format("{} phase points are too few for an Allan deviation", x.size()));
  // ADEV and HDEV of rate samples from their block sums where they apply (as the sample-source
  // entry point below): one read of the samples, not the phase decimated point by point.
  if (auto r = detail::deviation_from_block_sums(k, x.samples(), x.kind(), x.tau0_s(), taus,
                                                 on_progress))
    return std::move(*r);
  const auto factors = averaging_factors(taus, k, x.size());
  // Rate samples rebuild their phase on every read: the sweep reads each point about ten times
  // (the window and the far streams), thousands of sweeps over a short series (`--taus all`: one
  // per group of factors) thousands of times. Up to 2^22 points (32 MB) the phase is built once
  // (on all cores, phase_source::build) and read as angle samples with the rate source's block
  // sums: the same phase (phase_reader is bit-identical wherever it starts), so the same sums bit
  // for bit; three times faster at 557 k points with `--taus all`, OADEV octave at 1e6 17 -> 4 ms
  // CPU. Beyond that the built phase no longer stays in the cache (32 MB of L3 on the project's
  // VM) and each far stream reads it from memory, which costs more than rebuilding it from the
  // samples in the cache: OADEV octave at 1e7 91 ms CPU built, 65 ms rebuilt; at 5e6 43 vs 30 ms;
  // even at 2.5e6-4e6 (docs/PERFORMANCE.md). ADEV and HDEV read each point about once: no gain.
  constexpr std::size_t materialize_max_points = std::size_t{1} << 22;
  if (x.kind() == input_kind::rate && x.size() <= materialize_max_points && !is_extended(k) &&
      k != dev_kind::adev && k != dev_kind::hdev) {
    // Not zeroed first: build() writes every point, each thread the pages it built.
    const auto phase = std::make_unique_for_overwrite<double[]>(x.size());
    const std::span<double> all(phase.get(), x.size());
    x.build(all);
    const span_samples samples(all);
    const phase_source angle = x.built(samples);
    return collect(k, factors, raw_deviations(k, angle, factors, on_progress), x.tau0_s());
  }
  return collect(k, factors, raw_deviations(k, x, factors, on_progress), x.tau0_s());
}

std::vector<dropped_factor> dropped_factors(const tau_spec& spec,
                                            std::span<const deviation_point> points, dev_kind k,
                                            std::size_t n_phase, double tau0_s) {
  std::vector<dropped_factor> out;
  if (spec.kind != tau_spec::set::list) return out;
  for (std::size_t m : spec.factors) {
    const bool kept = std::any_of(points.begin(), points.end(),
                                  [m](const deviation_point& p) { return p.m == m; });
    if (kept || std::any_of(out.begin(), out.end(), [m](auto& d) { return d.m == m; })) continue;
    const std::size_t need = facts(k).need_per_m * m + facts(k).need_extra;
    const double tau_s = static_cast<double>(m) * tau0_s;
    if (facts(k).even_m_only && m % 2 != 0) {
      out.push_back(
          {m, tau_s, fmt::format("{} needs an even averaging factor; {} is odd", to_string(k), m)});
      continue;
    }
    out.push_back(
        {m, tau_s,
         fmt::format("{} at tau = {:g} s needs at least {} phase points; the series has {}",
                     to_string(k), tau_s, need, n_phase)});
  }
  return out;
}

result<std::vector<deviation_point>> deviation_of_phase(dev_kind k, std::span<const double> x,
                                                        double tau0_s, const tau_spec& taus,
                                                        const progress_fn& on_progress) {
  return deviation(k, x, input_kind::angle, tau0_s, taus, on_progress);
}

result<std::vector<deviation_point>> deviation(dev_kind k, const sample_source& samples,
                                               input_kind in, double tau0_s, const tau_spec& taus,
                                               const progress_fn& on_progress) {
  if (auto r = detail::deviation_from_block_sums(k, samples, in, tau0_s, taus, on_progress))
    return std::move(*r);
  const auto src = phase_source::make(samples, in, tau0_s);
  if (!src) return src.err();
  return deviation(k, *src, taus, on_progress);
}

result<std::vector<deviation_point>> deviation(dev_kind k, std::span<const double> data,
                                               input_kind in, double tau0_s, const tau_spec& taus,
                                               const progress_fn& on_progress) {
  const span_samples samples(data);
  return deviation(k, samples, in, tau0_s, taus, on_progress);
}

result<std::vector<deviation_point>> oadev(std::span<const double> data, input_kind in,
                                           double tau0_s, const tau_spec& taus) {
  return deviation(dev_kind::oadev, data, in, tau0_s, taus);
}

}  // namespace gyroflip::analysis
