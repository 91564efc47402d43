// The sign-reversal method against closed forms (paper eqns 6-12, FACTS §1 and METHOD-NOTES.md).
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/sensor/random.hpp"

#include "gyroflip/analysis/noise_fit.hpp"

#include "gyroflip/analysis/confidence.hpp"

#include "gyroflip/analysis/allan.hpp"

#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/compensation.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/method/dwells.hpp"
#include "gyroflip/method/flip_detect.hpp"
#include "gyroflip/method/flip_stream.hpp"
#include "gyroflip/method/pairing.hpp"
#include "support/synth.hpp"

namespace gyroflip::method {
namespace {

using test::synth_rows;
using test::synth_spec;

std::vector<cycle> cycles_of(const synth_spec& s, pairing p) {
  const auto rows = synth_rows(s);
  return pair_cycles(extract_dwells(rows), p);
}

TEST(Dwells, WeightedByNAvgAndTurningRowsSkipped) {
  const std::vector<row> rows{{0.0, 0, 1.0, 20.0, 1},
                              {1.0, 0, 4.0, 22.0, 3},
                              {1.5, table_moving, 99.0, 99.0, 1},
                              {2.0, 0, 2.0, 21.0, 4},
                              {3.0, 1, -1.0, 20.0, 2}};
  const auto d = extract_dwells(rows);
  ASSERT_EQ(d.size(), 2u);  // the turning row does not split the 0-deg dwell
  EXPECT_EQ(d[0].position, 0);
  EXPECT_EQ(d[0].weight, 8u);
  EXPECT_DOUBLE_EQ(d[0].rate_dps, (1.0 + 12.0 + 8.0) / 8.0);
  EXPECT_DOUBLE_EQ(d[0].time_s, (0.0 + 3.0 + 8.0) / 8.0);
  EXPECT_DOUBLE_EQ(d[0].temp_c, (20.0 + 66.0 + 84.0) / 8.0);
  EXPECT_EQ(d[1].position, 1);
  EXPECT_DOUBLE_EQ(d[1].rate_dps, -1.0);
}

TEST(Method, ConstantBiasGTermAndEarthTermSplit) {
  // y = s (d_g + W_E.s) + b: dN = d_g + W_E.s exactly (eqns 7-11), c = b.
  const auto north = *earth::parse_axis("north");
  const double earth_dps = earth::earth_rate_component_dps(42.6, north);
  const double g_dps = 0.39214;
  synth_spec s;
  s.delta_n_dps = [&](double) { return g_dps + earth_dps; };
  s.bias_dps = [](double) { return 0.8; };
  for (pairing p : {pairing::simple, pairing::abba}) {
    const auto cal = calibrate(cycles_of(s, p));
    ASSERT_TRUE(cal);
    EXPECT_NEAR(cal->delta_n_dps, g_dps + earth_dps, 1e-15);
    EXPECT_NEAR(cal->std_dps, 0.0, 1e-15);
    EXPECT_NEAR(cal->bias_mean_dps, 0.8, 1e-15);
    const auto split = split_delta_n(cal->delta_n_dps, 42.6, north);
    EXPECT_NEAR(split.earth_rate_dps, 3.0755e-3, 0.5e-7);  // paper eqn 9 value
    EXPECT_NEAR(split.g_term_dps, g_dps, 1e-15);
  }
}

TEST(Method, LinearRampAbbaExactSimpleOffByHalfSlopeTimesSpacing) {
  // b(t) = b0 + b' t. abba cancels it exactly; simple leaks -b' dt/2 (dt = 0.895 s from the
  // 0-deg dwell to the 180-deg dwell), or +b' dt/2 when the cycle starts at 180 deg.
  constexpr double slope = 1e-3;
  synth_spec s;
  s.bias_dps = [](double t) { return 0.5 + slope * t; };
  for (bool start_180 : {false, true}) {
    s.start_at_180 = start_180;
    const auto abba = cycles_of(s, pairing::abba);
    const auto simple = cycles_of(s, pairing::simple);
    ASSERT_EQ(abba.size(), 60u);
    ASSERT_EQ(simple.size(), 60u);
    const double leak = (start_180 ? 1.0 : -1.0) * slope * s.dwell_spacing_s / 2.0;
    for (std::size_t j = 0; j < abba.size(); ++j) {
      EXPECT_NEAR(abba[j].rate_dps, 0.0123, 1e-15) << j;
      EXPECT_NEAR(simple[j].rate_dps, 0.0123 + leak, 1e-15) << j;
      EXPECT_NEAR(abba[j].bias_dps, 0.5 + slope * abba[j].time_s, 1e-14) << j;  // c = b(t)
      EXPECT_NEAR(simple[j].bias_dps, 0.5 + slope * simple[j].time_s, 1e-14) << j;
    }
  }
}

TEST(Method, UnequalDwellSpacingStillCancelsRampWithAbba) {
  // A dropped stretch of data makes the spacing uneven; time interpolation keeps abba exact.
  synth_spec s;
  s.bias_dps = [](double t) { return -0.2 + 3e-3 * t; };
  auto rows = synth_rows(s);
  for (std::size_t i = 30; i < rows.size(); ++i) rows[i].time_s += 7.3;  // gap after row 30
  for (auto& r : rows) r.rate_dps = (r.position == 0 ? 0.0123 : -0.0123) - 0.2 + 3e-3 * r.time_s;
  for (const auto& c : pair_cycles(extract_dwells(rows), pairing::abba))
    EXPECT_NEAR(c.rate_dps, 0.0123, 1e-14);
}

TEST(Method, ExponentialWarmUpLeakClosedForms) {
  // b(t) = A exp(-t/tau) (paper Fig. 3: sensor switched on at the start). With dwell spacing h,
  // a cycle of dwells a (0 deg) and b = a + h (180 deg) gives
  //   simple: r - dN = A (e_a - e_b)/2,   abba (interior): r - dN = -A (e_a - e_b)(cosh(h/tau) -
  //   1)/4,
  // with e = exp(-t/tau): abba shrinks the warm-up leak by (cosh(h/tau) - 1)/2 ~ h^2/(4 tau^2).
  constexpr double amp = 0.2;
  constexpr double tau = 60.0;
  synth_spec s;
  s.bias_dps = [](double t) { return 0.5 + amp * std::exp(-t / tau); };
  const auto abba = cycles_of(s, pairing::abba);
  const auto simple = cycles_of(s, pairing::simple);
  const double h = s.dwell_spacing_s;
  const double shrink = (std::cosh(h / tau) - 1.0) / 2.0;
  for (std::size_t j = 1; j + 1 < abba.size(); ++j) {
    const double ta = simple[j].time_s - h / 2;
    const double de = std::exp(-ta / tau) - std::exp(-(ta + h) / tau);
    EXPECT_NEAR(simple[j].rate_dps - 0.0123, amp * de / 2.0, 1e-15) << j;
    EXPECT_NEAR(abba[j].rate_dps - 0.0123, -amp * de / 2.0 * shrink, 1e-15) << j;
  }
  // The leak is visible in dN with simple pairing and essentially gone with abba.
  const auto cs = *calibrate(simple);
  const auto ca = *calibrate(abba);
  EXPECT_GT(std::abs(cs.delta_n_dps - 0.0123), 100.0 * std::abs(ca.delta_n_dps - 0.0123));
}

TEST(Method, DeltaNOfTemperatureRecoveredFromThreeTemperatures) {
  // Paper Tab. 3 averages as a line: dN(4 degC) = 0.00381, dN(20 degC) = 0.00309 deg/s.
  const auto truth = [](double t_c) { return 0.00381 + (0.00309 - 0.00381) / 16.0 * (t_c - 4.0); };
  std::vector<delta_n_point> pts;
  for (double t_c : {4.0, 20.0, 30.0}) {
    synth_spec s;
    s.temp_c = t_c;
    s.delta_n_dps = [&](double) { return truth(t_c); };
    s.bias_dps = [&](double t) {
      return 0.1 * t_c + 1e-4 * t;
    };  // bias depends on T too; it cancels
    const auto cal = *calibrate(cycles_of(s, pairing::abba));
    EXPECT_DOUBLE_EQ(cal.temp_c, t_c);
    pts.push_back({cal.temp_c, cal.delta_n_dps, cal.stderr_correlated_dps});
  }
  const auto m = fit_delta_n_model(pts, 1);
  ASSERT_TRUE(m) << m.err().message;
  EXPECT_NEAR(m->coeffs_dps[1], (0.00309 - 0.00381) / 16.0, 1e-15);
  for (double t_c : {-5.0, 4.0, 12.0, 20.0, 30.0})
    EXPECT_NEAR(m->eval(t_c), truth(t_c), 1e-15) << t_c;
  EXPECT_EQ(m->temp_min_c, 4.0);
  EXPECT_EQ(m->temp_max_c, 30.0);
  // A quadratic through three points is exact too, and its curvature is ~0 here.
  const auto q = fit_delta_n_model(pts, 2);
  ASSERT_TRUE(q);
  EXPECT_NEAR(q->coeffs_dps[2], 0.0, 1e-16);
}

TEST(Method, DeltaNModelUncertaintyAndErrors) {
  // Scatter larger than the stated errors inflates the covariance (Birge ratio).
  const std::vector<delta_n_point> pts{
      {0, 1.0, 0.01}, {10, 2.2, 0.01}, {20, 2.8, 0.01}, {30, 4.1, 0.01}};
  const auto m = *fit_delta_n_model(pts, 1);
  EXPECT_GT(m.chi2_per_dof, 1.0);
  const auto unscaled_var0 = 1.0 / (4.0 / (0.01 * 0.01));  // (X'WX)^-1 for the centred intercept
  EXPECT_NEAR(m.cov[0], unscaled_var0 * m.chi2_per_dof, 1e-12);
  EXPECT_NEAR(m.stderr_at(m.t_ref_c), std::sqrt(m.cov[0]), 1e-15);
  EXPECT_FALSE(fit_delta_n_model(std::vector<delta_n_point>{{20, 1, 0.1}, {20, 1.1, 0.1}}, 1));
  EXPECT_FALSE(fit_delta_n_model(pts, 7));
  EXPECT_FALSE(
      fit_delta_n_model(std::vector<delta_n_point>{{std::nan(""), 1, 0.1}, {20, 1.1, 0.1}}, 0));
}

TEST(Method, CompensationReturnsInputRate) {
  // Eqn 12 on a rate-table run: w_in = r - dN, with a drifting bias that the flip removes.
  synth_spec s;
  s.input_dps = 0.25;
  s.bias_dps = [](double t) { return 0.3 - 2e-4 * t; };
  const auto cycles = cycles_of(s, pairing::abba);
  std::vector<compensated_cycle> out;
  for (const auto& c : cycles) out.push_back(compensate(c, constant_model(0.0123)));
  for (const auto& c : out) {
    EXPECT_NEAR(c.rate_dps, 0.25, 1e-14);
    EXPECT_NEAR(c.bias_dps, 0.3 - 2e-4 * c.time_s, 1e-14);
  }
  const auto sum = summarize(out, 10.0);
  EXPECT_NEAR(sum.mean_dps, 0.25, 1e-14);
  ASSERT_TRUE(sum.drift_dps);
  EXPECT_NEAR(*sum.drift_dps, 0.0, 1e-13);
  // A model applies dN at each cycle's temperature.
  delta_n_model m = constant_model(0.0);
  m.coeffs_dps = {0.01, 1e-3};
  m.t_ref_c = 20.0;
  cycle c{1.0, 0.02, 0.0, 25.0};
  EXPECT_DOUBLE_EQ(compensate(c, m).delta_n_dps, 0.015);
  EXPECT_NEAR(compensate(c, m).rate_dps, 0.005, 1e-15);
}

TEST(Method, TooFewCyclesIsAnError) {
  const std::vector<cycle> two(2);
  EXPECT_FALSE(calibrate(two));
}

// --- Statistics with fixed seeds ------------------------------------------------------------

TEST(MethodStatistics, DeltaNWithinFourSigmaOverManySeeds) {
  // White noise 0.01 deg/s per dwell, 200 cycles: the estimate must lie within 4 standard errors
  // of the truth for every seed, and the z-scores must have a spread near 1 (the error is honest,
  // neither too small nor grossly inflated). 60 seeds: P(any |z| > 4) ~ 0.4 % if all is right.
  for (pairing p : {pairing::simple, pairing::abba}) {
    std::vector<double> z;
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
      synth_spec s;
      s.dwells = 400;
      s.noise_dps = 0.01;
      s.seed = seed;
      s.bias_dps = [](double t) { return 0.5 + 1e-5 * t; };
      const auto cal = *calibrate(cycles_of(s, p));
      z.push_back((cal.delta_n_dps - 0.0123) / cal.stderr_correlated_dps);
      EXPECT_LT(std::abs(z.back()), 4.0) << "seed " << seed;
    }
    double ss = 0.0;
    for (double v : z) ss += v * v;
    const double rms = std::sqrt(ss / static_cast<double>(z.size()));
    EXPECT_GT(rms, 0.6) << to_string(p);
    EXPECT_LT(rms, 1.4) << to_string(p);
  }
}

TEST(MethodStatistics, CorrelatedErrorExceedsNaiveWhenDeltaNRandomWalks) {
  // If dN itself wanders (a random-walk g-term, e.g. from temperature), neighbouring cycle
  // values are correlated and std/sqrt(n) is far too optimistic.
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    test::normal_source rnd(seed + 100);
    auto walk = std::make_shared<std::vector<double>>(1, 0.0123);
    for (int k = 1; k < 2000; ++k) walk->push_back(walk->back() + 1e-4 * rnd());
    synth_spec s;
    s.dwells = 2000;
    s.noise_dps = 0.002;
    s.seed = seed;
    s.delta_n_dps = [walk, s](double t) {
      return (*walk)[static_cast<std::size_t>(std::lround((t - s.t0_s) / s.dwell_spacing_s))];
    };
    const auto rw = *calibrate(cycles_of(s, pairing::abba));
    EXPECT_GT(rw.stderr_correlated_dps, 3.0 * rw.stderr_dps) << seed;
  }
}

