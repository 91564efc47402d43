// The flip-period planner (method/plan.hpp) against closed forms, a brute-force quadratic form
// and Monte Carlo runs of exactly simulated white and random-walk rate noise.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gyroflip/method/plan.hpp"

namespace gm = gyroflip::method;

namespace {

constexpr double ln2 = std::numbers::ln2;
constexpr double pi = std::numbers::pi;

// The IEEE 952 AVAR model (FACTS §7) that the noise fit uses: the gap variance at no gap.
double ieee_avar(const gm::plan_noise& n, double tau) {
  return 3 * n.quantization_deg * n.quantization_deg / (tau * tau) +
         n.arw_dps_rthz * n.arw_dps_rthz / tau +
         2 * ln2 / pi * n.bias_instability_dps * n.bias_instability_dps +
         n.rrw_dps_per_rts * n.rrw_dps_per_rts * tau / 3;
}

// Flicker's gap variance over B^2/(2 pi), in long double straight from the formula.
long double flicker_direct(long double r) {
  const long double rm = r - 1;
  return (r + 1) * (r + 1) * std::log(r + 1) + (rm > 0 ? rm * rm * std::log(rm) : 0) -
         2 * r * r * std::log(r);
}

}  // namespace

TEST(Plan, GapVarianceWithoutAGapIsTheIeeeAllanModel) {
  const gm::plan_noise n{0.001, 0.0354, 0.02, 1e-4};
  for (const double tau : {0.01, 0.5, 3.0, 100.0, 5000.0})
    EXPECT_NEAR(gm::gap_avar(n, tau, tau) / ieee_avar(n, tau), 1.0, 1e-12) << tau;
}

TEST(Plan, GapVarianceOfEachTermAtAGap) {
  // White FM does not see the gap, white PM loses the adjacent dwells' shared sample (2/3),
  // random-walk FM grows as (3T - tau)/6 (Barnes 1971's B2 for mu = 1), flicker as the formula.
  const double tau = 2.0, T = 7.0;
  EXPECT_DOUBLE_EQ(gm::gap_avar({0, 0.03, 0, 0}, tau, T), 0.03 * 0.03 / tau);
  EXPECT_DOUBLE_EQ(gm::gap_avar({0.01, 0, 0, 0}, tau, T), 2 * 0.01 * 0.01 / (tau * tau));
  EXPECT_NEAR(gm::gap_avar({0, 0, 0, 1e-3}, tau, T), 1e-6 * (3 * T - tau) / 6, 1e-18);
  for (const double r : {1.0, 1.5, 3.5, 19.99, 20.0, 20.01, 57.0, 1e3, 1e4}) {
    const double want = static_cast<double>(0.04L * 0.04L / (2 * pi) * flicker_direct(r));
    EXPECT_NEAR(gm::gap_avar({0, 0, 0.04, 0}, 1.0, r) / want, 1.0, 1e-9) << r;
  }
  // The flicker gap variance grows like ln r: (B^2/2pi)(2 ln r + 3) far from the dwell.
  EXPECT_NEAR(gm::gap_avar({0, 0, 1.0, 0}, 1.0, 1e8) / ((2 * std::log(1e8) + 3) / (2 * pi)), 1.0,
              1e-12);
}

TEST(Plan, WhiteNoiseGivesTheDeadTimeFactor) {
  // N^2 (tau + d) / (tau T) for a run of whole pairs: the dead time only costs data.
  const gm::plan_noise n{0, 0.005, 0, 0};
  const double tau = 1.5, d = 0.4, pairs = 500;
  const double T = pairs * 2 * (tau + d);
  EXPECT_NEAR(gm::flip_mean_variance(n, tau, d, 500) /
                  (n.arw_dps_rthz * n.arw_dps_rthz * (tau + d) / (tau * T)),
              1.0, 1e-12);
  EXPECT_EQ(gm::pairs_in(T, tau, d), 500u);
  EXPECT_EQ(gm::pairs_in(T - 1e-6, tau, d), 499u);
}

