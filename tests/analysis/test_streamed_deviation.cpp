// Every statistic computed by the sweeps over a phase source (issue 4: bounded memory) against a
// reference written straight from NIST SP1065's formulas in long double, on series around the
// block boundaries (1024 phase points, 4096 terms, 2^20 terms a chunk), for every kind, tau set,
// rate and angle input; and a .npy / raw float64 file source bit-identical to the same samples in
// memory.
#include <cmath>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/io/series.hpp"
#include "support/series_files.hpp"
#include "support/synth.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::analysis {
namespace {

const std::vector<dev_kind> all_kinds = {dev_kind::adev,  dev_kind::oadev, dev_kind::mdev,
                                         dev_kind::tdev,  dev_kind::hdev,  dev_kind::ohdev,
                                         dev_kind::totdev};

// Second (order 2) or third (order 3) difference at lag m starting at x_i.
long double difference(const std::vector<long double>& x, std::size_t order, std::size_t i,
                       std::size_t m) {
  if (order == 2) return x[i + 2 * m] - 2.0L * x[i + m] + x[i];
  return x[i + 3 * m] - 3.0L * x[i + 2 * m] + 3.0L * x[i + m] - x[i];
}

// Sum of the squared MDEV inner sums (SP1065 eqn 14), sliding in long double; n terms.
long double mdev_sum(const std::vector<long double>& x, std::size_t m, std::size_t n) {
  long double inner = 0.0L;
  for (std::size_t i = 0; i < m; ++i) inner += difference(x, 2, i, m);
  long double s = 0.0L;
  for (std::size_t j = 0; j < n; ++j) {
    s += inner * inner;
    if (j + 1 < n) inner += difference(x, 2, j + m, m) - difference(x, 2, j, m);
  }
  return s;
}

// TOTDEV's sum (SP1065 eqn 25): centres 1..N-2 of x reflected at both ends.
long double totdev_sum(const std::vector<long double>& x, std::size_t m) {
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  const auto at = [&](std::ptrdiff_t k) {
    if (k < 0) return 2.0L * x[0] - x[static_cast<std::size_t>(-k)];
    if (k > n - 1) return 2.0L * x.back() - x[static_cast<std::size_t>(2 * (n - 1) - k)];
    return x[static_cast<std::size_t>(k)];
  };
  const auto mi = static_cast<std::ptrdiff_t>(m);
  long double s = 0.0L;
  for (std::ptrdiff_t c = 1; c <= n - 2; ++c) {
    const long double d = at(c - mi) - 2.0L * at(c) + at(c + mi);
    s += d * d;
  }
  return s;
}

// The deviation of kind k at factor m on phase x by the formulas, and its number of terms.
raw_deviation reference(dev_kind k, const std::vector<double>& xd, double tau0_s, std::size_t m) {
  const std::vector<long double> x(xd.begin(), xd.end());
  const std::size_t big_n = x.size();
  const long double tau = static_cast<long double>(m) * static_cast<long double>(tau0_s);
  long double s = 0.0L;
  long double c = 2.0L;
  std::size_t n = 0;
  const std::size_t order = (k == dev_kind::hdev || k == dev_kind::ohdev) ? 3 : 2;
  if (order == 3) c = 6.0L;
  switch (k) {
    case dev_kind::adev:
    case dev_kind::hdev: {  // eqns 7 and 17: the phase decimated by m
      const std::size_t groups = (big_n - 1) / m;
      if (groups < order) return {};
      n = groups - order + 1;
      for (std::size_t i = 0; i < n; ++i) {
        const long double d = difference(x, order, i * m, m);
        s += d * d;
      }
      break;
    }
    case dev_kind::oadev:
    case dev_kind::ohdev:  // eqns 11 and 18
      if (big_n < order * m + 1) return {};
      n = big_n - order * m;
      for (std::size_t i = 0; i < n; ++i) {
        const long double d = difference(x, order, i, m);
        s += d * d;
      }
      break;
    case dev_kind::totdev:
      if (big_n < 3 || m > big_n - 1) return {};
      n = big_n - 2;
      s = totdev_sum(x, m);
      break;
    case dev_kind::mdev:
    case dev_kind::tdev:
      if (big_n < 3 * m) return {};
      n = big_n - 3 * m + 1;
      s = mdev_sum(x, m, n);
      c = 2.0L * static_cast<long double>(m) * static_cast<long double>(m);
      break;
    default:  // the extended kinds: test_extended.cpp
      return {};
  }
  long double dev = std::sqrt(s / (c * tau * tau * static_cast<long double>(n)));
  if (k == dev_kind::tdev) dev *= tau / std::sqrt(3.0L);
  return {static_cast<double>(dev), n};
}

// deviation() of the samples against the reference at every factor of `taus`, to `tol`.
void expect_matches(dev_kind k, const std::vector<double>& data, input_kind in,
                    const tau_spec& taus, const std::string& what, double tol = 1e-12) {
  constexpr double tau0_s = 0.01;
  const auto x = in == input_kind::rate ? phase_from_rate(data, tau0_s) : data;
  const auto got = deviation(k, data, in, tau0_s, taus);
  std::vector<std::pair<std::size_t, raw_deviation>> want;
  if (x.size() >= 3)
    for (std::size_t m : averaging_factors(taus, k, x.size()))
      if (const auto r = reference(k, x, tau0_s, m); r.n > 0) want.emplace_back(m, r);
  ASSERT_EQ(got.ok(), !want.empty()) << what;
  if (!got) return;
  ASSERT_EQ(got->size(), want.size()) << what;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const auto& p = (*got)[i];
    ASSERT_EQ(p.m, want[i].first) << what;
    EXPECT_EQ(p.n, want[i].second.n) << what << " m " << p.m;
    EXPECT_NEAR(p.dev / want[i].second.dev, 1.0, tol) << what << " m " << p.m;
  }
}

