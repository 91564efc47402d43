// Confidence intervals against Stable32: noise identification (alpha column), Greenhall EDF and
// chi-squared bounds (Min/Max Sigma columns at 68.3 %), plus chi-squared quantiles.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/sensor/random.hpp"
#include "support/reference_data.hpp"

namespace gyroflip::analysis {
namespace {

const std::string vectors = std::string(GYROFLIP_VECTORS_DIR) + "/stable32/";

// With Stable32's alpha, our bounds must agree to `tol` (both use Greenhall & Riley's algorithm
// with its tables; Stable32 has its own chi-squared approximation). Where our lag-1 noise
// identification has enough points, it must give Stable32's alpha.
void check_ci(const std::string& table, dev_kind k, const std::vector<double>& x, double tol) {
  const auto rows = test::read_stable32_table(table);
  ASSERT_FALSE(rows.empty()) << table;
  for (const auto& r : rows) {
    const double dev = deviation_at(k, x, 1.0, r.af).dev;
    const double e = edf(k, r.alpha, r.af, x.size());
    const double lo = dev * std::sqrt(e / chi2_quantile(1.0 - 0.1585, e));
    const double hi = dev * std::sqrt(e / chi2_quantile(0.1585, e));
    EXPECT_NEAR(lo / r.lo, 1.0, tol) << table << " AF " << r.af;
    EXPECT_NEAR(hi / r.hi, 1.0, tol) << table << " AF " << r.af;
    // Stable32 (and allantools) use lag-1 from 31 decimated points on; at 30 (GPS, m = 8192)
    // Stable32 already reads the type differently.
    if (x.size() / r.af >= 31) {
      if (const auto id = noise_alpha_lag1(x, r.af)) {
        EXPECT_EQ(*id, r.alpha) << table << " AF " << r.af;
      }
    }
  }
}

// Our curve of kind k at a table's factors with 68.3 % bounds, as add_confidence gives them.
std::vector<deviation_point> default_curve(const std::vector<test::stable32_row>& rows, dev_kind k,
                                           const std::vector<double>& x) {
  tau_spec spec{tau_spec::set::list, {}};
  for (const auto& r : rows) spec.factors.push_back(r.af);
  auto pts = *deviation(k, x, input_kind::angle, 1.0, spec);
  add_confidence(pts, k, x, 0.683);
  return pts;
}

// Issue 23: the curve with bounds as `gyroflip adev` computes it by default (noise identified at
// each tau by us, edf_rule::stable32) against a Stable32 table: wherever our alpha is Stable32's,
// both bounds agree to 1e-3; rows in `loose` (AF -> tolerance) are documented exceptions. Returns
// the rows where the alpha agreed.
std::size_t check_end_to_end(const std::string& table, dev_kind k, const std::vector<double>& x,
                             const std::map<std::size_t, double>& loose = {}) {
  const auto rows = test::read_stable32_table(table);
  const auto pts = default_curve(rows, k, x);
  EXPECT_EQ(pts.size(), rows.size()) << table;
  std::size_t agreed = 0;
  for (std::size_t i = 0; i < std::min(pts.size(), rows.size()); ++i) {
    const auto& p = pts[i];
    const auto& r = rows[i];
    EXPECT_EQ(p.m, r.af) << table;
    EXPECT_EQ(p.n, r.n) << table << " AF " << r.af;
    // The default rule: the EDF of the type identified at this tau, nothing else.
    EXPECT_EQ(p.edf, edf(k, p.alpha, p.m, x.size())) << table << " AF " << r.af;
    if (p.alpha != r.alpha) continue;
    ++agreed;
    const auto it = loose.find(r.af);
    const double tol = it == loose.end() ? 1e-3 : it->second;
    EXPECT_NEAR(p.ci_lo / r.lo, 1.0, tol) << table << " AF " << r.af;
    EXPECT_NEAR(p.ci_hi / r.hi, 1.0, tol) << table << " AF " << r.af;
  }
  return agreed;
}

TEST(Confidence, Chi2Quantiles) {
  // Published values (e.g. NIST/SEMATECH e-Handbook table of chi-squared critical values).
  EXPECT_NEAR(chi2_quantile(0.95, 1), 3.841459, 1e-6);
  EXPECT_NEAR(chi2_quantile(0.05, 10), 3.940299, 1e-6);
  EXPECT_NEAR(chi2_quantile(0.99, 100), 135.807, 1e-3);
  EXPECT_NEAR(chi2_quantile(0.025, 1), 0.000982069, 1e-9);
  EXPECT_NEAR(chi2_quantile(0.975, 1), 5.023886, 1e-6);
  EXPECT_NEAR(chi2_quantile(0.5, 1), 0.4549364, 1e-7);
  EXPECT_NEAR(chi2_quantile(0.5, 2), 2.0 * std::log(2.0), 1e-12);  // exponential median
}

// Student's t quantiles against published tables (NIST/SEMATECH e-Handbook §1.3.6.7.2, upper
// critical values; Abramowitz & Stegun Table 26.10) and closed forms: nu = 1 is Cauchy
// (tan(pi (p - 1/2))), nu = 2 has t = (2p - 1) sqrt(2 / (4p(1 - p))).
// The distribution function behind the runs' lower-tail test (fifth review of issue 31, F9): closed
// forms for 2 dof (1 - exp(-x/2)) and 1 dof (erf(sqrt(x/2))), and the inverse of chi2_quantile.
TEST(Confidence, Chi2DistributionFunction) {
  for (const double x : {1e-8, 2e-4, 0.5, 3.0, 20.0}) {
    EXPECT_NEAR(chi2_cdf(x, 2.0), -std::expm1(-x / 2.0), 1e-12 * (1.0 - std::exp(-x / 2.0)) + 1e-15)
        << x;
    EXPECT_NEAR(chi2_cdf(x, 1.0), std::erf(std::sqrt(x / 2.0)), 1e-10) << x;
  }
  for (const double dof : {1.0, 3.0, 12.0})
    for (const double p : {1e-4, 0.3, 0.95})
      EXPECT_NEAR(chi2_cdf(chi2_quantile(p, dof), dof), p, 1e-9 * p);
  EXPECT_EQ(chi2_cdf(0.0, 2.0), 0.0);
  EXPECT_TRUE(std::isnan(chi2_cdf(1.0, 0.0)));
}

TEST(Confidence, StudentTQuantiles) {
  const double t975[] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
                         2.201,  2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086};
  for (std::size_t nu = 1; nu <= 20; ++nu)
    EXPECT_NEAR(student_t_quantile(0.975, static_cast<double>(nu)), t975[nu - 1], 5e-4) << nu;
  EXPECT_NEAR(student_t_quantile(0.995, 10), 3.169, 5e-4);
  EXPECT_NEAR(student_t_quantile(0.9995, 5), 6.869, 5e-4);
  EXPECT_NEAR(student_t_quantile(0.999, 30), 3.385, 5e-4);
  EXPECT_NEAR(student_t_quantile(0.9, 1), std::tan(std::numbers::pi * 0.4), 1e-9);
  const double p = 0.99;
  EXPECT_NEAR(student_t_quantile(p, 2), (2 * p - 1) * std::sqrt(2.0 / (4 * p * (1 - p))), 1e-9);
  EXPECT_NEAR(student_t_quantile(0.025, 7), -student_t_quantile(0.975, 7), 1e-12);
  EXPECT_NEAR(student_t_quantile(0.5, 4), 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(student_t_quantile(1.0, 4)));
  EXPECT_TRUE(std::isnan(student_t_quantile(0.9, 0)));
}

TEST(Confidence, PhaseDatAllKindsMatchStable32) {
  std::ifstream f(vectors + "phasedat/PHASE.DAT");
  const auto x = test::read_values(f);
  for (const char* k : {"adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"})
    check_ci(vectors + "phasedat/phase_dat_" + k + "_octave.txt", *parse_dev_kind(k), x, 1e-3);
}

TEST(Confidence, PinkFlickerFmMatchesStable32) {
  std::ifstream f(vectors + "pink_frequency/pink_frequency.txt");
  const auto x = phase_from_rate(test::read_values(f), 1.0);
  check_ci(vectors + "pink_frequency/s32_oadev_octave.txt", dev_kind::oadev, x, 1e-3);
}

TEST(Confidence, GpsWhiteAndFlickerPmFromSharedIfPresent) {
  const auto gps = test::gps_phase();
  if (!gps) GTEST_SKIP() << "../shared/reference/allan/gps not available";
  const auto& x = *gps;
  const std::string dir = test::gps_dir();
  for (const char* k : {"OADEV", "MDEV", "TDEV", "HDEV", "OHDEV"}) {
    std::string lower(k);
    for (char& c : lower) c = static_cast<char>(std::tolower(c));
    check_ci(dir + "stable32_" + k + "_octave.txt", *parse_dev_kind(lower), x, 1e-3);
  }
  check_ci(dir + "stable32_ADEV_decade.txt", dev_kind::adev, x, 1e-3);
  // TOTDEV with flicker PM: SP1065 Table 5's formula (as allantools' edf_totdev) is within 6e-4
  // of Stable32 up to m = 32768; at m = 65536 (beyond (N-1)/4, T/tau = 3.7) Stable32's interval
  // is 3e-3 narrower (its EDF 5 % larger: 43.7 against 41.6).
  const auto rows = test::read_stable32_table(dir + "stable32_TOTDEV_octave.txt");
  for (const auto& r : rows) {
    const double dev = deviation_at(dev_kind::totdev, x, 1.0, r.af).dev;
    const double e = edf(dev_kind::totdev, r.alpha, r.af, x.size());
    const double tol = r.af == 65536 ? 4e-3 : 1e-3;
    EXPECT_NEAR(dev * std::sqrt(e / chi2_quantile(1.0 - 0.1585, e)) / r.lo, 1.0, tol) << r.af;
    EXPECT_NEAR(dev * std::sqrt(e / chi2_quantile(0.1585, e)) / r.hi, 1.0, tol) << r.af;
  }
}

// Issue 23: by default the bounds are Stable32's (the type identified at each tau), on every
// Stable32 table with bounds that tests/vectors and ../shared hold: 1e-3 wherever the type agrees.
// Our types are Stable32's on every row of the PHASE.DAT octave tables but TOTDEV (7 of 9) and of
// the pink one; on GPS on all but 1 row of 15-17 per table (NoiseTypeIsStable32sOnItsTables).
TEST(Confidence, DefaultBoundsAreStable32sWhereTheNoiseTypeAgrees) {
  const auto x = test::read_values(vectors + "phasedat/PHASE.DAT");
  for (const char* k : {"adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"})
    EXPECT_GE(check_end_to_end(vectors + "phasedat/phase_dat_" + std::string(k) + "_octave.txt",
                               *parse_dev_kind(k), x),
              std::string(k) == "totdev" ? 7u : 8u)
        << k;
  const auto pink =
      phase_from_rate(test::read_values(vectors + "pink_frequency/pink_frequency.txt"), 1.0);
  EXPECT_GE(
      check_end_to_end(vectors + "pink_frequency/s32_oadev_octave.txt", dev_kind::oadev, pink),
      12u);
  const auto gps = test::gps_phase();
  if (!gps) GTEST_SKIP() << "../shared/reference/allan/gps not available";
  const std::string dir = test::gps_dir();
  EXPECT_GE(check_end_to_end(dir + "stable32_ADEV_decade.txt", dev_kind::adev, *gps), 15u);
  for (const char* name : {"OADEV", "MDEV", "TDEV", "HDEV", "OHDEV"}) {
    std::string lower(name);
    for (char& c : lower) c = static_cast<char>(std::tolower(c));
    EXPECT_GE(
        check_end_to_end(dir + "stable32_" + name + "_octave.txt", *parse_dev_kind(lower), *gps),
        15u)
        << name;
  }
  EXPECT_GE(
      check_end_to_end(dir + "stable32_TOTDEV_octave.txt", dev_kind::totdev, *gps, {{65536, 4e-3}}),
      16u);
}

// Rows of a Stable32 table (any kind with an alpha column, all-tau or not) where our noise type at
// the row's factor, identified for kind k as add_confidence does, is Stable32's alpha.
std::size_t alpha_agreement(const std::string& table, dev_kind k, const std::vector<double>& x) {
  const auto rows = test::read_stable32_table(table);
  const auto pts = default_curve(rows, k, x);
  EXPECT_EQ(pts.size(), rows.size()) << table;
  std::size_t agreed = 0;
  for (std::size_t i = 0; i < std::min(pts.size(), rows.size()); ++i)
    if (pts[i].alpha == rows[i].alpha) ++agreed;
  return agreed;
}

// Issue 23 review H1 (2026-11-24): the noise type is Stable32's on every row of its PHASE.DAT
// all-tau tables, B1 rows included (before: 112-121 of 125-139 for the classic kinds, 171 of 185
// TOTDEV, 114 of 158 MTOTDEV/TTOTDEV, whose bias correction was then 2-6 % off on the other 44).
// Stable32's B1 rule as its tables show it (docs/ANALYSIS.md, "Noise identification"): N of
// B1(N, mu) the number of frequency data except for ADEV/HDEV, and no type beyond half the kind's
// largest all-tau factor. Rows agreeing now (before) elsewhere: OCXO all-tau ADEV 252 (232) of 261,
// OADEV 269 (212) and MDEV, TDEV, OHDEV 268 (213) of 273, HDEV 241 (221) of 261, TOTDEV 78 (5) of
// 310; pink ADEV, HDEV 222 (211) of 225, OADEV, MDEV, TDEV, OHDEV 194 (180) of 195, octave OADEV
// 12 (11) of 12; GPS ADEV decade 15 (14) of 15, octave OADEV ... OHDEV 15 (14) of 16, TOTDEV 16
// of 17; PHASE.DAT octave TOTDEV 7 of 9. No table lost a row.
TEST(Confidence, NoiseTypeIsStable32sOnItsTables) {
  const auto x = test::read_values(vectors + "phasedat/PHASE.DAT");
  const std::string pd = vectors + "phasedat/phase_dat_";
  const std::map<std::string, std::size_t> all_tau = {
      {"adev", 125}, {"oadev", 139}, {"mdev", 139},  {"tdev", 139},
      {"hdev", 125}, {"ohdev", 139}, {"totdev", 185}};
  for (const auto& [k, rows] : all_tau) {
    EXPECT_EQ(alpha_agreement(pd + k + ".txt", *parse_dev_kind(k), x), rows) << k;
    EXPECT_EQ(alpha_agreement(pd + k + "_octave.txt", *parse_dev_kind(k), x),
              k == "totdev" ? 7u : 8u)
        << k;
  }
  EXPECT_EQ(alpha_agreement(pd + "mtotdev.txt", dev_kind::mtotdev, x), 158u);
  EXPECT_EQ(alpha_agreement(pd + "ttotdev_all.txt", dev_kind::ttotdev, x), 158u);
  EXPECT_EQ(alpha_agreement(pd + "mtotdev_octave.txt", dev_kind::mtotdev, x), 5u);
  EXPECT_EQ(alpha_agreement(pd + "mtotdev_decade.txt", dev_kind::mtotdev, x), 8u);
  EXPECT_EQ(alpha_agreement(pd + "ttotdev_octave.txt", dev_kind::ttotdev, x), 5u);
  EXPECT_EQ(alpha_agreement(pd + "htotdev_octave.txt", dev_kind::htotdev, x), 5u);
  auto f = test::read_values(vectors + "ocxo/ocxo_frequency.txt");
  for (double& v : f) v = (v - 1e7) / 1e7;
  const auto ocxo = phase_from_rate(f, 1.0);
  const std::map<std::string, std::size_t> ocxo_rows = {
      {"adev", 252}, {"oadev", 269}, {"mdev", 268}, {"tdev", 268},
      {"hdev", 241}, {"ohdev", 268}, {"totdev", 78}};
  for (const auto& [k, rows] : ocxo_rows)
    EXPECT_GE(
        alpha_agreement(vectors + "ocxo/stable32_" + k + "_alltau.txt", *parse_dev_kind(k), ocxo),
        rows)
        << k;
  const auto pink =
      phase_from_rate(test::read_values(vectors + "pink_frequency/pink_frequency.txt"), 1.0);
  const std::map<std::string, std::size_t> pink_rows = {
      {"adev", 222}, {"oadev", 194}, {"mdev", 194}, {"tdev", 194}, {"hdev", 222}, {"ohdev", 194}};
  for (const auto& [k, rows] : pink_rows)
    EXPECT_GE(alpha_agreement(vectors + "pink_frequency/" + k + ".txt", *parse_dev_kind(k), pink),
              rows)
        << k;
  EXPECT_EQ(alpha_agreement(vectors + "pink_frequency/s32_oadev_octave.txt", dev_kind::oadev, pink),
            12u);
  // GPS: DefaultBoundsAreStable32sWhereTheNoiseTypeAgrees counts its rows.
}

// Re-review L6: a known noise type (Stable32's manual setting) gives every point that type's EDF;
// on PHASE.DAT's octave OADEV (white FM at every tau in Stable32's table) the bounds are the
// table's, whatever other taus are listed; a type outside 2..-2 is refused.
TEST(Confidence, AGivenNoiseTypeGivesTheTablesBoundsAtEveryTau) {
  const auto x = test::read_values(vectors + "phasedat/PHASE.DAT");
  const auto rows = test::read_stable32_table(vectors + "phasedat/phase_dat_oadev_octave.txt");
  auto pts = *deviation(dev_kind::oadev, x, input_kind::angle, 1.0, {});
  add_confidence(pts, dev_kind::oadev, x.size(), 0.683, 0);
  ASSERT_EQ(pts.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(pts[i].alpha, 0);
    EXPECT_EQ(pts[i].edf, edf(dev_kind::oadev, 0, pts[i].m, x.size()));
    EXPECT_NEAR(pts[i].ci_lo / rows[i].lo, 1.0, 1e-3) << rows[i].af;
    EXPECT_NEAR(pts[i].ci_hi / rows[i].hi, 1.0, 1e-3) << rows[i].af;
  }
  // Flicker PM given instead: a different EDF, so different bounds around the same value.
  auto fpm = *deviation(dev_kind::oadev, x, input_kind::angle, 1.0, {});
  add_confidence(fpm, dev_kind::oadev, x.size(), 0.683, 1);
  EXPECT_NE(fpm.back().edf, pts.back().edf);
  EXPECT_EQ(fpm.back().dev, pts.back().dev);
  EXPECT_TRUE(check_noise_alpha(-2));
  EXPECT_FALSE(check_noise_alpha(3));
  EXPECT_FALSE(check_noise_alpha(-3));
}

// Issue 23: the guard of issue 13 item 14 is an option (edf_rule::guarded): never a larger EDF than
// the default, and the same alpha. On PHASE.DAT's octave taus every type is Stable32's white FM,
// so the guarded bounds are Stable32's; on its all-tau factors Stable32 itself reads flicker PM
// at a few taus between white-FM ones (AF 69-71, 83, 87 ...), and there the guard narrows the EDF.
TEST(Confidence, GuardIsAnOptionThatNeverNarrowsAnInterval) {
  const auto x = test::read_values(vectors + "phasedat/PHASE.DAT");
  const auto rows = test::read_stable32_table(vectors + "phasedat/phase_dat_oadev_octave.txt");
  auto plain = *deviation(dev_kind::oadev, x, input_kind::angle, 1.0, {});
  auto guarded = plain;
  add_confidence(plain, dev_kind::oadev, x, 0.683);
  add_confidence(guarded, dev_kind::oadev, x, 0.683, edf_rule::guarded);
  ASSERT_EQ(plain.size(), rows.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(guarded[i].alpha, rows[i].alpha);
    EXPECT_NEAR(guarded[i].ci_lo / rows[i].lo, 1.0, 1e-3) << rows[i].af;
    EXPECT_NEAR(guarded[i].ci_hi / rows[i].hi, 1.0, 1e-3) << rows[i].af;
  }
  const auto all = test::read_stable32_table(vectors + "phasedat/phase_dat_oadev.txt");
  tau_spec spec{tau_spec::set::list, {}};
  for (const auto& r : all) spec.factors.push_back(r.af);
  plain = *deviation(dev_kind::oadev, x, input_kind::angle, 1.0, spec);
  guarded = plain;
  add_confidence(plain, dev_kind::oadev, x, 0.683);
  add_confidence(guarded, dev_kind::oadev, x, 0.683, edf_rule::guarded);
  std::size_t narrowed = 0;
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(guarded[i].alpha, plain[i].alpha);
    EXPECT_LE(guarded[i].edf, plain[i].edf);
    if (guarded[i].edf < plain[i].edf) ++narrowed;
  }
  EXPECT_GE(narrowed, 5u);
}

