// IEEE 952 noise terms: synthetic series with known N, B, K (fixed seeds), and the real static
// ADIS16405 run in ../shared/reference/gyro (skipped when absent; NonCommercial data, not copied).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/analysis/readoffs.hpp"
#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/sensor/error_terms.hpp"
#include "gyroflip/sensor/random.hpp"
#include "support/synth.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::analysis {
namespace {

std::vector<deviation_point> oadev_with_ci(const std::vector<double>& y, double tau0_s) {
  auto pts = *oadev(y, input_kind::rate, tau0_s);
  // As analyse_noise: the fit's weights come from the guarded EDFs.
  add_confidence(pts, dev_kind::oadev, phase_from_rate(y, tau0_s), 0.683, edf_rule::guarded);
  return pts;
}

noise_terms fit_rate(const std::vector<double>& y, double tau0_s, double level = 0.683) {
  return *fit_noise_terms(oadev_with_ci(y, tau0_s), level);
}

// The truth lies inside the reported interval.
bool within(const noise_term& t, double truth) {
  return t.resolved && t.lo <= truth && truth <= t.hi;
}

// The whole analysis (analyse_noise) of rate samples y at tau0_s.
noise_analysis analyse(const std::vector<double>& y, double tau0_s, bool detect = true) {
  const span_samples src(y);
  const auto x = phase_source::make(src, input_kind::rate, tau0_s);
  EXPECT_TRUE(x);
  tau_range r;
  r.detect_shaping = detect;
  auto a = analyse_noise(*x, 0.683, r);
  EXPECT_TRUE(a) << a.err().message;
  return *a;
}

// Issue 34 item 1: records through the simulator's sensor with an ADIS16405-like anti-alias
// filter (first-order low-pass at 28 Hz, 100 Hz samples: lag-1 correlation 0.17, first-octave
// slope -0.33 where the real ADIS16405 shows -0.31), N = 0.04 deg/s/sqrt(Hz) (2.4 deg/sqrt(h)),
// B = 0.008 deg/s, 2^19 samples, 8 fixed seeds (bench/noise_fit_coverage.cpp runs 200). The
// default fit leaves the filtered short taus out: N within 2 % of the truth in >= 7 of 8 seeds,
// its interval holding the truth in >= 6. With every tau fitted (the fit before issue 34, and
// detect_shaping false) N is 3-4 % low in every seed: >= 7 of 8 beyond 2 %.
TEST(NoiseFit, DefaultFitLeavesTheFilteredShortTausOut) {
  constexpr double n_true = 0.04, b_true = 0.008;
  int within2 = 0, inside = 0, old_beyond2 = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const auto y = test::static_gyro_rates(n_true, b_true, 0.0, 28.0, 0.01, 1u << 19, seed);
    const auto a = analyse(y, 0.01);
    EXPECT_GE(a.shaping.points, 2u) << seed;
    EXPECT_EQ(a.shaping.cause, "filter") << seed;
    EXPECT_FALSE(a.terms.quantization.resolved) << seed;
    within2 += std::abs(a.terms.arw.value / n_true - 1.0) <= 0.02;
    inside += within(a.terms.arw, n_true);
    // The interval holds every reading of the other fit ranges.
    EXPECT_EQ(a.terms.fit_ranges, 5u);
    EXPECT_LE(a.terms.arw.lo, a.terms.arw.range_lo);
    EXPECT_LE(a.terms.arw.range_lo, a.terms.arw.value);
    EXPECT_LE(a.terms.arw.value, a.terms.arw.range_hi);
    EXPECT_LE(a.terms.arw.range_hi, a.terms.arw.hi);
    const auto old = analyse(y, 0.01, false);
    EXPECT_EQ(old.shaping.points, 0u);
    old_beyond2 += old.terms.arw.value < 0.98 * n_true;
  }
  EXPECT_GE(within2, 7);
  EXPECT_GE(inside, 6);
  EXPECT_GE(old_beyond2, 7);
}