std::vector<double> white(std::size_t n, std::uint64_t seed) {
  test::normal_source g(seed);
  std::vector<double> y(n);
  for (double& v : y) v = 0.3 + g();
  return y;
}

// A random-walk angle with an offset (the phase of white rate noise, not mean-removed).
std::vector<double> walk(std::size_t n, std::uint64_t seed) {
  test::normal_source g(seed);
  std::vector<double> a(n);
  double v = 10.0;
  for (double& x : a) x = v += 0.01 * g();
  return a;
}

std::string name(dev_kind k, input_kind in, std::size_t n, const std::string& taus) {
  return std::string(to_string(k)) + (in == input_kind::rate ? " rate " : " angle ") +
         std::to_string(n) + " " + taus;
}

TEST(StreamedDeviation, ShortSeriesAroundBlockBoundariesMatchTheFormulas) {
  for (std::size_t n :
       {2u, 3u, 4u, 5u, 1023u, 1024u, 1025u, 4095u, 4096u, 4097u, 3u * 4096u + 1u}) {
    for (const input_kind in : {input_kind::rate, input_kind::angle}) {
      const auto data = in == input_kind::rate ? white(n, n) : walk(n, n);
      for (const dev_kind k : all_kinds) {
        std::vector<std::string> sets = {"octave", "decade", "1,3,7,1000,1025,4099"};
        if (n <= 4097) sets.emplace_back("all");
        // The last factors of the phase: TOTDEV has terms up to m = N - 1 (issue 23: it dropped
        // m = N - 1, which Stable32 and allantools compute), the others none.
        const std::size_t n_phase = in == input_kind::rate ? n + 1 : n;
        if (n_phase >= 3) sets.push_back(fmt::format("{},{}", n_phase - 2, n_phase - 1));
        for (const auto& t : sets)
          expect_matches(k, data, in, *parse_tau_spec(t), name(k, in, n, t));
      }
    }
  }
}

TEST(StreamedDeviation, LongSeriesWithFarFactorsAndSeveralChunksMatchTheFormulas) {
  // 2^20 + 4097 samples: two chunks (MDEV restarts its inner sums at the second), two threads,
  // factors beyond the shared window (m > 65536 / 43690) read from far streams, TOTDEV
  // reflected over half the record; listed factors are no multiples of any block.
  const std::size_t n = (std::size_t{1} << 20) + 4097;
  const auto y = white(n, 21);
  for (const dev_kind k : {dev_kind::oadev, dev_kind::mdev, dev_kind::totdev})
    expect_matches(k, y, input_kind::rate, *parse_tau_spec("octave"),
                   name(k, input_kind::rate, n, "octave"));
  const auto list = *parse_tau_spec("3,1025,43691,65537,131071,262145");
  for (const dev_kind k : all_kinds)
    expect_matches(k, y, input_kind::rate, list, name(k, input_kind::rate, n, "list"));
  const auto a = walk(n, 22);
  for (const dev_kind k : {dev_kind::mdev, dev_kind::totdev, dev_kind::ohdev})
    expect_matches(k, a, input_kind::angle, list, name(k, input_kind::angle, n, "list"));
}