TEST(Confidence, AddConfidenceEndToEndOnPhaseDat) {
  std::ifstream f(vectors + "phasedat/PHASE.DAT");
  const auto x = test::read_values(f);
  auto pts = *deviation(dev_kind::oadev, x, input_kind::angle, 1.0, {});
  add_confidence(pts, dev_kind::oadev, x, 0.683);
  const auto rows = test::read_stable32_table(vectors + "phasedat/phase_dat_oadev_octave.txt");
  ASSERT_EQ(pts.size(), rows.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    // With 30 decimated points or more the lag-1 type is Stable32's, and so are the bounds.
    if ((x.size() - 1) / pts[i].m + 1 >= 30) {
      EXPECT_EQ(pts[i].alpha, rows[i].alpha) << pts[i].m;
      EXPECT_NEAR(pts[i].ci_lo / rows[i].lo, 1.0, 1e-3) << i;
      EXPECT_NEAR(pts[i].ci_hi / rows[i].hi, 1.0, 1e-3) << i;
    }
    EXPECT_LT(pts[i].ci_lo, pts[i].dev);
    EXPECT_GT(pts[i].ci_hi, pts[i].dev);
  }
  // A wider level gives wider bounds.
  auto wide = pts;
  add_confidence(wide, dev_kind::oadev, x, 0.95);
  EXPECT_LT(wide[3].ci_lo, pts[3].ci_lo);
  EXPECT_GT(wide[3].ci_hi, pts[3].ci_hi);
}