TEST(Plan, RunVarianceIsTheQuadraticFormOfTheDwellDifferences) {
  // Brute force: Var(sum w_j y_j) = -1/2 sum_j sum_k w_j w_k D(|j-k|), D(L) = 2 gap_avar(tau, L S),
  // w = +-1/(2M) alternating, over 2M dwells. 2600 pairs: past the planner's exact lags (2048),
  // so its asymptotic tail is checked too.
  const gm::plan_noise n{2e-4, 0.0354, 0.02, 1e-4};
  const double tau = 0.7, d = 0.45, S = tau + d;
  for (const std::size_t pairs : {std::size_t{1}, std::size_t{7}, std::size_t{2600}}) {
    const std::size_t dwells = 2 * pairs;
    std::vector<long double> D(dwells);
    for (std::size_t L = 1; L < dwells; ++L)
      D[L] = 2.0L * gm::gap_avar(n, tau, static_cast<double>(L) * S);
    long double v = 0;
    const long double w2 = 1.0L / (4.0L * static_cast<long double>(pairs * pairs));
    for (std::size_t L = 1; L < dwells; ++L)  // lag L occurs (dwells - L) times, twice over j<k
      v -= (L % 2 ? -1.0L : 1.0L) * w2 * static_cast<long double>(dwells - L) * D[L];
    EXPECT_NEAR(gm::flip_mean_variance(n, tau, d, pairs) / static_cast<double>(v), 1.0, 2e-7)
        << pairs;
  }
}

TEST(Plan, ASampledWhiteAndRandomWalkRunHasTheVariance) {
  // Independent route: rate noise sampled every dt, white N/sqrt(dt) plus a bias random walk with
  // steps K sqrt(dt); dwells are sample means and the run's rate the mean of (A - B)/2. The
  // estimate is linear in the unit normals, so its variance is the sum of their squared
  // coefficients: each white deviate's own, and each walk step's K sqrt(dt) times the weight of
  // every later sample. Sampling differs from the continuous forms by O(dt/tau) (0.5 % here).
  const double dt = 0.005, N = 0.01, K = 2e-3;
  const std::size_t tau_n = 200, dead_n = 80, pairs = 40;  // tau 1 s, d 0.4 s
  std::vector<double> weight;  // per sample: the estimate's weight of its bias
  double white = 0;
  for (std::size_t p = 0; p < 2 * pairs; ++p)
    for (std::size_t i = 0; i < tau_n + dead_n; ++i) {
      const double w = i < dead_n ? 0.0 : (p % 2 ? -0.5 : 0.5) / static_cast<double>(tau_n * pairs);
      weight.push_back(w);
      white += w * w * N * N / dt;
    }
  double walk = 0, later = 0;
  for (std::size_t i = weight.size(); i-- > 0;) {
    later += weight[i];
    walk += later * later * K * K * dt;
  }
  const double want = gm::flip_mean_variance({0, N, 0, K}, 1.0, 0.4, pairs);
  EXPECT_NEAR((white + walk) / want, 1.0, 0.01);
  // and the white part alone exactly
  EXPECT_NEAR(white / gm::flip_mean_variance({0, N, 0, 0}, 1.0, 0.4, pairs), 1.0, 1e-12);
}

TEST(Plan, OptimumAgreesWithTheWhiteFlickerClosedFormForShortDeadTimes) {
  // adxrs150's N and B: tau_c = N^2 / (0.4413 B^2) = 7.08 s. With d << tau_c the exact optimum
  // approaches sqrt(d tau_c) and sigma* (N + 0.664 B sqrt d)/sqrt T.
  const gm::plan_noise n{0, 0.0353553, 0.02, 0};
  const auto p = gm::plan_flip(n, 0.02, 3600);
  ASSERT_TRUE(p) << p.err().message;
  EXPECT_NEAR(p->closed_form.corner_tau_s, 7.0818, 1e-3);
  // The exact optimum lies 20-35 % beyond sqrt(d tau_c): successive pairs' flicker errors are
  // anti-correlated and the flicker gap variance grows with the gap, both of which the closed
  // form leaves out. The minimum is flat: at the closed form's dwell sigma is within 1 %.
  EXPECT_GT(p->dwell_s / p->closed_form.dwell_s, 1.1);
  EXPECT_LT(p->dwell_s / p->closed_form.dwell_s, 1.4);
  EXPECT_NEAR(p->sigma_dps / p->closed_form.sigma_dps, 1.0, 0.03);
  const double tau_cf = p->closed_form.dwell_s;
  EXPECT_NEAR(std::sqrt(gm::flip_mean_variance(n, tau_cf, 0.02, gm::pairs_in(3600, tau_cf, 0.02))) /
                  p->sigma_dps,
              1.0, 0.01);
  EXPECT_NEAR(p->period_s, 2 * (p->dwell_s + 0.02), 1e-12);
  // The scan's minimum is a minimum: the curve is higher a little to either side.
  for (const double f : {0.8, 1.25})
    EXPECT_GT(std::sqrt(gm::flip_mean_variance(n, p->dwell_s * f, 0.02,
                                               gm::pairs_in(3600, p->dwell_s * f, 0.02))),
              p->sigma_dps);
}

