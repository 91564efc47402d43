// The harmonic fit of an indexed run and the heading (method/harmonic.hpp, issue 33) against
// exact synthetic dwells, closed forms and the issue's published figures.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gyroflip/core/units.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "support/synth.hpp"

namespace gm = gyroflip::method;
using gyroflip::position_table;

namespace {

constexpr double rad = std::numbers::pi / 180.0;

// A four-position sweep 0,1,2,3,3,2,1,0 of `blocks` periods, dwell spacing 1 s: r = bias(t) +
// c1 cos + s1 sin + white noise of `sigma`.
std::vector<gm::indexed_dwell> sweep(std::size_t blocks, double b0, double slope, double c1,
                                     double s1, double sigma, std::uint64_t seed) {
  const int order[8] = {0, 1, 2, 3, 3, 2, 1, 0};
  gyroflip::test::normal_source n(seed);
  std::vector<gm::indexed_dwell> d;
  double t = 0.0;
  for (std::size_t j = 0; j < blocks; ++j)
    for (const int p : order) {
      const double a = 90.0 * p * rad;
      d.push_back({t, p, b0 + slope * t + c1 * std::cos(a) + s1 * std::sin(a) + sigma * n(), 256});
      t += 1.0;
    }
  return d;
}

position_table four() {
  const double a[4] = {0.0, 90.0, 180.0, 270.0};
  return *position_table::of_angles(a);
}

}  // namespace

// A bias moving linearly drops out of every block exactly (the sweep is symmetric in time).
TEST(Harmonic, LinearBiasDriftDropsOutExactly) {
  const auto d = sweep(20, 0.3, 1e-3, 2e-3, -1e-3, 0.0, 1);
  const auto f = gm::fit_harmonics(d, four());
  ASSERT_TRUE(f) << f.err().message;
  EXPECT_EQ(f->period, 8U);
  EXPECT_EQ(f->blocks, 20U);
  EXPECT_NEAR(f->value[1], 2e-3, 1e-14);
  EXPECT_NEAR(f->value[2], -1e-3, 1e-14);
}

// White dwell noise: the estimates scatter as sigma sqrt(2 / dwells) (the closed form: each of
// c1, s1 is 2/M sum r cos), and the reported covariance says so (64 blocks: correlated error
// on). Tolerances: 200 runs give the variance to +-10 % (1 sigma), checked at +-30 %.
TEST(Harmonic, WhiteNoiseGivesTheClosedFormAndItsOwnSigma) {
  const double sigma = 0.01;
  const std::size_t blocks = 64;
  double ss = 0.0, reported = 0.0, z2 = 0.0;
  const int runs = 200;
  for (int s = 0; s < runs; ++s) {
    const auto d = sweep(blocks, 0.1, 0.0, 3e-3, 1e-3, sigma, static_cast<std::uint64_t>(100 + s));
    const auto f = gm::fit_harmonics(d, four());
    ASSERT_TRUE(f);
    ss += (f->value[1] - 3e-3) * (f->value[1] - 3e-3);
    reported += f->var(1);
    z2 += (f->value[2] - 1e-3) * (f->value[2] - 1e-3) / f->var(2);
  }
  const double closed = sigma * sigma * 2.0 / (8.0 * blocks);
  EXPECT_NEAR(ss / runs / closed, 1.0, 0.3);
  EXPECT_NEAR(reported / runs / closed, 1.0, 0.1);
  EXPECT_NEAR(z2 / runs, 1.0, 0.3);
}

TEST(Harmonic, RefusesWhatCannotBeSeparated) {
  const double two[2] = {0.0, 180.0};
  std::vector<gm::indexed_dwell> d;
  for (int k = 0; k < 40; ++k) d.push_back({1.0 * k, k % 2, 0.0, 1.0});
  const auto f = gm::fit_harmonics(d, *position_table::of_angles(two));
  ASSERT_FALSE(f);
  EXPECT_NE(f.err().message.find("at least 3"), std::string::npos) << f.err().message;
  // Two harmonics from four positions: refused (2 theta aliases at 0/90/180/270).
  EXPECT_FALSE(gm::fit_harmonics(sweep(10, 0, 0, 1, 1, 0, 1), four(), {2}));
}