// Regression (issue 13 item 16, 2026-11-23): EDF sums ran up to 20 000 terms, so `adev --taus all`
// spent most of its time in log. Greenhall's large-r forms keep the cost bounded; their values
// must agree with the simple formulas of SP1065 Table 5 (OADEV; white PM, white FM, random-walk
// FM) away from the ends (m >= 40: below, Table 5's white-FM form is itself off by up to 17 %,
// while Greenhall's sum is exact there), and stay positive, finite and non-increasing in m.
TEST(Edf, LargeFactorsAgreeWithSimpleFormulasAndAreBounded) {
  constexpr std::size_t n = 1000000;
  const double nn = static_cast<double>(n);
  double last[3] = {1e300, 1e300, 1e300};
  for (std::size_t m = 1; m <= n / 8; m = m * 3 / 2 + 1) {
    const double mm = static_cast<double>(m);
    const double wfm =
        (3.0 * (nn - 1) / (2 * mm) - 2.0 * (nn - 2) / nn) * 4 * mm * mm / (4 * mm * mm + 5);
    const double rwfm = (nn - 2) / (mm * (nn - 3) * (nn - 3)) *
                        ((nn - 1) * (nn - 1) - 3 * mm * (nn - 1) + 4 * mm * mm);
    const double wpm = (nn + 1) * (nn - 2 * mm) / (2 * (nn - mm));
    const double got[3] = {edf(dev_kind::oadev, 2, m, n), edf(dev_kind::oadev, 0, m, n),
                           edf(dev_kind::oadev, -2, m, n)};
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(std::isfinite(got[k]) && got[k] > 0.0) << m;
      EXPECT_LE(got[k], last[k] * (1 + 1e-9)) << "k " << k << " m " << m;
      last[k] = got[k];
    }
    if (m >= 40 && m <= n / 20) {
      EXPECT_NEAR(got[1] / wfm, 1.0, 0.05) << m;
      EXPECT_NEAR(got[2] / rwfm, 1.0, 0.10) << m;
    }
    if (m >= 4) {
      EXPECT_NEAR(got[0] / wpm, 1.0, 0.05) << m;
    }
    // Every kind and noise type, bounded work or not, gives a usable number.
    for (const auto k :
         {dev_kind::adev, dev_kind::mdev, dev_kind::hdev, dev_kind::ohdev, dev_kind::totdev})
      for (int alpha = -2; alpha <= 2; ++alpha) {
        if (alpha == -2 && k == dev_kind::mdev) continue;
        const double e = edf(k, alpha, m, n);
        EXPECT_TRUE(std::isfinite(e) && e >= 0.0) << to_string(k) << " " << alpha << " " << m;
      }
  }
}