TEST(MethodStatistics, CorrelatedErrorMatchesTheoryForWhiteNoise) {
  // White dwell noise: simple cycles are independent (true error = naive). abba cycles share
  // dwells: r_j = (1.5 a_j + 0.5 a_{j+1} - 0.5 b_{j-1} - 1.5 b_j)/4, so var = 5/16, lag-1
  // covariance 1.5/16, rho_1 = 0.3, and the true error of the mean is sqrt(1 + 2 rho_1) = 1.265
  // times the naive one. The estimate (EDF ~ 10 per seed) averaged over 20 seeds must be within
  // 15 % of that (3 sigma of the average is ~ 11 %).
  for (const auto& [p, truth] :
       {std::pair{pairing::simple, 1.0}, std::pair{pairing::abba, std::sqrt(1.6)}}) {
    double ratio = 0.0;
    constexpr int seeds = 20;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
      synth_spec s;
      s.dwells = 2000;
      s.noise_dps = 0.002;
      s.seed = seed;
      const auto c = *calibrate(cycles_of(s, p));
      EXPECT_GE(c.stderr_correlated_dps, c.stderr_dps);
      ratio += c.stderr_correlated_dps / c.stderr_dps / seeds;
    }
    EXPECT_NEAR(ratio / truth, 1.0, 0.15) << to_string(p);
  }
}