TEST(Plan, LongerDeadTimeLengthensTheDwellAndCostsError) {
  const gm::plan_noise n{0, 0.0046, 0.004, 2e-5};
  double last_tau = 0, last_sigma = 0;
  for (const double d : {0.1, 0.4, 2.0}) {
    const auto p = gm::plan_flip(n, d, 4 * 3600.0);
    ASSERT_TRUE(p);
    EXPECT_GT(p->dwell_s, last_tau);
    EXPECT_GT(p->sigma_dps, last_sigma);
    EXPECT_GT(p->sigma_dps, p->sigma_no_dead_dps);
    last_tau = p->dwell_s, last_sigma = p->sigma_dps;
  }
}

TEST(Plan, RefusesWhatItCannotPlan) {
  EXPECT_FALSE(gm::plan_flip({}, 0.4, 3600));
  EXPECT_FALSE(gm::plan_flip({0, -1, 0, 0}, 0.4, 3600));
  EXPECT_FALSE(gm::plan_flip({0, 0.01, 0, 0}, -0.1, 3600));
  EXPECT_FALSE(gm::plan_flip({0, 0.01, 0, 0}, 0.4, 1.0));
  EXPECT_FALSE(gm::plan_flip({0, 0.01, 0, 0}, NAN, 3600));
}

// Indexed runs (three or more positions, issue 33): the first harmonic's error.

TEST(PlanIndexed, ThePeriodsWeightsGiveTheHarmonicsOfAnyBiasLine) {
  // Noise-free dwells b + b' t + c cos + s sin: the weights return c and s exactly, for the sweep
  // of 4 and of 5 unequally spaced positions.
  for (const auto& angles :
       {std::vector<double>{0, 90, 180, 270}, std::vector<double>{0, 60, 135, 200, 300}}) {
    const auto visits = gm::sweep_visits(angles);
    const auto p = gm::indexed_period_of(visits, 0.7, 0.3);
    ASSERT_TRUE(p) << p.err().message;
    double c = 0, s = 0;
    for (std::size_t k = 0; k < visits.size(); ++k) {
      const double a = visits[k] * pi / 180, t = p->start_s[k] + 0.35;
      const double y = 0.3 - 0.02 * t + 1e-3 * std::cos(a) - 2e-3 * std::sin(a);
      c += p->weight_c[k] * y;
      s += p->weight_s[k] * y;
    }
    EXPECT_NEAR(c, 1e-3, 1e-15);
    EXPECT_NEAR(s, -2e-3, 1e-15);
  }
  // 4-position sweep: 6 turns per 8 dwells; its period.
  const auto p =
      gm::indexed_period_of(gm::sweep_visits(std::vector<double>{0, 90, 180, 270}), 1.0, 0.25);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(p->period_s, 8 * 1.0 + 6 * 0.25);
  EXPECT_FALSE(gm::indexed_period_of(std::vector<double>{0, 180, 180, 0}, 1.0, 0.2));
}