// A 20 Hz line at 100 Hz (as on the ADIS16405's Z axis): octave taus fall alternately on its
// bumps (ADEV 0.37, 0.36, 0.19, 0.15 deg/s at 0.01 ... 0.08 s, the ADIS16405 Z's 0.38 at
// 0.02 s), which the fit over every tau cannot describe. The default fit leaves those taus out:
// no Q, N within 2 %.
TEST(NoiseFit, ASpectralLineIsNotReadAsQuantisation) {
  constexpr double n_true = 0.04;
  const auto y = test::static_gyro_rates(n_true, 0.008, 0.0, 28.0, 0.01, 1u << 19, 3, 0.4, 20.0);
  const auto old = analyse(y, 0.01, false);
  // Every tau fitted: N 3 % high, chi2/dof 9 (on the real ADIS16405 Z a Q 10x too large).
  EXPECT_GT(std::abs(old.terms.arw.value / n_true - 1.0), 0.02);
  EXPECT_GT(old.terms.chi2_per_dof, 4.0);
  const auto a = analyse(y, 0.01);
  EXPECT_EQ(a.shaping.cause, "line");
  EXPECT_FALSE(a.terms.quantization.resolved);
  EXPECT_NEAR(a.terms.arw.value / n_true, 1.0, 0.02);
}

// A real quantisation term (white angle noise, ADEV slope -1) bends the curve the convex way:
// nothing is left out and Q is resolved near its truth.
TEST(NoiseFit, RealQuantisationIsKept) {
  constexpr double n_true = 0.005, q_true = 2e-3, dt = 0.01;
  sensor::normal_stream white(5, sensor::stream::user);
  sensor::normal_stream angle(5, static_cast<sensor::stream>(17));
  std::vector<double> y(1u << 18);
  // White angle noise e of std q sqrt(3)... : AVAR 3 sigma_e^2 / tau^2 = 3 Q^2 / tau^2.
  double e_prev = q_true * angle.next();
  for (auto& v : y) {
    const double e = q_true * angle.next();
    v = n_true / std::sqrt(dt) * white.next() + (e - e_prev) / dt;
    e_prev = e;
  }
  const auto a = analyse(y, dt);
  EXPECT_EQ(a.shaping.points, 0u);
  ASSERT_TRUE(a.terms.quantization.resolved);
  EXPECT_NEAR(a.terms.quantization.value / q_true, 1.0, 0.1);
  EXPECT_TRUE(within(a.terms.arw, n_true));
}

// Regression (issue 13 item 14, 2026-11-23): on pure white rate noise (360 000 samples at
// 100 Hz, 40 seeds), 4 seeds read alpha = 1 or 2 at tau = 81.92 s (44 decimated points); the
// EDF jumped from ~64 (white FM at m = 8192) to 805 or 20 000, the interval shrank to +-0.5 %
// (from +-9 %), N came out 8 % low with the truth outside its interval, and a Q that does not
// exist was "resolved". Now:
// - no tau's EDF exceeds what the noise types identified at it and its neighbours give there;
// - N's 1-sigma interval holds the truth for >= 20 of 40 seeds (nominal 27; 20 is 2.6 binomial
//   standard deviations below);
// - Q is resolved in at most 3 seeds (a 2-sigma test of a zero term: 1 expected).
TEST(NoiseFit, WhiteNoiseHasNoIntervalNarrowerThanItsNeighboursAllow) {
  constexpr double n_true = 0.005;  // deg/sqrt(s)
  constexpr double tau0_s = 0.01;
  constexpr int seeds = 40;
  int n_inside = 0;
  int q_resolved = 0;
  for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
    sensor::normal_stream white(seed, sensor::stream::user);
    std::vector<double> y(360000);
    for (auto& v : y) v = n_true / std::sqrt(tau0_s) * white.next();
    const auto pts = oadev_with_ci(y, tau0_s);
    const std::size_t n_phase = y.size() + 1;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      // The EDF is at most what the types at this tau and its two neighbours give.
      double allowed = edf(dev_kind::oadev, pts[i].alpha, pts[i].m, n_phase);
      for (const std::size_t j : {i - 1, i + 1})
        if (j < pts.size())
          allowed = std::min(allowed, edf(dev_kind::oadev, pts[j].alpha, pts[i].m, n_phase));
      EXPECT_LE(pts[i].edf, allowed * (1.0 + 1e-12)) << "seed " << seed << " tau " << pts[i].tau_s;
      // White FM everywhere: the EDF never exceeds the white-FM one by more than its neighbours'
      // types could justify, and never by the old factor of 6 to 150.
      EXPECT_LT(pts[i].edf, 1.5 * edf(dev_kind::oadev, 0, pts[i].m, n_phase))
          << "seed " << seed << " tau " << pts[i].tau_s << " alpha " << pts[i].alpha;
    }
    const auto f = *fit_noise_terms(pts, 0.683);
    n_inside += within(f.arw, n_true);
    q_resolved += f.quantization.resolved;
  }
  EXPECT_GE(n_inside, 20);
  EXPECT_LE(q_resolved, 3);
}