// --- Streaming form ---------------------------------------------------------------------------

void expect_same(const std::vector<cycle>& a, const std::vector<cycle>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].time_s, b[i].time_s) << i;
    EXPECT_EQ(a[i].rate_dps, b[i].rate_dps) << i;
    EXPECT_EQ(a[i].bias_dps, b[i].bias_dps) << i;
    EXPECT_TRUE(a[i].temp_c == b[i].temp_c || (std::isnan(a[i].temp_c) && std::isnan(b[i].temp_c)))
        << i;
  }
}

TEST(MethodStreaming, BitIdenticalToBatch) {
  for (std::size_t dwells : {3u, 4u, 5u, 41u, 40u}) {
    for (bool raw : {false, true}) {
      for (pairing p : {pairing::simple, pairing::abba}) {
        synth_spec s;
        s.dwells = dwells;
        s.noise_dps = 0.05;
        s.seed = dwells;
        s.conversions = raw ? 16 : 1;
        s.temp_c = raw ? std::nan("") : 21.5;
        s.bias_dps = [](double t) { return 0.4 + 0.01 * std::sin(t); };
        const auto rows = synth_rows(s);
        std::vector<cycle> streamed;
        flip_stream st(p);
        const auto sink = [&](const cycle& c) { streamed.push_back(c); };
        for (const auto& r : rows) st.push(r, sink);
        st.flush(sink);
        SCOPED_TRACE(testing::Message()
                     << dwells << " dwells, raw " << raw << ", " << to_string(p));
        expect_same(streamed, pair_cycles(extract_dwells(rows), p));
        EXPECT_EQ(streamed.size(), p == pairing::abba && dwells < 3 ? 0u : dwells / 2);
      }
    }
  }
}

}  // namespace
// Issue 13 item 15: the cycle values of the abba pairing are correlated. With white dwell noise
// (variance s^2) each abba cycle is (u_{2j-1} + 3u_{2j} + 3u_{2j+1} + u_{2j+2})/8 of the sign-
// corrected dwells u, so var = 20/64 s^2, lag-1 covariance 6/64 s^2 and none beyond: the Allan
// variance over m cycles is (m 20/64 + (2m - 3) 6/64)/m^2 s^2 = s^2 (1/(2m) - 9/(32 m^2)) - 44 %
// below the white line at m = 1. Checked on 200 000 simulated dwells (relative tolerance 2 %,
// about 5 standard errors at m = 8). The noise fit that knows it (noise_series) then finds no
// bias instability and the ARW N = s sqrt(T/2) of the white line within its interval.
TEST(AbbaCycles, AllanVarianceOfWhiteDwellNoiseHasTheClosedForm) {
  constexpr double sigma = 0.01;
  constexpr double dwell_s = 0.9;
  sensor::normal_stream g(5, sensor::stream::user);
  std::vector<dwell> d(200000);
  for (std::size_t k = 0; k < d.size(); ++k) {
    const int sign = k % 2 == 0 ? 1 : -1;
    d[k].position = sign > 0 ? 0 : 1;  // the paper's table, pair {0, 1}
    d[k].time_s = dwell_s * static_cast<double>(k);
    d[k].rate_dps = 0.3 * sign + 0.1 + sigma * g.next();
    d[k].weight = 256;
  }
  const auto cycles = pair_cycles(d, pairing::abba);
  std::vector<double> r;
  for (const auto& c : cycles) r.push_back(c.rate_dps);
  const double cycle_s = 2.0 * dwell_s;
  analysis::tau_spec taus{analysis::tau_spec::set::list, {1, 2, 4, 8}};
  const auto pts = *analysis::oadev(r, analysis::input_kind::rate, cycle_s, taus);
  for (const auto& p : pts) {
    const double m = static_cast<double>(p.m);
    const double want = sigma * sigma * (1.0 / (2.0 * m) - 9.0 / (32.0 * m * m));
    EXPECT_NEAR(p.dev * p.dev / want, 1.0, 0.02) << "m " << p.m;
  }
  auto curve = *analysis::oadev(r, analysis::input_kind::rate, cycle_s);
  // The fit's weights from the guarded EDFs, as analysis::analyse_noise computes them.
  analysis::add_confidence(curve, analysis::dev_kind::oadev, analysis::phase_from_rate(r, cycle_s),
                           0.683, analysis::edf_rule::guarded);
  const auto f = *analysis::fit_noise_terms(curve, 0.683, noise_series_of(pairing::abba, cycle_s));
  EXPECT_FALSE(f.bias_instability.resolved);
  const double n_true = sigma * std::sqrt(cycle_s / 2.0);
  EXPECT_TRUE(f.arw.resolved && f.arw.lo <= n_true && n_true <= f.arw.hi)
      << f.arw.lo << " " << n_true << " " << f.arw.hi;
  EXPECT_LT(f.chi2_per_dof, 2.0);
}