// The heading of the axis from (c1, s1) = W_H (cos psi, sin psi) (table axis up), its delta-method
// sigma (sigma_c / W_H rad for equal, independent errors), and down: s1 mirrored.
TEST(Harmonic, HeadingOfTheFirstHarmonic) {
  const double w = 3.0755e-3;
  for (const double psi : {0.0, 30.0, 135.0, 250.0, 359.0}) {
    const auto h =
        gm::heading_of(w * std::cos(psi * rad), w * std::sin(psi * rad), 1e-8, 1e-8, 0.0);
    EXPECT_NEAR(h.heading_deg, psi, 1e-9);
    EXPECT_NEAR(h.sigma_deg, 1e-4 / w / rad, 1e-9);
    const auto down =
        gm::heading_of(w * std::cos(psi * rad), -w * std::sin(psi * rad), 1e-8, 1e-8, 0.0, false);
    EXPECT_NEAR(std::remainder(down.heading_deg - psi, 360.0), 0.0, 1e-9);
  }
}

// The issue's figures at 42.6 deg N: sqrt(2) N / (W_E cos(lat) sqrt(1 h)) is 2.0 deg for the
// HZ1-90-100A (N = 0.0046) and 15.5 deg for the ADXRS150 (N = 0.0354 deg/s/sqrt(Hz)).
TEST(Harmonic, WhiteLimitIsTheIssuesFigures) {
  EXPECT_NEAR(gm::heading_white_limit_deg(0.0046, 42.6, 3600.0), 2.0, 0.05);
  EXPECT_NEAR(gm::heading_white_limit_deg(0.0354, 42.6, 3600.0), 15.5, 0.1);
  EXPECT_NEAR(gm::heading_white_limit_deg(0.0354, 42.6, 4 * 3600.0), 15.5 / 2.0, 0.05);
  // k = 1 for a known-bias pair; dead time adds 0.664 B sqrt(d) to N.
  EXPECT_NEAR(gm::heading_white_limit_deg(0.0354, 42.6, 3600.0, 1.0) * std::sqrt(2.0), 15.5, 0.1);
  EXPECT_NEAR(gm::heading_dead_time_limit_deg(0.0354, 0.02, 0.25, 42.6, 3600.0),
              gm::heading_white_limit_deg(0.0354 + 0.664 * 0.02 * 0.5, 42.6, 3600.0), 1e-12);
}

// Two base azimuths: a term fixed to the table (tilt x g) cancels exactly, for any base turn
// but 0; the Earth's part rotates with the base.
TEST(Harmonic, TwoAzimuthsRemoveTheTablesTerm) {
  const double w = 3.0755e-3, gc = 2e-4, gs = -3e-4;
  for (const double turn : {180.0, 90.0, -120.0}) {
    for (const double psi : {10.0, 200.0}) {
      const std::array<double, 2> h1{w * std::cos(psi * rad) + gc, w * std::sin(psi * rad) + gs};
      const std::array<double, 2> h2{w * std::cos((psi + turn) * rad) + gc,
                                     w * std::sin((psi + turn) * rad) + gs};
      const std::array<double, 4> cov{1e-10, 0.0, 0.0, 1e-10};
      const auto h = gm::heading_two_azimuths(h1, cov, h2, cov, turn);
      ASSERT_TRUE(h);
      EXPECT_NEAR(std::remainder(h->first.heading_deg - psi, 360.0), 0.0, 1e-9) << turn;
      EXPECT_NEAR(h->table_term_dps, std::hypot(gc, gs), 1e-12);
      // Turned 180 deg, each run weighs half: sigma = sigma_1 / sqrt(2) / W rad.
      if (turn == 180.0) {
        EXPECT_NEAR(h->first.sigma_deg, 1e-5 / std::sqrt(2.0) / w / rad, 1e-9);
      }
    }
  }
  EXPECT_FALSE(gm::heading_two_azimuths({1, 0}, {1, 0, 0, 1}, {1, 0}, {1, 0, 0, 1}, 0.0));
}

