// Confidence intervals against Stable32: noise identification (alpha column), Greenhall EDF and
// chi-squared bounds (Min/Max Sigma columns at 68.3 %), plus chi-squared quantiles.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "support/reference_data.hpp"

namespace gyroflip::analysis {
namespace {

const std::string vectors = std::string(GYROFLIP_VECTORS_DIR) + "/stable32/";

// With Stable32's alpha, our bounds must agree to `tol` (Stable32 uses Greenhall's tables and its
// own chi-squared approximation; we evaluate Greenhall's sum directly). Where our lag-1 noise
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
    if (const auto id = noise_alpha_lag1(x, r.af)) {
      EXPECT_EQ(*id, r.alpha) << table << " AF " << r.af;
    }
  }
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

TEST(Confidence, PhaseDatAllKindsMatchStable32) {
  std::ifstream f(vectors + "phasedat/PHASE.DAT");
  const auto x = test::read_values(f);
  for (const char* k : {"adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"})
    check_ci(vectors + "phasedat/phase_dat_" + k + "_octave.txt", *parse_dev_kind(k), x, 3e-3);
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
  // TOTDEV with PM noise: SP1065 gives no TOTVAR EDF; the OADEV EDF we use is within 3 %.
  check_ci(dir + "stable32_TOTDEV_octave.txt", dev_kind::totdev, x, 3e-2);
}

TEST(Confidence, AddConfidenceEndToEndOnPhaseDat) {
  std::ifstream f(vectors + "phasedat/PHASE.DAT");
  const auto x = test::read_values(f);
  auto pts = *deviation(dev_kind::oadev, x, input_kind::angle, 1.0, {});
  add_confidence(pts, dev_kind::oadev, x, 0.683);
  const auto rows = test::read_stable32_table(vectors + "phasedat/phase_dat_oadev_octave.txt");
  ASSERT_EQ(pts.size(), rows.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(pts[i].alpha, rows[i].alpha);
    EXPECT_NEAR(pts[i].ci_lo / rows[i].lo, 1.0, 3e-3) << i;
    EXPECT_NEAR(pts[i].ci_hi / rows[i].hi, 1.0, 3e-3) << i;
    EXPECT_LT(pts[i].ci_lo, pts[i].dev);
    EXPECT_GT(pts[i].ci_hi, pts[i].dev);
  }
  // A wider level gives wider bounds.
  auto wide = pts;
  add_confidence(wide, dev_kind::oadev, x, 0.95);
  EXPECT_LT(wide[3].ci_lo, pts[3].ci_lo);
  EXPECT_GT(wide[3].ci_hi, pts[3].ci_hi);
}

}  // namespace
}  // namespace gyroflip::analysis
