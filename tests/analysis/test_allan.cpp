// The Allan family against published values: NIST SP1065 NBS14 sets and every Stable32 table in
// tests/vectors/stable32 (PROVENANCE.md); GPS from ../shared when present.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "support/reference_data.hpp"

namespace gyroflip::analysis {
namespace {

const std::string vectors = std::string(GYROFLIP_VECTORS_DIR) + "/stable32/";

// Checks every row of a Stable32 table: the deviation to 1e-4 relative, the term count exactly.
void check_table(const std::string& path, dev_kind k, const std::vector<double>& x, double tau0_s) {
  const auto rows = test::read_stable32_table(path);
  ASSERT_FALSE(rows.empty()) << path;
  for (const auto& r : rows) {
    const auto d = deviation_at(k, x, tau0_s, r.af);
    EXPECT_NEAR(d.dev / r.sigma, 1.0, 1e-4) << path << " AF " << r.af;
    EXPECT_EQ(d.n, r.n) << path << " AF " << r.af;
  }
}

const std::vector<std::pair<std::string, dev_kind>> kinds = {
    {"adev", dev_kind::adev},    {"oadev", dev_kind::oadev}, {"mdev", dev_kind::mdev},
    {"tdev", dev_kind::tdev},    {"hdev", dev_kind::hdev},   {"ohdev", dev_kind::ohdev},
    {"totdev", dev_kind::totdev}};

TEST(AllanStable32, PhaseDatAllTauAndOctave) {
  const auto x = test::read_values(vectors + "phasedat/PHASE.DAT");
  ASSERT_EQ(x.size(), 1001u);
  for (const auto& [name, k] : kinds) {
    check_table(vectors + "phasedat/phase_dat_" + name + ".txt", k, x, 1.0);
    check_table(vectors + "phasedat/phase_dat_" + name + "_octave.txt", k, x, 1.0);
  }
}

TEST(AllanStable32, OcxoFrequencyAllTau) {
  auto f = test::read_values(vectors + "ocxo/ocxo_frequency.txt");
  ASSERT_EQ(f.size(), 19982u);
  for (double& v : f) v = (v - 1e7) / 1e7;
  const auto x = phase_from_rate(f, 1.0);
  for (const auto& [name, k] : kinds)
    check_table(vectors + "ocxo/stable32_" + name + "_alltau.txt", k, x, 1.0);
}

TEST(AllanStable32, PinkFrequencyWithTau0Of42Seconds) {
  const auto y = test::read_values(vectors + "pink_frequency/pink_frequency.txt");
  ASSERT_EQ(y.size(), 10000u);
  const auto x42 = phase_from_rate(y, 42.0);
  for (const auto& [name, k] : kinds) {
    const std::string file = name == "totdev" ? "totdev_alpha0.txt" : name + ".txt";
    check_table(vectors + "pink_frequency/" + file, k, x42, 42.0);
  }
  check_table(vectors + "pink_frequency/s32_oadev_octave.txt", dev_kind::oadev,
              phase_from_rate(y, 1.0), 1.0);
}

TEST(AllanStable32, GpsPhaseFromSharedIfPresent) {
  const auto gps = test::gps_phase();
  if (!gps) GTEST_SKIP() << "../shared/reference/allan/gps not available";
  const auto& x = *gps;
  const std::string dir = test::gps_dir();
  ASSERT_EQ(x.size(), 241218u);
  check_table(dir + "stable32_ADEV_decade.txt", dev_kind::adev, x, 1.0);
  for (const char* name : {"OADEV", "MDEV", "TDEV", "HDEV", "OHDEV", "TOTDEV"}) {
    std::string lower(name);
    for (char& c : lower) c = static_cast<char>(std::tolower(c));
    check_table(dir + "stable32_" + name + "_octave.txt", *parse_dev_kind(lower), x, 1.0);
  }
}

// NIST SP1065 p. 107-108, NBS14 10-point set (frequency), tau = 1 and 2; 7 significant digits.
TEST(AllanNbs14, TenPoint) {
  const std::vector<double> y{892, 809, 823, 798, 671, 644, 883, 903, 677};
  const std::vector<std::pair<dev_kind, std::pair<double, double>>> expect = {
      {dev_kind::adev, {91.22945, 115.8082}}, {dev_kind::oadev, {91.22945, 85.95287}},
      {dev_kind::mdev, {91.22945, 74.78849}}, {dev_kind::totdev, {91.22945, 93.90379}},
      {dev_kind::hdev, {70.80608, 116.7980}}, {dev_kind::ohdev, {70.80607, 85.61487}},
      {dev_kind::tdev, {52.67135, 86.35831}}};
  const auto x = phase_from_rate(y, 1.0);
  for (const auto& [k, v] : expect) {
    EXPECT_NEAR(deviation_at(k, x, 1.0, 1).dev / v.first, 1.0, 1e-6) << to_string(k);
    EXPECT_NEAR(deviation_at(k, x, 1.0, 2).dev / v.second, 1.0, 1e-6) << to_string(k);
  }
}

// NIST SP1065 1000-point set (Lehmer generator), tau = 1, 10, 100 s.
TEST(AllanNbs14, ThousandPoint) {
  const auto y = test::nbs14_1000();
  const std::vector<std::pair<dev_kind, std::vector<double>>> expect = {
      {dev_kind::adev, {0.2922319, 0.09965736, 0.03897804}},
      {dev_kind::oadev, {0.2922319, 0.09159953, 0.03241343}},
      {dev_kind::mdev, {0.2922319, 0.06172376, 0.02170921}},
      {dev_kind::totdev, {0.2922319, 0.09134743, 0.03406530}},
      {dev_kind::hdev, {0.2943883, 0.1052754, 0.03910860}},
      {dev_kind::ohdev, {0.2943883, 0.09581083, 0.03237638}},
      {dev_kind::tdev, {0.1687202, 0.3563623, 1.253382}}};
  for (const auto& [k, v] : expect) {
    const auto curve = deviation(k, y, input_kind::rate, 1.0, *parse_tau_spec("1,10,100"));
    ASSERT_TRUE(curve) << curve.err().message;
    ASSERT_EQ(curve->size(), 3u);
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_NEAR((*curve)[i].dev / v[i], 1.0, 1e-6) << to_string(k) << " " << i;
  }
}

TEST(Allan, RateAndAngleInputAgree) {
  // The same signal as rate samples and as the integrated angle (not mean-removed) gives the
  // same deviations: the input kind is converted, never assumed.
  const auto y = test::nbs14_1000();
  std::vector<double> angle{100.0};
  for (double v : y) angle.push_back(angle.back() + 0.01 * v);
  for (const auto& [name, k] : kinds) {
    const auto a = deviation(k, y, input_kind::rate, 0.01, {});
    const auto b = deviation(k, angle, input_kind::angle, 0.01, {});
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->size(), b->size()) << name;
    for (std::size_t i = 0; i < a->size(); ++i)
      EXPECT_NEAR((*a)[i].dev / (*b)[i].dev, 1.0, 1e-9) << name;
  }
}

TEST(Allan, TauSetsAndErrors) {
  const auto f = averaging_factors(*parse_tau_spec("decade"), dev_kind::oadev, 100001);
  EXPECT_EQ(f, (std::vector<std::size_t>{1, 2, 4, 10, 20, 40, 100, 200, 400, 1000, 2000, 4000,
                                         10000, 20000}));
  EXPECT_EQ(averaging_factors(*parse_tau_spec("octave"), dev_kind::totdev, 1001).back(), 256u);
  EXPECT_EQ(averaging_factors(*parse_tau_spec("octave"), dev_kind::oadev, 1001).back(), 128u);
  EXPECT_EQ(averaging_factors(*parse_tau_spec("all"), dev_kind::adev, 1001).size(), 200u);
  EXPECT_FALSE(parse_tau_spec("1,x"));
  EXPECT_FALSE(parse_tau_spec("0"));
  EXPECT_FALSE(parse_tau_spec("fortnight"));
  const std::vector<double> two{1.0, 2.0};
  EXPECT_FALSE(deviation(dev_kind::oadev, std::vector<double>{1.0}, input_kind::rate, 1.0, {}));
  EXPECT_FALSE(deviation(dev_kind::oadev, two, input_kind::rate, 0.0, {}));
  EXPECT_FALSE(deviation(dev_kind::oadev, std::vector<double>{1.0, NAN, 2.0, 3.0}, input_kind::rate,
                         1.0, {}));
}

TEST(Allan, WhiteRateNoiseHasSlopeMinusHalf) {
  // White rate noise of std s per sample: ADEV(m) = s / sqrt(m) (ARW, SP1065 WFM). Fixed seed,
  // 2^20 samples; tolerance 5 % at m <= 1024 (EDF > 1000 there).
  std::uint64_t st = 99;
  const auto uniform = [&st] {
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return (static_cast<double>(st >> 11) + 0.5) * 0x1.0p-53;
  };
  std::vector<double> y(1 << 20);
  for (std::size_t i = 0; i < y.size(); i += 2) {  // Box-Muller
    const double r = std::sqrt(-2.0 * std::log(uniform())), t = 6.283185307179586 * uniform();
    y[i] = 0.3 * r * std::cos(t);
    y[i + 1] = 0.3 * r * std::sin(t);
  }
  const auto c = *oadev(y, input_kind::rate, 0.01, *parse_tau_spec("1,4,16,64,256,1024"));
  for (const auto& p : c)
    EXPECT_NEAR(p.dev * std::sqrt(static_cast<double>(p.m)) / 0.3, 1.0, 0.05) << p.m;
}

}  // namespace
}  // namespace gyroflip::analysis