// Issue 23 review F7/F8 (2026-11-24): Tables 1-2 had rows alpha = 2 .. -2 only, so the overlapping
// Hadamard EDF of flicker-walk (-3) and random-run (-4) FM read past the array (ASan: index 5 of
// table_ab[5][3]) and came out ~35 % high (-3, m 33, N 1000: 35.95); d = 1 and modified d = 3 were
// refused. Truth: Greenhall's basic sum evaluated in full, all J terms ("direct", the issue 23
// reviewer's transcription, /tmp/rev23a/w/ci3.py), and allantools 2024.06's edf_greenhall (same
// algorithm and tables; it has no row -4 for unmodified variances). The table forms approximate the
// sum: within 0.1 % here (-4, m 33: 21.290 against 21.284).
TEST(Edf, GreenhallCoversEveryDefinedAlphaAndDifference) {
  struct case_t {
    int alpha, d;
    std::size_t m, n;
    bool overlapping, modified;
    double direct, allantools, tol;  // allantools 0: not defined there
  };
  const case_t cases[] = {
      {-3, 3, 33, 1000, true, false, 26.428519669305047, 26.43731816631665, 1e-3},
      {-3, 3, 100, 1000, true, false, 7.185156075975377, 7.186858316221767, 1e-3},
      {-4, 3, 33, 1000, true, false, 21.284045041851954, 0.0, 1e-3},
      {-4, 3, 64, 5000, true, false, 58.004812635453085, 0.0, 1e-3},
      {-3, 3, 33, 1000, true, true, 22.560199515983182, 22.5591087688098, 1e-3},
      {-4, 3, 33, 1000, true, true, 18.003064025459402, 18.007646252614876, 1e-3},
      {-4, 3, 64, 5000, true, true, 50.09869687376954, 50.11087946202889, 1e-3},
      {0, 1, 256, 100000, false, false, 389.9996693804659, 390.0, 1e-3},
      {1, 1, 256, 100000, false, false, 277.4169289239757, 277.4169289239757, 1e-9},
      {0, 1, 256, 100000, true, false, 583.2952210707042, 584.8127407704656, 3e-3},
      {-1, 2, 256, 100000, false, true, 347.8192163966693, 347.8192163966693, 1e-9},
      {0, 3, 256, 100000, true, true, 327.1706451840889, 327.150719335708, 1e-3},
  };
  for (const auto& c : cases) {
    const auto e = edf_greenhall(c.alpha, c.d, c.m, c.n, c.overlapping, c.modified);
    ASSERT_TRUE(e) << c.alpha << " " << c.d;
    EXPECT_NEAR(*e / c.direct, 1.0, c.tol) << c.alpha << " d " << c.d << " m " << c.m;
    if (c.allantools > 0.0) {
      EXPECT_NEAR(*e / c.allantools, 1.0, 1e-9) << c.alpha << " d " << c.d << " m " << c.m;
    }
  }
  // The kinds' EDF is this function's.
  EXPECT_EQ(edf(dev_kind::ohdev, -4, 64, 5000), *edf_greenhall(-4, 3, 64, 5000, true, false));
  // Undefined: alpha + 2d <= 1, alpha or d out of range, m = 0 (no EDF, nothing read).
  for (const auto& [alpha, d] : std::vector<std::pair<int, int>>{
           {-1, 1}, {-2, 1}, {-3, 2}, {-4, 2}, {-5, 3}, {3, 2}, {0, 0}, {0, 4}})
    EXPECT_FALSE(edf_greenhall(alpha, d, 8, 1000, true, false)) << alpha << " " << d;
  EXPECT_FALSE(edf_greenhall(0, 2, 0, 1000, true, false));
  EXPECT_EQ(edf(dev_kind::oadev, -3, 8, 1000), 0.0);
  EXPECT_EQ(edf(dev_kind::hdev, 7, 8, 1000), 0.0);
}

