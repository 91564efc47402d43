// Rig module: geometry, profiles, stepper, AD7739, schedule and the recording generator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/rig/geometry.hpp"
#include "gyroflip/rig/profiles.hpp"
#include "gyroflip/rig/schedule.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/rig/turntable.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::rig {
namespace {

constexpr double pi = 3.14159265358979323846;
const double w_e = earth::earth_rate_wgs84_dps;

TEST(Geometry, DefaultRigFlipsEarthAndGravity) {
  const auto g = rig_geometry::make(42.6, "north", "").value();
  EXPECT_NEAR(g.table_axis.east, 1.0, 1e-15);  // horizontal, perpendicular to north
  const auto a = terms_at(g, 0.0);
  const auto b = terms_at(g, 180.0);
  EXPECT_NEAR(a.earth_dps.x, w_e * std::cos(42.6 * pi / 180.0), 1e-12);  // paper eqn 9
  EXPECT_EQ(b.earth_dps.x, -a.earth_dps.x);
  EXPECT_EQ(a.specific_force_g.z, -1.0);  // 1 g up, sensor z points down at 0 deg
  EXPECT_EQ(b.specific_force_g.z, 1.0);
  EXPECT_EQ(a.table_axis.y, 1.0);
  EXPECT_EQ(a.table_axis.x, 0.0);    // no table rate along the sensitive axis
  const auto q = terms_at(g, 90.0);  // half-way: x points up (right-handed turn about east)
  EXPECT_NEAR(q.earth_dps.x, w_e * std::sin(42.6 * pi / 180.0), 1e-12);
}

TEST(Geometry, VerticalAxisAndErrors) {
  const auto g = rig_geometry::make(42.6, "up", "").value();
  EXPECT_NEAR(terms_at(g, 0.0).earth_dps.x, w_e * std::sin(42.6 * pi / 180.0), 1e-12);
  EXPECT_EQ(terms_at(g, 0.0).specific_force_g.x, 1.0);  // gravity along s: paper Fig. 1
  EXPECT_EQ(terms_at(g, 180.0).specific_force_g.x, -1.0);
  EXPECT_FALSE(rig_geometry::make(42.6, "north", "north").ok());
  EXPECT_FALSE(rig_geometry::make(95.0, "north", "").ok());
}

TEST(Profiles, SpecsAndCsv) {
  auto r = profile::parse_rate("steps:10:5,20:-5").value();
  EXPECT_EQ(r.at(5.0), 0.0);
  EXPECT_EQ(r.at(10.0), 5.0);
  EXPECT_EQ(r.at(25.0), -5.0);
  auto s = profile::parse_rate("sine:2:0.5").value();
  EXPECT_NEAR(s.at(0.5), 2.0, 1e-12);
  EXPECT_EQ(profile::parse_rate("7.5").value().at(3.0), 7.5);
  EXPECT_FALSE(profile::parse_rate("wobble:1").ok());
  EXPECT_FALSE(profile::parse_rate("steps:10:5,5:1").ok());
  auto ramp = profile::parse_temperature("ramp:20:4:100").value();
  EXPECT_NEAR(ramp.at(50.0), 12.0, 1e-12);
  EXPECT_EQ(ramp.at(500.0), 4.0);
  auto fridge = profile::parse_temperature("fridge:4:2:600").value();
  EXPECT_NEAR(fridge.at(0.0), 5.0, 1e-12);
  EXPECT_NEAR(fridge.at(300.0), 3.0, 1e-12);
  auto csv = profile::table({0.0, 10.0}, {20.0, 10.0}).value();
  EXPECT_NEAR(csv.at(5.0), 15.0, 1e-12);
  EXPECT_EQ(csv.at(50.0), 10.0);
  EXPECT_EQ(profile::table({5.0, 5.0}, {1.0, 2.0}).err().message,
            "profile table row 2: time must increase");
  EXPECT_FALSE(profile::table({}, {}));
  EXPECT_TRUE(profile::is_temperature_spec("fridge:4:2:600"));
  EXPECT_TRUE(profile::is_temperature_spec("-3.5"));
  EXPECT_FALSE(profile::is_temperature_spec("lab_temps.csv"));
}

TEST(Profiles, FillIsBitIdenticalToAtForEveryKind) {
  // The simulator evaluates profiles one block at a time (fill), tests and headers call at():
  // both must give the same bits, across piece boundaries and across blocks.
  const std::vector<std::string> rates = {"2.5", "steps:0.3:5,0.71:-5,2:1", "sine:2:3:0.5"};
  const std::vector<std::string> temps = {"-0", "steps:0.5:4,1.5:30", "ramp:20:4:1.3",
                                          "fridge:4:2:0.37"};
  std::vector<profile> all;
  all.reserve(rates.size() + temps.size() + 1);
  for (const auto& r : rates) all.push_back(profile::parse_rate(r).value());
  for (const auto& t : temps) all.push_back(profile::parse_temperature(t).value());
  all.push_back(profile::table({0.2, 0.9, 1.1}, {20.0, 10.0, 12.0}).value());
  const std::size_t n = 1500;  // 3 s at 500 Hz: many pieces of each kind
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = (static_cast<double>(k) + 0.5) * 1.99886e-3;
  for (auto& p : all) {
    profile by_block = p;
    std::vector<double> v(n);
    by_block.fill(t.data(), v.data(), 700);  // two blocks, as the simulator fills them
    by_block.fill(t.data() + 700, v.data() + 700, n - 700);
    for (std::size_t k = 0; k < n; ++k) {
      const double want = p.at(t[k]);
      ASSERT_EQ(std::signbit(v[k]), std::signbit(want)) << k;
      ASSERT_EQ(v[k], want) << k;
    }
  }
  // The triangle against its closed form MEAN + A (1 - 4 phase) / MEAN + A (4 phase - 3).
  auto fridge = profile::parse_temperature("fridge:4:2:0.37").value();
  for (std::size_t k = 0; k < n; ++k) {
    const double ph = t[k] / 0.37 - std::floor(t[k] / 0.37);
    const double want = 4.0 + (ph < 0.5 ? 1.0 - 4.0 * ph : 4.0 * ph - 3.0);
    EXPECT_NEAR(fridge.at(t[k]), want, 1e-12) << t[k];
  }
}

TEST(Turntable, DefaultTurnAndTriangleProfile) {
  const auto t = turn_profile::make(stepper_params{}, 180.0).value();
  EXPECT_EQ(t.n_steps(), 100.0);
  EXPECT_NEAR(t.duration_s(), 0.300, 1e-12);  // 0.1 s ramp up, 40 steps at 400/s, 0.1 s down
  double prev = 0.0;
  for (double s = 0.0; s <= 0.31; s += 0.001) {
    const double a = t.angle_at(s);
    EXPECT_GE(a, prev);
    prev = a;
  }
  EXPECT_EQ(t.angle_at(1.0), 180.0);
  const auto tri = turn_profile::make({200, 100.0, 10000.0, 1000.0}, 18.0).value();  // 10 steps
  EXPECT_NEAR(tri.angle_at(tri.duration_s() / 2.0), 9.0, 1e-9);                      // symmetric
  EXPECT_FALSE(turn_profile::make(stepper_params{}, 1.0).ok());  // not whole steps
}

TEST(Ad7739, ConversionTimeCodesAndClipping) {
  ad7739_config c;
  EXPECT_NEAR(conversion_time_s(c), (128.0 * 94 + 249) / 6.144e6, 1e-15);  // 1.99886 ms
  c.filter_word = 127;
  EXPECT_NEAR(conversion_time_s(c), 2.686e-3, 1e-6);  // FACTS §5 [U]
  c.chop = false;
  c.filter_word = 3;
  EXPECT_NEAR(conversion_time_s(c), 64.8e-6, 0.1e-6);
  ad7739_config quiet;
  quiet.noise_uv_rms_at_2ms = 0.0;
  auto adc = ad7739::make(quiet, 1).value();
  EXPECT_NEAR(adc.lsb_v(), 5.0 / 16777216.0, 1e-20);
  EXPECT_EQ(adc.convert(3.0), ad7739::code_max);
  EXPECT_EQ(adc.convert(-3.0), 0);
  for (const double v : {0.0, 1e-6, -0.123456789, 2.4}) {
    EXPECT_NEAR(adc.volts(adc.convert(v)), v, adc.lsb_v() / 2.0 + 1e-18);
  }
  auto noisy = ad7739::make(ad7739_config{}, 5).value();
  double s2 = 0.0;
  for (int i = 0; i < 100000; ++i) {
    const double e = noisy.volts(noisy.convert(0.1)) - 0.1;
    s2 += e * e;
  }
  EXPECT_NEAR(std::sqrt(s2 / 100000.0), 2e-6 * std::sqrt(2e-3 / noisy.conversion_time_s()),
              0.05e-6);
  ad7739_config fw1;
  fw1.filter_word = 1;  // below the part's FW range
  EXPECT_FALSE(ad7739::make(fw1, 1).ok());
}

TEST(Ad7739, BlockIsBitIdenticalToPerConversion) {
  for (const bool chop : {true, false}) {  // without chop an offset is added
    ad7739_config c;
    c.chop = chop;
    auto adc = ad7739::make(c, 3).value();
    const std::size_t n = 20000;
    std::vector<double> v(n), noise(n), out(n);
    sensor::normal_stream g(8, sensor::stream::user);
    for (std::size_t i = 0; i < n; ++i) {
      v[i] = 3.0 * g.next();  // ~40 % beyond +-2.5 V: both end codes
      noise[i] = g.next();
    }
    v[0] = 2.5;  // the edges exactly
    v[1] = -2.5;
    adc.convert_block(v.data(), noise.data(), out.data(), 80.0, n);  // 1 / (12.5 mV/(deg/s))
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(out[i], adc.volts(adc.convert(v[i], noise[i])) * 80.0);
    }
  }
}