namespace gyroflip::analysis {
namespace {

// Accuracy on long series with a large offset (issue 4: "no catastrophic cancellation ...
// measure it"). Reference: phase and OADEV sums entirely in long double. The library must agree
// to 1e-9; a naive double running sum (no mean removal) is shown to miss that by orders of
// magnitude, so the test would catch a regression to it.
TEST(Allan, LongSeriesWithLargeOffsetStaysAccurate) {
  constexpr std::size_t n = std::size_t{1} << 20;
  std::uint64_t st = 7;
  const auto uniform = [&st] {
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(st >> 11) * 0x1.0p-53 - 0.5;
  };
  std::vector<double> y(n);
  for (auto& v : y) v = 1000.0 + 1e-3 * uniform();  // bias 1000 deg/s, noise 3e-4 deg/s rms
  std::vector<long double> xl(n + 1, 0.0L);
  std::vector<double> xn(n + 1, 0.0);  // naive: double running sum, no mean removal
  for (std::size_t i = 0; i < n; ++i) {
    xl[i + 1] = xl[i] + static_cast<long double>(y[i]);
    xn[i + 1] = xn[i] + y[i];
  }
  for (std::size_t m : {std::size_t{1}, std::size_t{64}, std::size_t{4096}}) {
    long double s = 0.0L;
    for (std::size_t i = 0; i + 2 * m <= n; ++i) {
      const long double d = xl[i + 2 * m] - 2.0L * xl[i + m] + xl[i];
      s += d * d;
    }
    const long double tau = static_cast<long double>(m);
    const auto ref = static_cast<double>(
        std::sqrt(s / (2.0L * tau * tau * static_cast<long double>(n + 1 - 2 * m))));
    const double ours = deviation_at(dev_kind::oadev, phase_from_rate(y, 1.0), 1.0, m).dev;
    const double naive = deviation_at(dev_kind::oadev, xn, 1.0, m).dev;
    EXPECT_NEAR(ours / ref, 1.0, 1e-9) << m;
    EXPECT_GT(std::abs(naive / ref - 1.0), 1e-7) << m;  // the naive sum really is worse
  }
}

}  // namespace
}  // namespace gyroflip::analysis