// Issue 13 item 14: below 30 decimated points the noise type comes from the B1 ratio (and R(n)
// for PM), as Stable32. On 16 points B1 is a weak test (Barnes): over 200 seeds each type must be
// identified far more often than chance (25 %). Measured rates: PM 0.85, WFM 0.67, RWFM 0.71
// (binomial standard error 0.033); the thresholds sit 3 standard errors below.
TEST(Confidence, FewPointNoiseTypeByB1) {
  constexpr std::size_t m = 20;
  constexpr std::size_t points = 16;
  constexpr std::size_t n = (points - 1) * m + 1;
  int pm = 0, wfm = 0, rwfm = 0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    sensor::normal_stream g(seed, sensor::stream::user);
    std::vector<double> w(n), x1(n), x2(n);
    for (auto& v : w) v = g.next();
    for (std::size_t i = 1; i < n; ++i) x1[i] = x1[i - 1] + w[i - 1];
    for (std::size_t i = 1; i < n; ++i) x2[i] = x2[i - 1] + x1[i - 1];
    const auto a_pm = noise_alpha(w, m);
    pm += a_pm && *a_pm >= 1;
    wfm += noise_alpha(x1, m) == 0;
    rwfm += noise_alpha(x2, m) == -2;
  }
  EXPECT_GE(pm, 150);
  EXPECT_GE(wfm, 110);
  EXPECT_GE(rwfm, 120);
  // Below 5 points nothing is identified.
  EXPECT_FALSE(noise_alpha(std::vector<double>(4 * m, 1.0), m));
}

}  // namespace
}  // namespace gyroflip::analysis