// The flip-modulation test (issue 13 item 12): a square wave of half-amplitude d on white noise
// of sigma is found when d^2 > 1 % of sigma^2 (and the means differ by > 10 standard errors),
// not when d = 0; turning rows (NaN angle) are ignored.
TEST(FlipDetect, SquareWaveOnNoise) {
  sensor::normal_stream g(3, sensor::stream::user);
  const auto series = [&](double d, std::vector<double>& v, std::vector<double>& a) {
    v.clear();
    a.clear();
    for (int k = 0; k < 4000; ++k) {
      const bool turning = k % 10 == 9;
      a.push_back(turning ? std::nan("") : (k / 10 % 2 == 0 ? 0.0 : 180.0));
      v.push_back((a.back() == 0.0 ? d : -d) + 0.01 * g.next());
    }
  };
  std::vector<double> v, a;
  series(0.0, v, a);
  EXPECT_FALSE(detect_flip_modulation(v, a).modulated);
  series(0.003, v, a);  // d^2 = 9 % of sigma^2
  const auto f = detect_flip_modulation(v, a);
  EXPECT_TRUE(f.modulated);
  EXPECT_NEAR(f.mean_0 - f.mean_180, 0.006, 0.001);
  EXPECT_EQ(f.n_0 + f.n_180, 3600u);
  series(0.0005, v, a);  // d^2 = 0.25 % of sigma^2: too small to matter
  EXPECT_FALSE(detect_flip_modulation(v, a).modulated);
  EXPECT_FALSE(detect_flip_modulation(std::vector<double>{1, 2, 3}, std::vector<double>{0, 0, 0})
                   .modulated);  // one position only
}

}  // namespace gyroflip::method