TEST(PlanIndexed, WhiteNoiseGivesTwiceNSquaredOverTheTimeAtPositions) {
  // c1 = sum cos_k mean_k / 4 per period of the 4-position sweep: Var = N^2 / (4 tau n), i.e.
  // 2 N^2 / T_dwelling (docs/NORTH.md's k = sqrt 2).
  const gm::plan_noise n{0, 0.01, 0, 0};
  const auto p =
      gm::indexed_period_of(gm::sweep_visits(std::vector<double>{0, 90, 180, 270}), 0.8, 0.3);
  ASSERT_TRUE(p);
  for (const std::size_t periods : {std::size_t{3}, std::size_t{40}, std::size_t{500}}) {
    const auto v = gm::indexed_run_variance(n, *p, periods);
    const double want = 0.01 * 0.01 / (4 * 0.8 * static_cast<double>(periods));
    EXPECT_NEAR(v.var_c1 / want, 1.0, 1e-12);
    EXPECT_NEAR(v.var_s1 / want, 1.0, 1e-12);
    EXPECT_NEAR(v.cov / want, 0.0, 1e-12);
  }
}

TEST(PlanIndexed, RunVarianceIsTheQuadraticFormOverEveryDwell) {
  // Brute force over all dwells of the run, -1/2 sum_jk w_j w_k D(|t_j - t_k|), D = 2 gap_avar:
  // independent of the lag grouping and of the lag^-2 continuation past 64 periods (300 here).
  const gm::plan_noise n{2e-4, 0.0354, 0.02, 1e-4};
  const auto p =
      gm::indexed_period_of(gm::sweep_visits(std::vector<double>{0, 72, 144, 216, 288}), 0.6, 0.35);
  ASSERT_TRUE(p);
  for (const std::size_t periods : {std::size_t{3}, std::size_t{20}, std::size_t{300}}) {
    std::vector<double> t, wc, ws;
    for (std::size_t b = 0; b < periods; ++b)
      for (std::size_t k = 0; k < p->start_s.size(); ++k) {
        t.push_back(static_cast<double>(b) * p->period_s + p->start_s[k]);
        wc.push_back(p->weight_c[k] / static_cast<double>(periods));
        ws.push_back(p->weight_s[k] / static_cast<double>(periods));
      }
    long double vc = 0, vs = 0, cv = 0;
    for (std::size_t j = 0; j < t.size(); ++j)
      for (std::size_t k = 0; k < t.size(); ++k) {
        if (j == k) continue;
        const long double d = gm::gap_avar(n, 0.6, std::abs(t[j] - t[k]));  // 1/2 D
        vc -= wc[j] * wc[k] * d, vs -= ws[j] * ws[k] * d, cv -= wc[j] * ws[k] * d;
      }
    const auto v = gm::indexed_run_variance(n, *p, periods);
    const double tol = periods > 64 ? 1e-4 : 1e-9;
    EXPECT_NEAR(v.var_c1 / static_cast<double>(vc), 1.0, tol) << periods;
    EXPECT_NEAR(v.var_s1 / static_cast<double>(vs), 1.0, tol) << periods;
    EXPECT_NEAR(v.cov, static_cast<double>(cv), tol * static_cast<double>(vc)) << periods;
  }
}

TEST(PlanIndexed, ThePlanIsTheCurvesMinimumAndLongerDeadTimesLengthenIt) {
  const gm::plan_noise n{0, 0.0354, 0.02, 1e-4};
  const auto visits = gm::sweep_visits(std::vector<double>{0, 90, 180, 270});
  double last_tau = 0;
  for (const double d : {0.1, 0.4, 2.0}) {
    const auto p = gm::plan_indexed(n, visits, d, 3600);
    ASSERT_TRUE(p) << p.err().message;
    EXPECT_GT(p->dwell_s, last_tau);
    last_tau = p->dwell_s;
    for (const auto& q : p->by_dwell) EXPECT_GE(q.sigma_dps, p->sigma_dps * (1 - 1e-12));
    for (const double f : {0.8, 1.25}) {
      const auto q = gm::indexed_period_of(visits, p->dwell_s * f, d);
      const auto periods = static_cast<std::size_t>(3600 / q->period_s);
      EXPECT_GT(std::sqrt(gm::indexed_run_variance(n, *q, periods).mean_var()), p->sigma_dps);
    }
    EXPECT_NEAR(p->period_s, 8 * p->dwell_s + 6 * d, 1e-9);
  }
  EXPECT_FALSE(gm::plan_indexed(n, std::vector<double>{0, 180, 180, 0}, 0.2, 3600));
  EXPECT_FALSE(gm::plan_indexed(n, visits, 0.2, 3));  // not three periods (1.28 s each)
}
