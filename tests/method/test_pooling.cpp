/// \file
/// \brief Pooling runs by random effects (issue 31, method/delta_n_model.hpp): the BCG trials'
/// published DerSimonian-Laird values (tests/vectors/metafor-bcg/PROVENANCE.md), closed forms for
/// equal within-run errors, and Student's t (analysis/confidence.hpp) against its closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/method/delta_n_model.hpp"

namespace gyroflip::method {
namespace {

struct trial {
  double tpos, tneg, cpos, cneg, ablat_deg;
};

// Colditz et al. 1994 as metafor's dat.bcg (PROVENANCE.md).
const trial bcg_trials[] = {
    {4, 119, 11, 128, 44},       {6, 300, 29, 274, 55},        {3, 228, 11, 209, 42},
    {62, 13536, 248, 12619, 52}, {33, 5036, 47, 5761, 13},     {180, 1361, 372, 1079, 44},
    {8, 2537, 10, 619, 19},      {505, 87886, 499, 87892, 13}, {29, 7470, 45, 7232, 27},
    {17, 1699, 65, 1600, 42},    {186, 50448, 141, 27197, 18}, {5, 2493, 3, 2338, 33},
    {27, 16886, 29, 17825, 33}};

// The log risk ratios with their standard errors, latitude as the "temperature".
std::vector<delta_n_point> bcg_points() {
  std::vector<delta_n_point> out;
  for (const auto& t : bcg_trials) {
    const double y = std::log((t.tpos / (t.tpos + t.tneg)) / (t.cpos / (t.cpos + t.cneg)));
    const double v = 1 / t.tpos - 1 / (t.tpos + t.tneg) + 1 / t.cpos - 1 / (t.cpos + t.cneg);
    out.push_back({t.ablat_deg, y, std::sqrt(v)});
  }
  return out;
}

TEST(Pooling, DerSimonianLairdReproducesMetaforOnTheBcgTrials) {
  const auto pts = bcg_points();
  // The fixed-effect fit (the weighted fit of before issue 31) and its Q.
  const auto fe = fit_delta_n_model(pts, 0);
  ASSERT_TRUE(fe);
  EXPECT_NEAR(fe->coeffs_dps[0], -0.4303, 1e-4);
  EXPECT_NEAR(fe->chi2_per_dof * 12.0, 152.2330, 1e-4);
  const auto re = fit_delta_n_random_effects(pts, 0);
  ASSERT_TRUE(re);
  EXPECT_TRUE(re->random_effects);
  EXPECT_EQ(re->dof, 12U);
  EXPECT_NEAR(re->coeffs_dps[0], -0.7141, 1e-4);
  EXPECT_NEAR(re->between_run_var_dps2, 0.3088, 1e-4);
  // Knapp-Hartung's error (metafor's test = "knha"); the z-based one is 0.17874.
  EXPECT_NEAR(re->stderr_at(0.0), 0.18069662833554745, 1e-12);
  EXPECT_NEAR(re->interval_at(0.0), 0.18069662833554745 * analysis::t_one_sigma(12.0), 1e-12);
}

TEST(Pooling, MetaRegressionOnLatitudeAsMetafor) {
  const auto re = fit_delta_n_random_effects(bcg_points(), 1);
  ASSERT_TRUE(re);
  EXPECT_NEAR(re->t_ref_c, 33.46153846153846, 1e-12);
  EXPECT_NEAR(re->between_run_var_dps2, 0.0633, 1e-4);  // as metafor prints it
  EXPECT_NEAR(re->between_run_var_dps2, 0.0633005024264148, 1e-12);
  EXPECT_NEAR(re->coeffs_dps[0], -0.71849485, 1e-8);
  EXPECT_NEAR(re->coeffs_dps[1], -0.02922874, 1e-8);
  ASSERT_EQ(re->cov.size(), 4U);
  EXPECT_NEAR(re->cov[0], 0.014256331205093679, 1e-12);
  EXPECT_NEAR(re->cov[1], 1.463995108036354e-4, 1e-13);
  EXPECT_NEAR(re->cov[3], 6.300796692144152e-5, 1e-14);
  EXPECT_EQ(re->dof, 11U);
}

// Equal within-run errors v: tau^2 = s^2 - v (the runs' sample variance less their own), the mean
// is the plain mean and its error s/sqrt(k), whatever v.
TEST(Pooling, EqualWithinRunErrorsGiveThePlainMeanAndItsStandardError) {
  const std::vector<double> dn = {3.2e-3, 2.0e-3, 3.1e-3, 2.6e-3};
  const double v_se = 1e-4;
  std::vector<delta_n_point> pts;
  for (double x : dn) pts.push_back({20.0, x, v_se});
  const auto re = fit_delta_n_random_effects(pts, 0);
  ASSERT_TRUE(re);
  double mean = 0.0, ss = 0.0;
  for (double x : dn) mean += x / 4.0;
  for (double x : dn) ss += (x - mean) * (x - mean);
  const double s2 = ss / 3.0;
  EXPECT_NEAR(re->coeffs_dps[0], mean, 1e-15);
  EXPECT_NEAR(re->between_run_var_dps2, s2 - v_se * v_se, 1e-18);
  EXPECT_NEAR(re->stderr_at(0.0), std::sqrt(s2 / 4.0), 1e-15);
  // The weighted fit of before scaled its 1/sqrt(sum w) by the Birge ratio: the same here.
  // With unequal errors it is not (the next test).
}

// The case: runs scattering far beyond their own errors, with unequal errors. The
// weighted mean follows the most precise run; random effects give (nearly) the plain mean.
TEST(Pooling, RunsScatteringBeyondTheirErrorsArePooledNearTheirPlainMean) {
  const std::vector<delta_n_point> pts = {
      {20.0, 3.4e-3, 4e-5}, {20.0, 2.0e-3, 1.2e-4}, {20.0, 3.2e-3, 9e-5}};
  const auto fe = fit_delta_n_model(pts, 0);
  const auto re = fit_delta_n_random_effects(pts, 0);
  ASSERT_TRUE(fe && re);
  const double plain = (3.4e-3 + 2.0e-3 + 3.2e-3) / 3.0;
  EXPECT_GT(std::abs(fe->coeffs_dps[0] - plain), 3e-4);  // the weighted mean is pulled to 3.4e-3
  EXPECT_LT(std::abs(re->coeffs_dps[0] - plain), 3e-5);
  EXPECT_GT(std::sqrt(re->between_run_var_dps2), 6e-4);
}

TEST(Pooling, AModelThroughItsRunsHasNoErrorAndNoDegreesOfFreedom) {
  const std::vector<delta_n_point> pts = {{4.0, 3.8e-3, 1e-4}, {20.0, 3.1e-3, 1e-4}};
  const auto re = fit_delta_n_random_effects(pts, 1);
  ASSERT_TRUE(re);
  EXPECT_EQ(re->dof, 0U);
  EXPECT_EQ(re->stderr_at(10.0), 0.0);
  EXPECT_TRUE(std::isnan(re->between_run_var_dps2));
  EXPECT_NEAR(re->eval(4.0), 3.8e-3, 1e-15);
}

// A new run's prediction interval, closed form: with no within-run errors (at rounding level)
// the fit is ordinary least squares and the interval the textbook one, t s sqrt(1 + 1/n + (x0 -
// xbar)^2 / Sxx) (NIST/SEMATECH e-Handbook 4.5.2.2 for the form; t at 68.3 %). Points (0, 0),
// (1, 1), (2, 3): slope 1.5, residuals 1/6, -1/3, 1/6, s^2 = 1/6 on 1 degree of freedom.
TEST(Pooling, ANewRunsIntervalIsTheLeastSquaresPredictionIntervalWithoutWithinRunErrors) {
  const std::vector<delta_n_point> pts = {{0.0, 0.0, 0.0}, {1.0, 1.0, 0.0}, {2.0, 3.0, 0.0}};
  const auto re = fit_delta_n_random_effects(pts, 1);
  ASSERT_TRUE(re);
  const double t = analysis::t_one_sigma(1.0);
  EXPECT_NEAR(re->new_run_interval_at(1.0), t * std::sqrt(1.0 / 6.0 * (1.0 + 1.0 / 3.0)), 1e-12);
  EXPECT_NEAR(re->new_run_interval_at(3.0), t * std::sqrt(1.0 / 6.0 * (1.0 + 1.0 / 3.0 + 2.0)),
              1e-12);
  EXPECT_NEAR(re->interval_at(3.0), t * std::sqrt(1.0 / 6.0 * (1.0 / 3.0 + 2.0)), 1e-12);
  // Without degrees of freedom there is nothing to predict from.
  const std::vector<delta_n_point> two = {{4.0, 3.8e-3, 1e-4}, {20.0, 3.1e-3, 1e-4}};
  EXPECT_TRUE(std::isnan(fit_delta_n_random_effects(two, 1)->new_run_interval_at(10.0)));
}

// Two runs that happen to agree (fourth review of issue 31, F1: `simulate --sensor tiny.toml`,
// an HZ1 without turn-on spreads, seeds 53 and 56, 300 s at 20 degC; true dN 0.0030900 deg/s):
// both 0.6 of their own errors above the truth, 16 microdeg/s apart. The untruncated
// Knapp-Hartung scale q = 0.00095 gave +-0.000015, 14 times off; the modified scale max(1, q)
// (Roever, Knapp & Friede 2015) keeps the error at least the fixed-effect one and the interval
// holds the truth.
TEST(Pooling, TwoRunsThatHappenToAgreeKeepAtLeastTheirFixedEffectError) {
  const std::vector<delta_n_point> pts = {{20.0, 0.003314632416795297, 0.0003900179764453308},
                                          {20.0, 0.003298497077031608, 0.0003495508174219319}};
  const auto re = fit_delta_n_random_effects(pts, 0);
  ASSERT_TRUE(re);
  double sum_w = 0.0;
  for (const auto& p : pts) sum_w += 1.0 / (p.stderr_dps * p.stderr_dps);
  const double fixed_effect = 1.0 / std::sqrt(sum_w);
  EXPECT_GE(re->stderr_at(20.0), fixed_effect * (1.0 - 1e-12));
  EXPECT_LE(std::abs(re->eval(20.0) - 0.0030900), re->interval_at(20.0));
  // A new run (its own noise and the between-run change) is never predicted closer than the
  // runs' own noise either.
  EXPECT_GE(re->new_run_interval_at(20.0),
            std::sqrt(std::pow(fixed_effect, 2) + 0.0003495508 * 0.0003495508));
  // Fixed seed, 2 runs, no between-run change (tau = 0), unequal errors: the error is never
  // below the fixed-effect error (before: in about half the campaigns), and the 68.3 % interval
  // holds the truth at least that often (measured 0.94, conservative: the modified scale with
  // Student's t for 1 degree of freedom; before 0.68 with intervals 14 times too short).
  std::mt19937_64 rng(53);
  std::normal_distribution<double> z;
  std::uniform_real_distribution<double> u01;
  int below = 0, held = 0;
  const int campaigns = 2000;
  for (int c = 0; c < campaigns; ++c) {
    std::vector<delta_n_point> two;
    double w = 0.0;
    for (int i = 0; i < 2; ++i) {
      const double se = 0.5 + u01(rng);
      two.push_back({20.0, se * z(rng), se});
      w += 1.0 / (se * se);
    }
    const auto m = fit_delta_n_random_effects(two, 0);
    ASSERT_TRUE(m);
    below += m->stderr_at(20.0) < (1.0 - 1e-12) / std::sqrt(w);
    held += std::abs(m->eval(20.0)) <= m->interval_at(20.0);
  }
  EXPECT_EQ(below, 0);
  EXPECT_GE(held / static_cast<double>(campaigns), 0.683);
}

// Simulated runs with known truth (dN_i = line + u_i + e_i, u_i ~ N(0, tau^2), e_i ~ N(0, se_i^2),
// se_i uniform in 0.5-1.5 units; fixed seed): a new run, drawn the same way at a random
// temperature, falls in its 68.3 % prediction interval at that rate, where the line's own
// interval (which holds the line) holds far fewer new runs once the runs scatter. Tolerance:
// 1500 campaigns give a binomial std of 0.012; +-0.04 is 3.3 of it. Measured over 4000
// campaigns per cell, 2-13 runs, tau 0-10 units: 0.669-0.703 (docs/METHOD-NOTES.md).
TEST(Pooling, ANewRunFallsInItsPredictionIntervalAtItsRate) {
  std::mt19937_64 rng(31);
  std::normal_distribution<double> z;
  std::uniform_real_distribution<double> u01;
  struct cell {
    std::size_t degree, runs;
    double tau;
  };
  for (const auto& c : {cell{0, 3, 0.0}, cell{1, 5, 3.0}, cell{0, 13, 1.0}, cell{1, 4, 10.0}}) {
    const auto truth = [&](double t_c) { return 3.0 - 0.2 * (t_c - 20.0); };
    const auto run_at = [&](double t_c) -> delta_n_point {
      const double se = 0.5 + u01(rng);
      return {t_c, truth(t_c) + c.tau * z(rng) + se * z(rng), se};
    };
    int n = 0, in_pred = 0, in_line = 0, line_in_line = 0;
    for (int k = 0; k < 1500; ++k) {
      std::vector<delta_n_point> pts;
      for (std::size_t i = 0; i < c.runs; ++i)  // a constant: runs at one temperature
        pts.push_back(run_at(c.degree == 0 ? 20.0
                                           : 15.0 + 10.0 * static_cast<double>(i) /
                                                        static_cast<double>(c.runs - 1)));
      const auto m = fit_delta_n_random_effects(pts, c.degree);
      ASSERT_TRUE(m);
      const double t_c = c.degree == 0 ? 20.0 : 15.0 + 10.0 * u01(rng);
      const auto fresh = run_at(t_c);
      const double miss = std::abs(fresh.delta_n_dps - m->eval(t_c));
      ++n;
      in_pred += miss <= m->new_run_interval_at(t_c);
      in_line += miss <= m->interval_at(t_c);
      line_in_line += std::abs(truth(t_c) - m->eval(t_c)) <= m->interval_at(t_c);
    }
    const double pred = in_pred / static_cast<double>(n);
    const double line = line_in_line / static_cast<double>(n);
    // The modified Knapp-Hartung scale max(1, q) (fourth review of issue 31, F1) is conservative
    // where the runs barely scatter beyond their own errors (Jackson et al. 2017): with tau 0
    // this seed gives 0.85 for 3 runs; where they scatter it holds 68 %.
    const double upper = c.tau >= 3.0 ? 0.683 + 0.04 : 0.90;
    EXPECT_GE(pred, 0.683 - 0.04) << c.degree << " " << c.runs << " " << c.tau;
    EXPECT_LE(pred, upper) << c.degree << " " << c.runs << " " << c.tau;
    EXPECT_GE(line, 0.683 - 0.04) << c.degree << " " << c.runs << " " << c.tau;
    EXPECT_LE(line, upper) << c.degree << " " << c.runs << " " << c.tau;
    std::printf("cell degree %zu runs %zu tau %g: new run %.3f, line %.3f\n", c.degree, c.runs,
                c.tau, pred, line);
    if (c.tau >= 3.0) {
      EXPECT_LT(in_line / static_cast<double>(n), 0.5) << c.runs << " " << c.tau;
    }
  }
}

// A run-to-run spread that grows away from the middle (issue 31 review, H3): each power-up has
// its own line, u_i = a_i + b_i (T - 20), a ~ N(0, 0.000959^2), b ~ N(0, (8.75e-5 /degC)^2) (the
// hz1-90-100a preset's turn-on spread of the g-term and its temperature coefficient), runs of
// within-run error 4.9e-5-9.1e-5 at 4, 12, 20, 28 and 36 degC. A new power-up's run at the ends
// and in the middle falls in its 68 % prediction interval 63-73 % of the time (this seed, 3000
// campaigns: 0.640, 0.729, 0.636). Also the same layout with a constant spread (b = 0), where a
// curvature estimate of 0 or below is common: 0.63-0.73 too (this seed 0.716, 0.658, 0.720).
// Before the fifth review (F14: moment estimates untruncated, 1500 campaigns) 0.647, 0.704,
// 0.662 and 0.635, 0.706, 0.632, with the band below the line's own error wherever the
// curvature came out negative; with 1500 campaigns the truncated estimate with its preliminary
// test gives 0.637, 0.735, 0.641 (the middle 0.4 binomial std over): 3000 campaigns, binomial
// std 0.0085, 0.5 s. Many-seed figures: bench/pooling_temperature_coverage (the simulator) and
// bench/pooling_spread_estimators.py (this layout), docs/PERFORMANCE.md.
TEST(Pooling, ANewRunFallsInItsPredictionIntervalAtEveryTemperatureWhenTheSpreadGrowsWithIt) {
  std::mt19937_64 rng(3131);
  std::normal_distribution<double> z;
  std::uniform_real_distribution<double> u01;
  const auto mean_line = [](double t_c) { return 3.09e-3 + 4.5e-5 * (t_c - 20.0); };
  for (const double slope_sigma : {8.75e-5, 0.0}) {
    const auto run_at = [&](double t_c) -> delta_n_point {
      const double se = 7e-5 * (0.7 + 0.6 * u01(rng));
      const double a = 0.000959 * z(rng), b = slope_sigma * z(rng);
      return {t_c, mean_line(t_c) + a + b * (t_c - 20.0) + se * z(rng), se};
    };
    const double tests_c[] = {4.0, 20.0, 36.0};
    int hits[3] = {0, 0, 0};
    const int campaigns = 3000;
    for (int c = 0; c < campaigns; ++c) {
      std::vector<delta_n_point> pts;
      for (const double t_c : {4.0, 12.0, 20.0, 28.0, 36.0}) pts.push_back(run_at(t_c));
      const auto m = fit_delta_n_random_effects(pts, 1);
      ASSERT_TRUE(m);
      for (int j = 0; j < 3; ++j) {
        const auto fresh = run_at(tests_c[j]);
        hits[j] +=
            std::abs(fresh.delta_n_dps - m->eval(tests_c[j])) <= m->new_run_interval_at(tests_c[j]);
      }
    }
    std::printf("slope spread %g: %.3f / %.3f / %.3f at 4 / 20 / 36 degC\n", slope_sigma,
                hits[0] / static_cast<double>(campaigns), hits[1] / static_cast<double>(campaigns),
                hits[2] / static_cast<double>(campaigns));
    for (int j = 0; j < 3; ++j) {
      const double rate = hits[j] / static_cast<double>(campaigns);
      EXPECT_GE(rate, 0.63) << "at " << tests_c[j] << " degC, slope spread " << slope_sigma;
      EXPECT_LE(rate, 0.73) << "at " << tests_c[j] << " degC, slope spread " << slope_sigma;
    }
  }
}

// Fifth review of issue 31, F14: the moment estimates of tau^2(T) = t0 + t1 (T - T_ref)^2 were
// not truncated, and where one came out negative the band pinched below the line's own error.
// Two fixed sets of 5 runs (errors 2e-5 deg/s, scatter ~2e-4): in the first the moment estimate
// of t1 is negative (-3.0e-9; main drew +-0.000046 at 4 and 36 degC, where the line's own
// interval is +-0.00037); in the second t0 is negative (-5.3e-8, t1 2.4e-9 at 0.94 of its error;
// main drew +-0.000040 at 20 degC against the line's +-0.00023). Now both estimates are
// non-negative (or tau^2(T) not used) and the band is never below the line's interval, inside
// the span or out of it.
TEST(Pooling, ANewRunsBandIsNeverBelowTheLinesOwnErrorWhenTheSpreadEstimateIsNegative) {
  const std::vector<double> temps{4.0, 12.0, 20.0, 28.0, 36.0};
  for (const auto& dn : {std::vector{3.0e-3, 3.4e-3, 2.6e-3, 3.5e-3, 3.2e-3},
                         std::vector{3.8e-3, 3.3e-3, 3.1e-3, 2.2e-3, 2.9e-3}}) {
    std::vector<delta_n_point> runs;
    for (std::size_t i = 0; i < temps.size(); ++i) runs.push_back({temps[i], dn[i], 2e-5});
    const auto m = fit_delta_n_random_effects(runs, 1);
    ASSERT_TRUE(m);
    ASSERT_GE(m->between_run_var_dps2, 5.0 * 4e-10);  // past the gate: tau^2(T) was estimated
    if (std::isfinite(m->tau2_centre_dps2)) {
      EXPECT_GE(m->tau2_centre_dps2, 0.0) << dn[0];
      EXPECT_GE(m->tau2_curvature_dps2_per_c2, 0.0) << dn[0];
    }
    for (double t_c = -20.0; t_c <= 60.0; t_c += 1.0)
      EXPECT_GE(m->new_run_interval_at(t_c), m->interval_at(t_c)) << dn[0] << " at " << t_c;
  }
  // The second: t1 resolved (0.94 of its error), t0 truncated to 0 and t1 refitted alone.
  std::vector<delta_n_point> second;
  for (std::size_t i = 0; i < temps.size(); ++i)
    second.push_back({temps[i], std::vector{3.8e-3, 3.3e-3, 3.1e-3, 2.2e-3, 2.9e-3}[i], 2e-5});
  const auto m2 = fit_delta_n_random_effects(second, 1);
  ASSERT_TRUE(m2);
  EXPECT_EQ(m2->tau2_centre_dps2, 0.0);
  EXPECT_GT(m2->tau2_curvature_dps2_per_c2, 0.0);
}

// Too few runs to tell a spread that changes with temperature: the constant-tau^2 interval.
TEST(Pooling, FewRunsKeepAConstantBetweenRunVariance) {
  const std::vector<delta_n_point> four = {
      {4.0, 3.8e-3, 1e-4}, {12.0, 3.3e-3, 1e-4}, {20.0, 3.1e-3, 1e-4}, {28.0, 2.2e-3, 1e-4}};
  const auto m4 = fit_delta_n_random_effects(four, 1);
  ASSERT_TRUE(m4);
  EXPECT_TRUE(std::isnan(m4->tau2_centre_dps2));
  const double t = analysis::t_one_sigma(2.0);
  EXPECT_NEAR(m4->new_run_interval_at(30.0),
              t * std::sqrt(std::pow(m4->stderr_at(30.0), 2) + m4->new_run_var_dps2), 1e-15);
  // Five runs scattering about twice their errors: the scatter is too close to their own noise.
  auto five = four;
  five.push_back({36.0, 2.9e-3, 1e-4});
  for (auto& p : five) p.stderr_dps = 3e-4;
  const auto m5 = fit_delta_n_random_effects(five, 1);
  ASSERT_TRUE(m5);
  EXPECT_LT(m5->between_run_var_dps2, 5.0 * 9e-8);
  EXPECT_TRUE(std::isnan(m5->tau2_centre_dps2));
  // The same runs 5 times more precise: tau^2(T) is estimated and the band drawn from it.
  for (auto& p : five) p.stderr_dps = 2e-5;
  const auto m5p = fit_delta_n_random_effects(five, 1);
  ASSERT_TRUE(m5p);
  EXPECT_TRUE(std::isfinite(m5p->tau2_centre_dps2));
  EXPECT_TRUE(std::isfinite(m5p->new_run_interval_at(36.0)));
  EXPECT_GT(m5p->new_run_interval_at(36.0), 0.0);
}

// Student's t against its closed forms: nu = 1 is Cauchy, t = tan(pi (p - 1/2)); nu = 2 has
// t = (2p - 1)/sqrt(2 p (1 - p)); and the printed tables (NIST/SEMATECH e-Handbook 1.3.6.7.2).
TEST(StudentT, QuantilesMatchClosedFormsAndTables) {
  for (double p : {0.6, 0.8413447460685429, 0.975, 0.999}) {
    EXPECT_NEAR(analysis::student_t_quantile(p, 1.0), std::tan(std::numbers::pi * (p - 0.5)),
                1e-9 * std::tan(std::numbers::pi * (p - 0.5)));
    EXPECT_NEAR(analysis::student_t_quantile(p, 2.0), (2 * p - 1) / std::sqrt(2 * p * (1 - p)),
                1e-10);
  }
  EXPECT_NEAR(analysis::student_t_quantile(0.975, 10.0), 2.228, 1e-3);
  EXPECT_NEAR(analysis::student_t_quantile(0.975, 30.0), 2.042, 1e-3);
  EXPECT_NEAR(analysis::student_t_quantile(0.95, 5.0), 2.015, 1e-3);
  EXPECT_NEAR(analysis::student_t_quantile(0.025, 4.0), -2.776, 1e-3);
  EXPECT_NEAR(analysis::t_one_sigma(1.0), 1.8373, 1e-4);
  EXPECT_NEAR(analysis::t_one_sigma(2.0), 1.3213, 1e-4);
  EXPECT_NEAR(analysis::t_one_sigma(1e6), 1.0, 1e-5);
  EXPECT_EQ(analysis::t_one_sigma(0.0), 1.0);
}

}  // namespace
}  // namespace gyroflip::method