// Issue 4: "noise-id recovers the generating N, B, K within their intervals for >= 90 % of
// seeds". 2^18 samples at 1 Hz (73 h): N = 0.01 deg/sqrt(s), B = 0.001 deg/s
// (sensor::flicker_bank, itself within +-10 % of the ideal floor), K = 4e-5 deg/s/sqrt(s).
// 40 seeds. The 95 % intervals must hold for >= 36 (90 %); the 1-sigma intervals of B and K for
// >= 24 (60 %; nominal 68 %). Measured 2026-11-22: 95 %: N 40, B 40, K 38; 1 sigma: B 29,
// K 30. With the octave points treated as independent (the covariance before the sandwich)
// K fails both: 31 and 17.
TEST(NoiseFit, RecoversWhiteFlickerAndRandomWalkWithinTheirIntervals) {
  constexpr double n_true = 0.01, b_true = 0.001, k_true = 4e-5;
  constexpr int seeds = 40;
  int n95 = 0, b95 = 0, k95 = 0, b68 = 0, k68 = 0;
  for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
    sensor::normal_stream white(seed, sensor::stream::user);
    sensor::normal_stream walk(seed, static_cast<sensor::stream>(17));
    sensor::flicker_bank flicker(b_true, 1.0, 1e5, 1.0,
                                 sensor::normal_stream(seed, static_cast<sensor::stream>(18)));
    std::vector<double> y(std::size_t{1} << 18);
    double w = 0.0;
    for (auto& v : y) {
      w += k_true * walk.next();  // K sqrt(h) with h = 1 s
      v = n_true * white.next() + flicker.step() + w;
    }
    const auto pts = oadev_with_ci(y, 1.0);
    const auto f95 = *fit_noise_terms(pts, 0.95);
    const auto f68 = *fit_noise_terms(pts, 0.683);
    n95 += within(f95.arw, n_true) ? 1 : 0;
    b95 += within(f95.bias_instability, b_true) ? 1 : 0;
    k95 += within(f95.rrw, k_true) ? 1 : 0;
    b68 += within(f68.bias_instability, b_true) ? 1 : 0;
    k68 += within(f68.rrw, k_true) ? 1 : 0;
    // The same fit at both levels; only the width differs.
    EXPECT_EQ(f95.rrw.value, f68.rrw.value);
    EXPECT_LT(f95.rrw.hi - f95.rrw.lo, 2.2 * (f68.rrw.hi - f68.rrw.lo));
    EXPECT_GT(f95.rrw.hi - f95.rrw.lo, 1.5 * (f68.rrw.hi - f68.rrw.lo));
  }
  EXPECT_GE(n95, 36);
  EXPECT_GE(b95, 36);
  EXPECT_GE(k95, 36);
  EXPECT_GE(b68, 24);
  EXPECT_GE(k68, 24);
}