namespace gyroflip::analysis {
namespace {

// ADEV and HDEV of rate samples at octave factors come from block sums of the samples (one read,
// no phase; docs/ANALYSIS.md "ADEV and HDEV of rate samples from block sums"). Against a direct
// long-double reference of the same statistic (block sums S_k of m samples, (order-1)-th
// differences of S; tau0 cancels), and against the phase path (a phase_source, as the intervals
// use), on white and random-walk rate noise, on lengths around the 2^18-sample work items and below
// one item.
TEST(Allan, OctaveAdevHdevFromBlockSums) {
  std::uint64_t st = 11;
  const auto uniform = [&st] {
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(st >> 11) * 0x1.0p-53 - 0.5;
  };
  for (const std::size_t n : {std::size_t{7}, std::size_t{4097}, (std::size_t{1} << 18) - 1,
                              (std::size_t{1} << 18) + 1, 3 * (std::size_t{1} << 18) + 5}) {
    for (const bool walk : {false, true}) {
      std::vector<double> y(n);
      double level = 0.0;
      for (auto& v : y) {
        level = walk ? level + uniform() : 5.0 + uniform();
        v = level;
      }
      const span_samples samples(y);
      const auto phase = *phase_source::make(samples, input_kind::rate, 0.5);
      for (const dev_kind k : {dev_kind::adev, dev_kind::hdev}) {
        const std::size_t order = k == dev_kind::adev ? 2 : 3;
        const auto fast = *deviation(k, samples, input_kind::rate, 0.5, {});
        const auto slow = *deviation(k, phase, {});
        ASSERT_EQ(fast.size(), slow.size()) << n;
        for (std::size_t i = 0; i < fast.size(); ++i) {
          const std::size_t m = fast[i].m;
          ASSERT_EQ(m, slow[i].m);
          EXPECT_EQ(fast[i].n, slow[i].n) << n << " m " << m;
          // The phase path's own rounding on a random walk reaches 1e-11 (its phase grows as
          // N^1.5); the block sums match the long-double reference to 1e-13 either way.
          EXPECT_NEAR(fast[i].dev / slow[i].dev, 1.0, walk ? 1e-10 : 1e-12) << n << " m " << m;
          std::vector<long double> s(n / m, 0.0L);
          for (std::size_t j = 0; j < s.size() * m; ++j) s[j / m] += static_cast<long double>(y[j]);
          long double sum = 0.0L;
          for (std::size_t j = 0; j + order <= s.size(); ++j) {
            const long double d = order == 2 ? s[j + 1] - s[j] : s[j + 2] - 2.0L * s[j + 1] + s[j];
            sum += d * d;
          }
          const auto terms = static_cast<long double>(s.size() + 1 - order);
          const long double c = order == 2 ? 2.0L : 6.0L;
          const auto ref =
              static_cast<double>(std::sqrt(sum / (c * static_cast<long double>(m * m) * terms)));
          EXPECT_NEAR(fast[i].dev / ref, 1.0, 1e-13) << n << " m " << m << (walk ? " walk" : "");
        }
      }
    }
  }
  // A non-finite sample is named as before (the phase path reports it); a factor that is not a
  // power of two takes the phase path.
  std::vector<double> y(5000, 1.0);
  y[4321] = NAN;
  const auto bad = deviation(dev_kind::adev, y, input_kind::rate, 1.0, {});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.err().message.find("sample 4321 (0-based) is not finite"), std::string::npos);
  y[4321] = 2.0;
  const auto mixed = *deviation(dev_kind::hdev, y, input_kind::rate, 1.0, *parse_tau_spec("3,4"));
  ASSERT_EQ(mixed.size(), 2u);
  EXPECT_EQ(mixed[0].m, 3u);
}

}  // namespace
}  // namespace gyroflip::analysis