namespace gyroflip::method {
namespace {

// Issue 33: a scheme is a demodulator behind one interface, selected by name in one table.
// Pushing dwells through make_demodulator gives the batch pairing's cycles bit for bit, and the
// table's names are the --pairing values.
TEST(Demodulator, SchemesBehindTheInterfaceGiveTheBatchPairingsCycles) {
  EXPECT_EQ(scheme_names(), (std::vector<std::string>{"abba", "simple", "harmonic"}));
  EXPECT_EQ(scheme_names_joined(" or "), "abba or simple or harmonic");
  for (const pairing p : {pairing::simple, pairing::abba}) {
    EXPECT_EQ(parse_pairing(to_string(p)), p);
    EXPECT_EQ(scheme_of(p).name, to_string(p));
    synth_spec s;
    s.dwells = 41;
    s.noise_dps = 0.05;
    s.seed = 9;
    s.bias_dps = [](double t) { return 0.4 + 0.01 * std::sin(t); };
    const auto dwells = extract_dwells(synth_rows(s));
    auto d = make_demodulator(p, position_table::pair_0_180(), "<test>");
    ASSERT_TRUE(d);
    EXPECT_EQ((*d)->name(), to_string(p));
    EXPECT_EQ((*d)->uses(), 0b11u);
    std::vector<cycle> out;
    for (const auto& dw : dwells)
      if (auto c = (*d)->push(dw)) out.push_back(*c);
    if (auto c = (*d)->flush()) out.push_back(*c);
    SCOPED_TRACE(to_string(p));
    expect_same(out, pair_cycles(dwells, p));
  }
  EXPECT_FALSE(parse_pairing("abab"));
  // A table without the pair: the scheme says so, naming the source.
  const double angles[] = {0.0, 90.0};
  const auto t = position_table::of_angles(angles);
  ASSERT_TRUE(t);
  const auto bad = make_demodulator(pairing::abba, *t, "run.csv");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.err().message.find("run.csv"), std::string::npos) << bad.err().message;
}

// Each scheme's noise transfer against the noise that passes through its demodulator: white dwell
// noise of unit variance (200 000 dwells, fixed seed) gives the estimates the variance and lag-1
// covariance of the kernel (tolerance 0.006, ~4 standard errors), and random-walk dwell means
// (a random walk of unit steps sampled once per dwell: two-sample variance lag/2 at a lag of that
// many dwells) the kernel's rate_variance (tolerance 5 %). The
// closed forms of the abba pairing (METHOD-NOTES.md) follow from its kernel: std/ADEV sqrt(20/14)
// and the Allan deficit 9/16 of the noise fit.
TEST(Demodulator, NoiseTransferMatchesTheNoiseThroughTheDemodulator) {
  const auto& abba = scheme_of(pairing::abba).transfer();
  const auto& simple = scheme_of(pairing::simple).transfer();
  EXPECT_EQ(abba.white_autocovariance(0), 20.0 / 64.0);
  EXPECT_EQ(abba.white_autocovariance(1), 6.0 / 64.0);
  EXPECT_EQ(abba.white_std_over_adev(), std::sqrt(20.0 / 14.0));
  EXPECT_EQ(abba.white_avar_deficit(), 0.5625);
  EXPECT_EQ(simple.white_std_over_adev(), 1.0);
  EXPECT_EQ(simple.white_avar_deficit(), 0.0);
  EXPECT_EQ(simple.white_covariance(), (std::array<double, 3>{0.5, 0.0, 0.5}));
  const auto series = noise_series_of(pairing::abba, 1.79);
  EXPECT_EQ(series.white_avar_deficit * series.cycle_s, 0.5625 * 1.79);
  EXPECT_NE(series.note.find("lag-1 correlation 0.3 "), std::string::npos) << series.note;
  EXPECT_NE(series.note.find("(9/16) T/tau^2"), std::string::npos) << series.note;
  EXPECT_FALSE(noise_series_of(pairing::simple, 1.79).shaped());

  for (const pairing p : {pairing::simple, pairing::abba}) {
    const auto& t = scheme_of(p).transfer();
    for (const bool walk : {false, true}) {
      sensor::normal_stream g(walk ? 11 : 12, sensor::stream::user);
      std::vector<dwell> d(200000);
      double level = 0.0;
      for (std::size_t k = 0; k < d.size(); ++k) {
        d[k].position = static_cast<int>(k % 2);
        d[k].time_s = static_cast<double>(k);
        level = walk ? level + g.next() : g.next();
        d[k].rate_dps = level;
        d[k].weight = 1;
      }
      auto demod = make_flip_demodulator(p);
      std::vector<double> r;
      for (const auto& dw : d)
        if (auto c = demod->push(dw)) r.push_back(c->rate_dps);
      r.erase(r.begin());  // the edge cycle (its own kernel)
      const double n = static_cast<double>(r.size());
      double var = 0.0, cov1 = 0.0;
      if (walk) {
        // Increments of r only: the walk makes r stationary (a zero-sum kernel) without its mean.
        for (const double x : r) var += x * x;
        var /= n;
        const double want =
            t.rate_variance([](std::size_t lag) { return 0.5 * static_cast<double>(lag); });
        SCOPED_TRACE(testing::Message() << to_string(p) << " random walk");
        EXPECT_NEAR(var / want, 1.0, 0.05) << var << " vs " << want;
        continue;
      }
      for (std::size_t i = 0; i < r.size(); ++i) {
        var += r[i] * r[i];
        if (i + 1 < r.size()) cov1 += r[i] * r[i + 1];
      }
      SCOPED_TRACE(testing::Message() << to_string(p) << " white");
      EXPECT_NEAR(var / n, t.white_autocovariance(0), 0.006);
      EXPECT_NEAR(cov1 / (n - 1), t.white_autocovariance(1), 0.006);
      EXPECT_NEAR(var / n, t.white_covariance()[0], 0.006);
    }
  }
}

}  // namespace
}  // namespace gyroflip::method