TEST(Schedule, PaperCycleOfAbout179Seconds) {
  const double tc = conversion_time_s(ad7739_config{});
  const auto s = schedule::make(schedule_params{}, stepper_params{}, tc).value();
  EXPECT_EQ(s.phases().size(), 2U * (256 + 151 + 41));
  EXPECT_NEAR(s.cycle_s(), 1.79, 0.005);  // paper section 4
  int a = 0, b = 0, moving = 0;
  for (const auto& p : s.phases()) {
    a += p.dwell == 0;
    b += p.dwell == 1;
    moving += p.moving;
    if (p.dwell >= 0) {
      EXPECT_FALSE(p.moving);
    }
  }
  EXPECT_EQ(a, 256);
  EXPECT_EQ(b, 256);
  EXPECT_EQ(moving, 2 * 151);
  schedule_params same{};
  same.settle_s = 0.1;
  same.pos_a_deg = same.pos_b_deg = 0.0;
  EXPECT_FALSE(schedule::make(same, stepper_params{}, tc).ok());
}

// A noiseless sensor so that the flip algebra can be checked to ADC precision.
simulation_config noiseless(double duration_s, const char* preset = "adxrs150") {
  simulation_config c;
  c.sensor = sensor::find_builtin(preset)->params;
  c.sensor.arw_dps_rthz = 0.0;
  c.sensor.bias_instability_dps = 0.0;
  c.sensor.rrw_dps_per_rts = 0.0;
  c.sensor.turn_on_bias_sigma_dps = 0.0;
  c.sensor.warmup_amplitude_dps = 0.0;
  c.sensor.g_sens_turn_on_sigma_dps_per_g = c.sensor.g_sens_tc_turn_on_sigma_dps_per_g_c = 0.0;
  c.sensor.nonlinearity_fs = 0.0;
  c.sensor.bias_dps = 0.25;
  c.adc.noise_uv_rms_at_2ms = 0.0;
  c.duration_s = duration_s;
  return c;
}