TEST(NoiseFit, LevelOutsideZeroOneIsAnError) {
  sensor::normal_stream white(3, sensor::stream::user);
  std::vector<double> y(4096);
  for (auto& v : y) v = white.next();
  const auto pts = oadev_with_ci(y, 1.0);
  EXPECT_FALSE(fit_noise_terms(pts, 0.0));
  EXPECT_FALSE(fit_noise_terms(pts, 1.0));
  EXPECT_TRUE(fit_noise_terms(pts, 0.5));
}

TEST(NoiseFit, WhiteNoiseAloneLeavesOtherTermsUnresolved) {
  sensor::normal_stream white(7, sensor::stream::user);
  std::vector<double> y(200000);
  for (auto& v : y) v = 0.05 * white.next();
  const auto f = fit_rate(y, 0.01);  // 100 Hz: N = 0.05 * sqrt(0.01) = 0.005 deg/sqrt(s)
  EXPECT_TRUE(within(f.arw, 0.005));
  EXPECT_FALSE(f.rrw.resolved);
  EXPECT_FALSE(f.rate_ramp.resolved);
  EXPECT_GE(f.notes.size(), 2u);
}

// The real ADIS16405 run: OADEV at octave taus equals the published table of the R package
// avar (adis_av, ../shared/reference/gyro/README.md) to 1e-5 relative (avar sums one term
// fewer); noise terms as the issue states them.
TEST(NoiseFit, Adis16405FromSharedIfPresent) {
  const std::string xz =
      std::string(GYROFLIP_SHARED_DIR) + "/reference/gyro/adis16405_imu1_gyro.csv.xz";
  test::temp_dir d;
  const std::string csv = d.file("adis.csv");
  if (std::system(("xz -dc '" + xz + "' > '" + csv + "' 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "../shared/reference/gyro not available";
  const std::vector<std::size_t> m = {2,    4,    8,    16,   32,    64,    128,   256,    512,
                                      1024, 2048, 4096, 8192, 16384, 32768, 65536, 131072, 262144};
  const std::vector<std::vector<double>> published = {
      {2.574697e-01, 1.927781e-01, 1.395352e-01, 1.000429e-01, 7.115400e-02, 5.106695e-02,
       3.611840e-02, 2.588821e-02, 1.830377e-02, 1.320574e-02, 1.001929e-02, 8.274232e-03,
       7.062839e-03, 7.641366e-03, 7.767978e-03, 6.133379e-03, 5.213027e-03, 5.723225e-03},
      {2.718048e-01, 2.031400e-01, 1.467134e-01, 1.050669e-01, 7.510722e-02, 5.339459e-02,
       3.809532e-02, 2.703881e-02, 1.982907e-02, 1.496944e-02, 1.154436e-02, 9.192334e-03,
       8.412387e-03, 8.428860e-03, 9.158808e-03, 1.193476e-02, 1.362211e-02, 2.050517e-02},
      {3.839717e-01, 1.901936e-01, 1.476251e-01, 9.646808e-02, 6.835891e-02, 4.780929e-02,
       3.454447e-02, 2.442928e-02, 1.736121e-02, 1.277977e-02, 9.916377e-03, 8.459067e-03,
       8.091776e-03, 8.715235e-03, 9.252822e-03, 1.329309e-02, 1.846856e-02, 2.081510e-02}};
  const char* axes[] = {"gx_dps", "gy_dps", "gz_dps"};
  for (std::size_t a = 0; a < 3; ++a) {
    SCOPED_TRACE(axes[a]);
    io::series_options so;
    so.column = axes[a];
    const auto s = io::read_series(csv, so);
    ASSERT_TRUE(s) << s.err().message;
    ASSERT_EQ(s->values().size(), 1000000u);
    EXPECT_NEAR(s->tau0_s(), 0.01, 1e-12);
    const auto x = phase_from_rate(s->values(), s->tau0_s());
    for (std::size_t i = 0; i < m.size(); ++i)
      EXPECT_NEAR(deviation_at(dev_kind::oadev, x, 0.01, m[i]).dev / published[a][i], 1.0, 1e-5)
          << m[i];
    const auto f = fit_rate(std::vector<double>(s->values().begin(), s->values().end()), 0.01);
    const double arw_deg_rth = 60.0 * f.arw.value;
    EXPECT_GE(arw_deg_rth, 2.3);
    EXPECT_LE(arw_deg_rth, 2.6);
    EXPECT_NEAR(f.bias_floor_tau_s, 81.92, 1e-9);  // the floor near 80 s
    if (a == 0) {
      EXPECT_FALSE(f.rrw.resolved);  // rate random walk is not resolved on X
    }
    // Issue 34 item 1, the default analysis: X and Y leave the filtered short taus out (the fit
    // over all taus was 5.8 % below ADEV(1 s) on X), Z the 20 Hz line's (read as a Q 10x the
    // real one before). N's interval holds ADEV(1 s) less the other fitted terms there.
    const auto n = analyse(std::vector<double>(s->values().begin(), s->values().end()), 0.01);
    EXPECT_EQ(n.shaping.cause, a == 2 ? "line" : "filter");
    EXPECT_FALSE(n.terms.quantization.resolved);
    EXPECT_NEAR(n.adev_1s_tau_s, 1.0, 1e-12);
    EXPECT_LE(n.terms.arw.lo, n.adev_1s_arw);
    EXPECT_GE(n.terms.arw.hi, n.adev_1s_arw);
    EXPECT_NEAR(n.terms.arw.value / n.adev_1s, 1.0, 0.03);
  }
}

// Read-offs on an exact IEEE 952 curve sigma^2 = N^2/tau + (0.6643 B)^2 + K^2 tau/3 (no flicker
// shape, so B's plateau is the floor only approximately): N from the -1/2 part at tau 1 s, K from
// the +1/2 part at tau 3 s, both within the curvature the other terms add there.
TEST(ReadOffs, AnExactCurveGivesItsTermsBack) {
  const double n = 0.01, b = 1e-3, k = 1e-5;
  std::vector<deviation_point> pts;
  for (double tau = 0.01; tau < 1e7; tau *= 2) {
    deviation_point p;
    p.tau_s = tau;
    p.dev = std::sqrt(n * n / tau + std::pow(0.6643 * b, 2) + k * k * tau / 3.0);
    pts.push_back(p);
  }
  const slope_readoffs r = read_off_terms(pts);
  ASSERT_TRUE(r.arw);
  ASSERT_TRUE(r.rrw);
  EXPECT_NEAR(*r.arw / n, 1.0, 0.02);
  EXPECT_LT(r.arw_from_tau_s, 1.0);  // where the white part dominates
  EXPECT_NEAR(*r.rrw / k, 1.0, 0.02);
  EXPECT_GT(r.rrw_from_tau_s, 1e5);
  EXPECT_TRUE(r.floor_is_minimum);
  // The floor of the sum lies a little above 0.6643 B (the other terms add there).
  EXPECT_GT(r.bias_instability, b);
  EXPECT_LT(r.bias_instability, 1.5 * b);
  // A curve that still falls: no +1/2 slope, the floor is its last point, not a minimum.
  pts.resize(12);
  const slope_readoffs f = read_off_terms(pts);
  EXPECT_FALSE(f.rrw);
  EXPECT_FALSE(f.floor_is_minimum);
  EXPECT_EQ(f.floor_tau_s, pts.back().tau_s);
}

}  // namespace
}  // namespace gyroflip::analysis