TEST(StreamedDeviation, FileSourcesEqualTheSamplesInMemory) {
  // .npy and raw float64 files, read through io::series (mapped, released as consumed), give
  // bit-identical curves and intervals to the same samples in memory: 2^19 + 3 4096 + 1
  // samples, so that OADEV and MDEV have far factors too.
  const std::size_t n = (std::size_t{1} << 19) + 3u * 4096u + 1u;
  const auto y = white(n, 23);
  test::temp_dir d;
  test::write_npy(d.file("y.npy"), y);
  test::write_f64(d.file("y.f64"), y);
  io::series_options so;
  so.sample_rate_hz = 100.0;
  for (const input_kind in : {input_kind::rate, input_kind::angle}) {
    const span_samples memory(y);
    const auto mem_src = *phase_source::make(memory, in, 0.01);
    for (const char* file : {"y.npy", "y.f64"}) {
      const auto s = io::read_series(d.file(file), so);
      ASSERT_TRUE(s) << s.err().message;
      ASSERT_EQ(s->samples().size(), n);
      const auto file_src = *phase_source::make(s->samples(), in, s->tau0_s());
      for (const dev_kind k : all_kinds) {
        auto a = *deviation(k, file_src, {});
        auto b = *deviation(k, mem_src, {});
        add_confidence(a, k, file_src, 0.683);
        add_confidence(b, k, mem_src, 0.683);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
          EXPECT_EQ(a[i].dev, b[i].dev) << file << " " << to_string(k) << " m " << a[i].m;
          EXPECT_EQ(a[i].alpha, b[i].alpha) << file << " " << to_string(k);
          EXPECT_EQ(a[i].ci_lo, b[i].ci_lo) << file << " " << to_string(k);
        }
      }
    }
  }
}

TEST(StreamedDeviation, SpanAndSourceEntryPointsAgree) {
  // deviation_at, deviation_of_phase, deviation (span) and the source are one implementation,
  // but for ADEV and HDEV of rate samples at octave factors, which the span entry point takes
  // from block sums (no phase; Allan.OctaveAdevHdevFromBlockSums): equal to rounding there.
  const auto y = white(20000, 24);
  const auto x = phase_from_rate(y, 1.0);
  const span_samples s(y);
  const auto src = *phase_source::make(s, input_kind::rate, 1.0);
  for (const dev_kind k : all_kinds) {
    const auto a = *deviation(k, src, {});
    const auto b = *deviation_of_phase(k, x, 1.0, {});
    const auto c = *deviation(k, y, input_kind::rate, 1.0, {});
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (k == dev_kind::adev || k == dev_kind::hdev)
        EXPECT_NEAR(c[i].dev / a[i].dev, 1.0, 1e-13) << to_string(k);
      else
        EXPECT_EQ(a[i].dev, c[i].dev) << to_string(k);
      // The same phase as angle samples: only MDEV's exact restarts sum it differently.
      EXPECT_NEAR(b[i].dev / a[i].dev, 1.0, 1e-14) << to_string(k);
      EXPECT_EQ(b[i].dev, deviation_at(k, x, 1.0, a[i].m).dev) << to_string(k);
    }
  }
  EXPECT_EQ(deviation_at(dev_kind::oadev, x, 1.0, 20000).n, 0u);  // too large: no terms
  EXPECT_EQ(deviation_at(dev_kind::oadev, x, 0.0, 1).n, 0u);      // bad tau0
}

// Issue 13 item 16: a long factor list on rate samples builds the phase once (more than 64 factors)
// instead of rebuilding it on every read; the curve must be the one of the streamed path.
TEST(StreamedDeviation, MaterializedPhaseForLongListsEqualsTheStreamedOne) {
  const auto y = white(30000, 25);
  const span_samples s(y);
  const auto src = *phase_source::make(s, input_kind::rate, 0.5);
  tau_spec many{tau_spec::set::list, {}};
  for (std::size_t m = 1; m <= 65; ++m) many.factors.push_back(m * 37);
  for (const dev_kind k : all_kinds) {
    const auto a = *deviation(k, src, many);  // 65 factors: materialized
    ASSERT_EQ(a.size(), 65u);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const auto b = *deviation(k, src, tau_spec{tau_spec::set::list, {a[i].m}});  // streamed
      if (k == dev_kind::mdev || k == dev_kind::tdev) {
        EXPECT_NEAR(a[i].dev / b[0].dev, 1.0, 1e-13) << to_string(k) << " m " << a[i].m;
      } else {
        EXPECT_EQ(a[i].dev, b[0].dev) << to_string(k) << " m " << a[i].m;
      }
      EXPECT_EQ(a[i].n, b[0].n);
    }
  }
}

// The progress callback of a long sweep reports often enough for a live line (at least 16
// times for `--taus all`), from the caller's thread.
TEST(StreamedDeviation, AllTausReportProgressAsTheyGo) {
  const auto y = white(1 << 16, 26);
  const span_samples s(y);
  const auto src = *phase_source::make(s, input_kind::angle, 1.0);
  const auto caller = std::this_thread::get_id();
  std::size_t calls = 0;
  bool same_thread = true;
  const auto pts = *deviation(dev_kind::oadev, src, tau_spec{tau_spec::set::all, {}},
                              [&](std::size_t, std::size_t) {
                                ++calls;
                                same_thread = same_thread && std::this_thread::get_id() == caller;
                              });
  EXPECT_EQ(pts.size(), (y.size() - 1) / 4);
  EXPECT_GE(calls, 16u);
  EXPECT_TRUE(same_thread);
}

}  // namespace
}  // namespace gyroflip::analysis