std::vector<dwell_row> dwells(const simulation_config& c) {
  auto sim = simulator::make(c).value();
  sample_block b(5000);
  dwell_averager avg(c.rig.n_avg);
  std::vector<dwell_row> rows;
  while (sim.fill(b) > 0) avg.add(b, rows);
  return rows;
}

TEST(Simulator, EarthAndGTermsFlipBiasDoesNot) {
  auto c = noiseless(30.0);
  c.sensor.warmup_amplitude_dps = 0.3;  // a moving bias, which must not flip
  const auto rows = dwells(c);
  ASSERT_GE(rows.size(), 30U);
  const double dn = 0.39522;
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    EXPECT_EQ(rows[i].angle_deg, 0.0);
    EXPECT_EQ(rows[i + 1].angle_deg, 180.0);
    EXPECT_NEAR(rows[i].g_term_dps + rows[i].earth_dps, dn, 1e-5);
    EXPECT_NEAR(rows[i + 1].g_term_dps, -rows[i].g_term_dps, 1e-12);
    EXPECT_NEAR(rows[i + 1].earth_dps, -rows[i].earth_dps, 1e-12);
    EXPECT_GT(rows[i].bias_dps, 0.25);
    EXPECT_GT(rows[i + 1].bias_dps, 0.25);  // same sign at both positions
    EXPECT_NEAR(rows[i + 1].bias_dps, rows[i].bias_dps, 0.01);
  }
}