namespace gyroflip::analysis {
namespace {

// Issue 23: deviation_with_confidence takes ADEV's and HDEV's noise-identification series from
// the block sums of its one read (rate samples, power-of-two factors). Against the two calls it
// replaces (the phase decimated point by point): the same curve, the same noise type at every
// tau (lag-1 on x_{km}, k < 2^20; B1 and R(n) on the last taus), the same EDF and bounds to
// rounding. Rate series with known types: white rate (alpha 0), its running sum (rate random
// walk, -2), the first difference of white noise (white PM, 2: R(n) splits it at the last
// taus); long enough (2^21 + 5 samples) that the first factors reach the 2^20-point cap.
TEST(Confidence, DeviationWithConfidenceFromBlockSumsEqualsTheTwoCalls) {
  constexpr std::size_t n = (std::size_t{1} << 21) + 5;
  sensor::normal_stream g(23, sensor::stream::user);
  std::vector<double> white(n + 1), walk(n), pm(n);
  for (auto& v : white) v = 0.3 + g.next();  // an offset: the mean the phase removes
  double run = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    run += white[i] - 0.3;
    walk[i] = 1e-3 * run;
    pm[i] = 0.3 + (white[i + 1] - white[i]);  // the offset: a trend in x unless removed
  }
  white.pop_back();
  const std::vector<std::pair<std::vector<double>*, int>> cases = {
      {&white, 0}, {&walk, -2}, {&pm, 2}};
  tau_spec repeated{tau_spec::set::list, {1, 4, 4, 1024, 64}};  // a factor twice, unsorted
  for (const auto& [y, alpha] : cases) {
    const span_samples samples(*y);
    const auto x = *phase_source::make(samples, input_kind::rate, 0.01);
    for (const auto k : {dev_kind::adev, dev_kind::hdev})
      for (const auto& spec : {tau_spec{}, repeated}) {
        auto two = *deviation(k, x, spec);
        add_confidence(two, k, x, 0.683);
        const auto one = *deviation_with_confidence(k, x, spec, 0.683);
        ASSERT_EQ(one.size(), two.size());
        for (std::size_t i = 0; i < one.size(); ++i) {
          EXPECT_EQ(one[i].m, two[i].m);
          EXPECT_EQ(one[i].dev, two[i].dev);
          EXPECT_EQ(one[i].alpha, two[i].alpha) << "m " << one[i].m << " alpha " << alpha;
          EXPECT_EQ(one[i].edf, two[i].edf) << "m " << one[i].m;
          EXPECT_NEAR(one[i].ci_lo / two[i].ci_lo, 1.0, 1e-14);
          EXPECT_NEAR(one[i].ci_hi / two[i].ci_hi, 1.0, 1e-14);
        }
        // The type is the one simulated where lag-1 has 2^20 points.
        EXPECT_EQ(one.front().alpha, alpha) << to_string(k);
      }
  }
}

// Where the block sums do not apply (angle input, a factor not a power of two, another kind),
// deviation_with_confidence is the two calls.
TEST(Confidence, DeviationWithConfidenceElsewhereIsTheTwoCalls) {
  sensor::normal_stream g(5, sensor::stream::user);
  std::vector<double> y(50'000);
  for (auto& v : y) v = g.next();
  const span_samples samples(y);
  for (const auto in : {input_kind::rate, input_kind::angle}) {
    const auto x = *phase_source::make(samples, in, 0.5);
    for (const auto k : {dev_kind::adev, dev_kind::oadev, dev_kind::hdev, dev_kind::totdev})
      for (const auto& spec : {tau_spec{}, tau_spec{tau_spec::set::list, {3, 10, 100}}}) {
        auto two = *deviation(k, x, spec);
        add_confidence(two, k, x, 0.9, {}, edf_rule::guarded);
        const auto one = *deviation_with_confidence(k, x, spec, 0.9, {}, edf_rule::guarded);
        ASSERT_EQ(one.size(), two.size());
        for (std::size_t i = 0; i < one.size(); ++i) {
          EXPECT_EQ(one[i].alpha, two[i].alpha);
          EXPECT_EQ(one[i].edf, two[i].edf);
          EXPECT_NEAR(one[i].ci_lo / two[i].ci_lo, 1.0, 1e-14);
          EXPECT_NEAR(one[i].ci_hi / two[i].ci_hi, 1.0, 1e-14);
        }
      }
  }
  // Errors as deviation(): too few points.
  const std::vector<double> two_samples{1.0, 2.0};
  const span_samples short_samples(two_samples);
  const auto x = *phase_source::make(short_samples, input_kind::angle, 1.0);
  EXPECT_FALSE(deviation_with_confidence(dev_kind::hdev, x, tau_spec{}, 0.683));
}

}  // namespace
}  // namespace gyroflip::analysis
