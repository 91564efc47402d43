// North finding on the simulator (issue 33): more than two positions, the sweep's visiting
// order, a vertical table axis at an azimuth, a tilted table, and the heading's error against
// the truth over a small fixed set of seeds (the 200-seed figures: bench/heading_coverage,
// docs/PERFORMANCE.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/simulate.hpp"

namespace gm = gyroflip::method;
namespace gr = gyroflip::rig;
namespace gw = gyroflip::workflow;

namespace {

gr::simulation_config north(const char* preset, double azimuth_deg, double duration_s) {
  gr::simulation_config c;
  c.sensor = gyroflip::sensor::load_preset(preset)->params;
  c.table_axis = "up";
  c.mount.azimuth_deg = azimuth_deg;
  c.rig.positions_deg = {0.0, 90.0, 180.0, 270.0};
  c.duration_s = duration_s;
  c.power_on_before_s = 3600.0;
  return c;
}

}  // namespace

TEST(North, FourPositionsAreSweptForwardsThenBackwards) {
  auto c = north("hz1-90-100a", 30.0, 60.0);
  auto run = gw::simulate_rows(c, true);
  ASSERT_TRUE(run) << run.err().message;
  const int expect[8] = {0, 90, 180, 270, 270, 180, 90, 0};
  ASSERT_GE(run->rows.size(), 16U);
  for (std::size_t k = 0; k < 16; ++k) EXPECT_EQ(run->rows[k].angle_deg, expect[k % 8]) << k;
  // Cycle order on request: the table's order over and over.
  c.order = gr::visit_order::cycle;
  run = gw::simulate_rows(c, false);
  ASSERT_TRUE(run);
  for (std::size_t k = 0; k < 8; ++k)
    EXPECT_EQ(run->rows[k].angle_deg, 90.0 * static_cast<double>(k % 4)) << k;
}

// The Earth term at each position is W_H cos(psi - theta) about a vertical axis (up), and the
// truth names the heading; a tilt of 1 mrad adds a first harmonic of g_z x 1 mrad (the g-term
// reads as Earth rate: 7 deg of heading with the ADXRS150's 0.39 deg/s/g).
TEST(North, TruthHoldsTheHeadingAndTheTiltsTerm) {
  auto c = north("adxrs150", 30.0, 30.0);
  c.sensor.cross_axis_y = 0.0;
  auto sim = gr::simulator::make(c);
  ASSERT_TRUE(sim);
  const double wh = 4.178074e-3 * std::cos(42.6 * std::numbers::pi / 180.0);
  for (const double th : {0.0, 90.0, 180.0, 270.0})
    EXPECT_NEAR(sim->earth_at_dps(th), wh * std::cos((30.0 - th) * std::numbers::pi / 180.0), 1e-9)
        << th;
  auto run = gw::simulate_rows(c, false);
  ASSERT_TRUE(run);
  EXPECT_NEAR(run->truth.heading_deg, 30.0, 1e-9);
  EXPECT_NEAR(run->truth.apparent_heading_deg, 30.0, 1e-9);  // level: nothing but Earth
  EXPECT_NEAR(std::hypot(run->truth.g_c1_dps, run->truth.g_s1_dps), 0.0, 1e-15);
  c.mount.tilt_mrad = 1.0;
  double gz = 0.0, worst = 0.0;
  for (double lean = 0.0; lean < 360.0; lean += 10.0) {  // where the table axis leans
    c.mount.tilt_azimuth_deg = lean;
    sim = gr::simulator::make(c);
    ASSERT_TRUE(sim);
    run = gw::simulate_rows(c, false);
    ASSERT_TRUE(run);
    gz = std::abs(sim->sensor_model().g_sens_g0().z);
    EXPECT_NEAR(std::hypot(run->truth.g_c1_dps, run->truth.g_s1_dps), gz * 1e-3, 1e-3 * gz * 1e-3);
    worst =
        std::max(worst, std::abs(std::remainder(run->truth.apparent_heading_deg - 30.0, 360.0)));
  }
  // The worst lean (the term across the Earth's): atan(g_z x tilt / W_H).
  const double shift = worst;
  EXPECT_NEAR(shift, std::atan(gz * 1e-3 / wh) * 180.0 / std::numbers::pi, 0.1);
  EXPECT_GT(shift, 6.5);  // the "1 mrad gives 7 deg"
}

// The heading from the simulator's runs, two base azimuths 180 deg apart with the tilt, a
// scale-factor error and the turns' dead time present: 12 fixed seeds, HZ1-90-100A, 2 x 20 min.
// Tolerances: the mean of z^2 = (error / reported sigma)^2 over 12 seeds lies in [0.27, 2.18]
// with 99 % probability when the sigma is right (chi^2_12 / 12); the rms error within 1.5 x
// the dead-time bound (the 200-seed ratio is 0.96, docs/PERFORMANCE.md).
TEST(North, HeadingErrorsMatchTheirSigmaOnFixedSeeds) {
  double z2 = 0.0, e2 = 0.0;
  const int seeds = 12;
  double d = 0.0, total_s = 0.0;
  for (int s = 0; s < seeds; ++s) {
    const double az = std::fmod(37.0 + 137.5 * s, 360.0);
    std::array<gm::harmonic_fit, 2> f;
    double truth = 0.0;
    for (int k = 0; k < 2; ++k) {
      auto c = north("hz1-90-100a", std::fmod(az + 180.0 * k, 360.0), 1200.0);
      c.sensor.scale_factor_error_ppm = 5000.0;
      c.mount.tilt_mrad = 1.0;
      c.mount.tilt_azimuth_deg = 60.0;
      c.rig.n_avg = 381;  // the planner's dwell for the sweep's dead time (0.76 s)
      c.seed = 500 + 2 * static_cast<std::uint64_t>(s) + static_cast<std::uint64_t>(k);
      auto sim = gr::simulator::make(c);
      ASSERT_TRUE(sim);
      d = sim->sched().dead_time_per_dwell_s();
      auto run = gw::simulate_rows(c, false);
      ASSERT_TRUE(run);
      if (k == 0) truth = run->truth.sensed_heading_deg;
      const auto table = c.rig.table();
      const auto rows = gw::recording_rows(run->rows, table);
      auto fit = gm::fit_harmonics(gm::indexed_dwells(rows), table);
      ASSERT_TRUE(fit) << fit.err().message;
      f[static_cast<std::size_t>(k)] = *fit;
    }
    total_s = 2400.0;
    const auto h = gm::heading_two_azimuths(
        {f[0].value[1], f[0].value[2]}, {f[0].var(1), f[0].cov(1, 2), f[0].cov(1, 2), f[0].var(2)},
        {f[1].value[1], f[1].value[2]}, {f[1].var(1), f[1].cov(1, 2), f[1].cov(1, 2), f[1].var(2)},
        180.0);
    ASSERT_TRUE(h);
    const double e = std::remainder(h->first.heading_deg - truth, 360.0);
    z2 += e * e / (h->first.sigma_deg * h->first.sigma_deg);
    e2 += e * e;
  }
  const auto p = gyroflip::sensor::load_preset("hz1-90-100a")->params;
  const double bound =
      gm::heading_dead_time_limit_deg(p.arw_dps_rthz, p.bias_instability_dps, d, 42.6, total_s);
  EXPECT_GT(z2 / seeds, 0.27);
  EXPECT_LT(z2 / seeds, 2.18);
  EXPECT_LT(std::sqrt(e2 / seeds) / bound, 1.5);
}