TEST(Simulator, FlipHalfDifferenceRecoversDeltaNAndHalfSumTheBias) {
  const auto rows = dwells(noiseless(20.0));
  const double sf_err = 0.0;  // preset is nominal
  for (std::size_t i = 0; i + 1 < rows.size(); i += 2) {
    const double r = (rows[i].rate_dps - rows[i + 1].rate_dps) / 2.0;
    const double c = (rows[i].rate_dps + rows[i + 1].rate_dps) / 2.0;
    // Cross-axis (2 %) sees no table rate while dwelling; ADC LSB = 2.4e-5 deg/s.
    EXPECT_NEAR(r, 0.39522 * (1.0 + sf_err), 2e-5);
    EXPECT_NEAR(c, 0.25, 2e-5);
  }
}

// The settle residual (issue 32): the table's move when the coils are released before a dwell
// (an assumed 0.1 step against the turn, 5 ms) and its ring-down after the last step (0.2 step,
// 60 Hz, 10 ms) are sensed through the gyro's cross-axis sensitivity to the table's rate. With
// back-and-forth turns and the coils released 0.2 ms before the first conversion (the firmware
// before issue 32), the release's whole move falls in the dwell (the gyro's 18-Hz output filter
// delays the 0.2 ms that came before) with opposite signs at A and B: r, and so dN, is off by
// c_y x 0.18 deg / T_dwell (the HZ1-90-100A: 3.5e-3 deg/s, more than its dN of 3.1e-3). Released
// halfway through the 80 ms of settling (the firmware now), what reaches the dwell is the filter's
// memory of a move that ended ~35 ms before, 2.2 % of it; turning one way, r is as without it and
// c (the bias) takes the move instead.
TEST(Simulator, TheSettleResidualEntersDeltaNOnlyWhenReleasedAtTheDwellAndTurningBack) {
  const auto case_rc = [](double release_before_s, bool one_way, bool settle_on) {
    auto c = noiseless(40.0, "hz1-90-100a");
    c.sensor.bias_dps = 0.0;
    c.rig.one_way = one_way;
    if (settle_on) c.settle = {0.36, 60.0, 0.010, 0.18, 0.005};
    c.release_before_dwell_s = release_before_s;
    const auto rows = dwells(c);
    double r = 0.0, bias = 0.0;
    int n = 0;
    for (std::size_t i = 2; i + 1 < rows.size(); i += 2, ++n) {  // from the second cycle
      r += (rows[i].rate_dps - rows[i + 1].rate_dps) / 2.0;
      bias += (rows[i].rate_dps + rows[i + 1].rate_dps) / 2.0;
    }
    return std::pair<double, double>{r / n, bias / n};
  };
  const double t_dwell = 256 * 1.99886e-3;
  const double cy = sensor::find_builtin("hz1-90-100a")->params.cross_axis_y;
  const double move = cy * 0.18 / t_dwell;  // deg/s
  const auto base = case_rc(-1.0, false, false);
  const auto old = case_rc(0.0002, false, true);
  const auto now = case_rc(-1.0, false, true);
  const auto base_1w = case_rc(-1.0, true, false);
  const auto old_1w = case_rc(0.0002, true, true);
  EXPECT_NEAR(old.first - base.first, move, 0.03 * move);
  EXPECT_NEAR(old.second - base.second, 0.0, 1e-3 * move);
  EXPECT_LT(std::abs(now.first - base.first), 0.03 * move);
  EXPECT_NEAR(old_1w.first - base_1w.first, 0.0, 1e-3 * move);
  EXPECT_NEAR(std::abs(old_1w.second - base_1w.second), move, 0.03 * move);
  std::printf(
      "settle residual in dN (HZ1-90-100A, c_y %.3f): released 0.2 ms before the dwell "
      "%.3g deg/s (back and forth), halfway through settling %.3g, one way %.3g; dN %.4g\n",
      cy, old.first - base.first, now.first - base.first, old_1w.first - base_1w.first, base.first);
}