// The one table of per-statistic facts (issue 34, item 8) against what each algorithm does: the
// fewest phase points with a term at m (need_per_m m + need_extra) is where deviation_at's term
// count turns from 0 to positive, Stable32's largest factor is the last one `all` gives, Theo1
// keeps even factors, and its tau is 0.75 m tau0. A wrong row fails here, not in a user's plot.
TEST(DevFacts, EveryRowAgreesWithItsAlgorithm) {
  using namespace gyroflip::analysis;
  std::vector<double> x(64);
  std::uint64_t s = 12345;  // a fixed LCG: any phase with non-zero differences will do
  for (double& v : x) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    v = static_cast<double>(s >> 11) * 0x1p-53 - 0.5;
  }
  for (const auto& f : dev_table) {
    SCOPED_TRACE(std::string(f.name));
    EXPECT_EQ(parse_dev_kind(f.name), f.kind);
    for (std::size_t m : {2u, 4u, 6u}) {
      const std::size_t need = f.need_per_m * m + f.need_extra;
      ASSERT_LE(need, x.size());
      const std::span<const double> enough(x.data(), need), short_of(x.data(), need - 1);
      EXPECT_GT(deviation_at(f.kind, enough, 1.0, m).n, 0u) << "m = " << m;
      EXPECT_EQ(deviation_at(f.kind, short_of, 1.0, m).n, 0u) << "m = " << m;
    }
    const auto all = averaging_factors(tau_spec{tau_spec::set::all, {}}, f.kind, 101);
    ASSERT_FALSE(all.empty());
    const std::size_t limit = 100 / f.span_divisor;
    EXPECT_EQ(all.back(), f.even_m_only ? limit - limit % 2 : limit);
    const auto odd = std::find_if(all.begin(), all.end(), [](std::size_t m) { return m % 2; });
    EXPECT_EQ(odd == all.end(), f.even_m_only);
    const auto curve = deviation_of_phase(f.kind, x, 0.5, tau_spec{tau_spec::set::list, {4}});
    ASSERT_TRUE(curve) << curve.err().message;
    EXPECT_DOUBLE_EQ(curve->front().tau_s, f.tau_factor * 4 * 0.5);
  }
}