// 0/180 with the scale factor known (issue 33 item 3): the projection p1 of the first harmonic
// on the table's 0 deg direction, the paper's A, B cycle fitted in blocks of A B A B with a bias
// and its slope: a linear drift drops out exactly (A B A B's slope column is not orthogonal to
// the contrast, but fitted), and white noise gives 1.25 sigma^2 / (number of dwells).
TEST(Harmonic, TwoPositionsGiveTheProjectionWhenAskedFor) {
  const double two[2] = {0.0, 180.0};
  const auto table = *position_table::of_angles(two);
  std::vector<gm::indexed_dwell> d;
  for (int k = 0; k < 400; ++k)
    d.push_back({1.0 * k, k % 2, 0.3 - 1e-4 * k + (k % 2 ? -1.0 : 1.0) * 2e-3, 256});
  gm::harmonic_options o;
  o.projection_of_two = true;
  const auto f = gm::fit_harmonics(d, table, o);
  ASSERT_TRUE(f) << f.err().message;
  ASSERT_EQ(f->names, (std::vector<std::string>{"b", "p1"}));
  EXPECT_NEAR(f->value[1], 2e-3, 1e-14);
  EXPECT_EQ(f->period, 4u);
  // white noise: Var p1 = sigma^2/n over n dwells (half at each end, (r_A - r_B)/2)
  double z2 = 0;
  const int runs = 60;
  for (int s = 0; s < runs; ++s) {
    gyroflip::test::normal_source n(100 + static_cast<std::uint64_t>(s));
    std::vector<gm::indexed_dwell> w;
    for (int k = 0; k < 800; ++k) w.push_back({1.0 * k, k % 2, 1e-3 * n(), 256});
    const auto g = gm::fit_harmonics(w, table, o);
    ASSERT_TRUE(g);
    z2 += g->value[1] * g->value[1] / (1e-6 / 800);
  }
  // Each block A B A B fits its bias and slope: the contrast (1,-1,1,-1) less its regression on
  // t = (-1.5,-0.5,0.5,1.5) is (0.4,-1.2,1.2,-0.4), sum of squares 3.2 against 4: Var p1 =
  // 1.25 sigma^2/n (the paper's A, B cycle pays 25 %; the sweep A B B A nothing). chi2_60/60:
  // 99 % within [0.62, 1.47].
  EXPECT_GT(z2 / runs / 1.25, 0.62);
  EXPECT_LT(z2 / runs / 1.25, 1.47);
  // not 180 deg apart: refused
  const double bent[2] = {0.0, 90.0};
  EXPECT_FALSE(gm::fit_harmonics(d, *position_table::of_angles(bent), o));
}

// psi = theta_0 +- acos(p1 / W_H): both solutions, the delta-method sigma, the axis down, the edge.
TEST(Harmonic, HeadingOfAProjectionHasTwoSolutions) {
  const double w = 3.0755e-3, sp = 2e-5;
  const auto h = gm::heading_of_projection(w * std::cos(60 * rad), sp * sp, w, 0.0);
  EXPECT_NEAR(h.heading_deg, 60.0, 1e-9);
  EXPECT_NEAR(h.mirror_deg, 300.0, 1e-9);
  EXPECT_NEAR(h.sigma_deg, sp / (w * std::sin(60 * rad)) / rad, 1e-9);
  EXPECT_FALSE(h.at_edge);
  // table axis down: r(theta) = W_H cos(psi + theta); positions 90/270: psi = -90 +- 60
  const auto d = gm::heading_of_projection(w * std::cos(60 * rad), sp * sp, w, 90.0, false);
  EXPECT_NEAR(d.heading_deg, 330.0, 1e-9);
  EXPECT_NEAR(d.mirror_deg, 210.0, 1e-9);
  // up, positions 90/270: psi = 90 +- 60
  const auto u = gm::heading_of_projection(w * std::cos(60 * rad), sp * sp, w, 90.0, true);
  EXPECT_NEAR(u.heading_deg, 150.0, 1e-9);
  EXPECT_NEAR(u.mirror_deg, 30.0, 1e-9);
  // beyond W_H by noise: clamped to 0 deg, the sigma the angle of one sigma from the edge
  const auto e = gm::heading_of_projection(w * 1.001, sp * sp, w, 0.0);
  EXPECT_TRUE(e.at_edge);
  EXPECT_NEAR(e.heading_deg, 0.0, 1e-9);
  EXPECT_NEAR(e.sigma_deg, std::acos(1 - sp / w) / rad, 1e-9);
}