TEST(Simulator, RateTableInputReversesAndTemperatureMovesG) {
  auto c = noiseless(10.0);
  c.rate = profile::constant(10.0);
  c.sensor = sensor::find_builtin("hz1-90-100a")->params;
  c.sensor.arw_dps_rthz = c.sensor.bias_instability_dps = c.sensor.rrw_dps_per_rts = 0.0;
  c.sensor.turn_on_bias_sigma_dps = c.sensor.warmup_amplitude_dps = 0.0;
  c.sensor.g_sens_turn_on_sigma_dps_per_g = c.sensor.g_sens_tc_turn_on_sigma_dps_per_g_c = 0.0;
  c.temperature = profile::constant(4.0);
  const auto rows = dwells(c);
  ASSERT_GE(rows.size(), 4U);
  EXPECT_EQ(rows[0].input_dps, 10.0);
  EXPECT_EQ(rows[1].input_dps, -10.0);
  EXPECT_NEAR(rows[0].g_term_dps + rows[0].earth_dps, 0.00381, 2e-5);  // paper Tab. 3, ~4 C
}

TEST(Simulator, TruthOffKeepsTheRecordingAndDwellMeansAreSequentialSums) {
  auto c = noiseless(40.0);
  c.sensor = sensor::find_builtin("adxrs150")->params;  // every noise term on
  c.temperature = profile::parse_temperature("fridge:4:2:7").value();
  auto with = simulator::make(c).value();
  auto without = simulator::make(c).value();
  sample_block a(333);  // dwells split across blocks
  sample_block b(333, false);
  dwell_averager avg_a(c.rig.n_avg), avg_b(c.rig.n_avg);
  std::vector<dwell_row> rows_a, rows_b;
  // Reference means: plain sums in conversion order, then one division (the averager's own).
  std::vector<double> sum(7, 0.0);
  std::vector<dwell_row> want;
  int count = 0;
  std::int64_t current = -1;
  while (with.fill(a) > 0) {
    ASSERT_EQ(without.fill(b), a.size);
    for (std::size_t i = 0; i < a.size; ++i) {
      ASSERT_EQ(a.time_s[i], b.time_s[i]);
      ASSERT_EQ(a.rate_dps[i], b.rate_dps[i]);
      ASSERT_EQ(a.temp_c[i], b.temp_c[i]);
      ASSERT_EQ(a.dwell[i], b.dwell[i]);
      ASSERT_EQ(std::isnan(a.angle_deg[i]), std::isnan(b.angle_deg[i]));
      if (a.dwell[i] != current) {
        sum.assign(7, 0.0);
        count = 0;
        current = a.dwell[i];
      }
      if (current < 0) continue;
      const double v[7] = {a.time_s[i],     a.rate_dps[i],  a.temp_c[i],   a.bias_dps[i],
                           a.g_term_dps[i], a.earth_dps[i], a.input_dps[i]};
      for (int j = 0; j < 7; ++j) sum[static_cast<std::size_t>(j)] += v[j];
      if (++count == c.rig.n_avg) {
        const double inv = 1.0 / count;
        want.push_back({sum[0] * inv, a.angle_deg[i], sum[1] * inv, sum[2] * inv, count,
                        sum[3] * inv, sum[4] * inv, sum[5] * inv, sum[6] * inv});
      }
    }
    avg_a.add(a, rows_a);
    avg_b.add(b, rows_b);
  }
  ASSERT_EQ(rows_a.size(), want.size());
  ASSERT_EQ(rows_b.size(), want.size());
  for (std::size_t r = 0; r < want.size(); ++r) {
    for (const auto& got : {rows_a[r], rows_b[r]}) {
      EXPECT_EQ(got.time_s, want[r].time_s);
      EXPECT_EQ(got.rate_dps, want[r].rate_dps);
      EXPECT_EQ(got.temp_c, want[r].temp_c);
      EXPECT_EQ(got.angle_deg, want[r].angle_deg);
      EXPECT_EQ(got.n_avg, c.rig.n_avg);
    }
    EXPECT_EQ(rows_a[r].bias_dps, want[r].bias_dps);
    EXPECT_EQ(rows_a[r].g_term_dps, want[r].g_term_dps);
    EXPECT_EQ(rows_a[r].earth_dps, want[r].earth_dps);
    EXPECT_EQ(rows_a[r].input_dps, want[r].input_dps);
    EXPECT_TRUE(std::isnan(rows_b[r].bias_dps));  // no truth, no truth means
  }
}

TEST(Simulator, RawBlocksMarkTurnsAndDwells) {
  auto c = noiseless(2.0);
  auto sim = simulator::make(c).value();
  sample_block b(1000);
  ASSERT_EQ(sim.fill(b), 1000U);
  EXPECT_EQ(b.dwell[0], 0);
  EXPECT_EQ(b.dwell[255], 0);
  EXPECT_EQ(b.dwell[256], -1);
  EXPECT_TRUE(std::isnan(b.angle_deg[300]));     // turning
  EXPECT_EQ(b.angle_deg[256 + 151 + 5], 180.0);  // settling: at the new position
  EXPECT_EQ(b.dwell[448], 1);
  EXPECT_NEAR(b.time_s[0], 0.5 * sim.conversion_time_s(), 1e-15);
  EXPECT_EQ(sim.total_samples(), static_cast<std::uint64_t>(2.0 / sim.conversion_time_s()));
}

// The coils' heat (simulator.hpp, coil_heating): energised all the time (hold), the gyro's
// temperature follows the first-order step T0 + rise (1 - exp(-t / tau)); energised only while
// turning and settling (the device's default), the rise settles at rise times that share of the
// cycle. The g-term follows the temperature, so the effect shows in dN: with the HZ1-90-100A's
// g-sensitivity tempco (paper Tab. 3) a rise of 2 degC moves dN by 9e-5 deg/s, 3 % of dN.
TEST(Simulator, CoilHeatWarmsTheGyroWhileTheCoilsAreOn) {
  auto c = noiseless(3.0 * 600.0, "hz1-90-100a");
  c.coil = {2.0, 300.0};
  const double t0 = 20.0;
  c.temperature = profile::constant(t0);
  c.rig.hold_coils = true;
  const auto held = dwells(c);
  c.rig.hold_coils = false;
  const auto released = dwells(c);
  ASSERT_GT(held.size(), 1000U);
  ASSERT_EQ(held.size(), released.size());
  auto sim = simulator::make(c).value();
  const double dwell_s = c.rig.n_avg * sim.conversion_time_s();
  const double on_share = 1.0 - 2.0 * dwell_s / sim.sched().cycle_s();
  ASSERT_GT(on_share, 0.05);
  ASSERT_LT(on_share, 0.6);
  for (std::size_t i = 0; i < held.size(); i += 97) {
    // A dwell's mean of the exponential, within its half-length's curvature.
    const double want = t0 + 2.0 * -std::expm1(-held[i].time_s / 300.0);
    EXPECT_NEAR(held[i].temp_c, want, 2e-3) << "dwell " << i;
    EXPECT_NEAR(held[i].g_term_dps, (i % 2 == 0 ? 1 : -1) * sim.g_term_at_a_dps(held[i].temp_c),
                1e-9);
  }
  // After 6 time constants: held at the full rise; released at the coils' share of it (the
  // ripple over one cycle is rise x cycle / tau at most).
  const auto& last_held = held.back();
  const auto& last_released = released.back();
  EXPECT_NEAR(last_held.temp_c - t0, 2.0, 0.01);
  EXPECT_NEAR(last_released.temp_c - t0, 2.0 * on_share, 2.0 * sim.sched().cycle_s() / 300.0);
  EXPECT_LT(last_released.temp_c - t0, 0.7 * (last_held.temp_c - t0));
  // dN moves with it: the g-term's change is gf1 x the rise (none without a heat path).
  const double dn_shift = sim.g_term_at_a_dps(last_held.temp_c) - sim.g_term_at_a_dps(t0);
  EXPECT_NEAR(std::abs(dn_shift), 4.5e-5 * (last_held.temp_c - t0), 1e-9);  // 1 g along the axis
  c.coil = {};
  const auto cold = dwells(c);
  EXPECT_EQ(cold.back().temp_c, t0);
  auto bad = c;
  bad.coil.rise_c = -1.0;
  EXPECT_FALSE(simulator::make(bad).ok());
}

}  // namespace
}  // namespace gyroflip::rig
