// One rig configuration (issue 20): the simulator's, the emulator's and the recorder's settings
// are rig::rig_config, whose defaults are the device's CONFIGURE defaults and whose check is the
// device's own rule with a message per field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/protocol/budget.hpp"
#include "gyroflip/rig/rig_config.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::rig {
namespace {

TEST(RigConfig, DefaultsAreTheDevicesDefaults) {
  // Today's disagreement the review found (a start rate of 100 in one place, 200 in another)
  // cannot come back: the defaults are one set.
  const rig_config c;
  EXPECT_TRUE(c.check());
  EXPECT_EQ(c.to_configure(), protocol::configure_msg{});
  const auto back = rig_config::from_configure(protocol::configure_msg{});
  ASSERT_TRUE(back) << back.err().message;
  EXPECT_EQ(back->to_configure(), protocol::configure_msg{});
  // The simulator's pieces from the same value.
  EXPECT_EQ(c.stepper().start_rate_sps, 200.0);
  EXPECT_EQ(c.stepper().max_rate_sps, 400.0);
  EXPECT_EQ(c.schedule(true).pos_b_deg, 180.0);
  EXPECT_FALSE(c.schedule(true).one_way);
}

TEST(RigConfig, AnAngleTableRoundTripsThroughConfigure) {
  rig_config c;
  c.positions_deg = {0.0, 90.0, 180.0, 270.0, 45.5};
  c.steps_per_rev = 720;  // 0.5-deg steps
  c.n_avg = 512;
  c.n_temp = 8;
  c.settle_s = 0.123;
  c.start_rate_sps = 150;
  c.max_rate_sps = 900;
  c.accel_sps2 = 5000;
  c.filter_word = 127;
  c.chop = false;
  c.one_way = c.home = c.hold_coils = c.raw = true;
  c.status_period_s = 2.5;
  c.flip_motor = 1;
  c.other_motor = protocol::other_motor::opposite;
  c.gyro_channel = 2;
  c.temp_channel = 3;
  ASSERT_TRUE(c.check()) << c.check().err().message;
  const protocol::configure_msg m = c.to_configure();
  EXPECT_EQ(m.n_positions, 5);
  EXPECT_EQ(m.pos_steps[1], 180);
  EXPECT_EQ(m.pos_steps[4], 91);
  EXPECT_EQ(m.pos_cdeg[4], 4550);
  EXPECT_EQ(m.settle_ms, 123);
  EXPECT_EQ(m.status_period_ms, 2500);
  EXPECT_EQ(m.flags, protocol::cfg_one_way | protocol::cfg_home | protocol::cfg_hold_coils |
                         protocol::cfg_raw);
  const auto back = rig_config::from_configure(m);
  ASSERT_TRUE(back) << back.err().message;
  EXPECT_EQ(back->to_configure(), m);
  EXPECT_EQ(back->positions_deg, c.positions_deg);
  // A table whose steps do not stand for its angles is refused.
  protocol::configure_msg bad = m;
  bad.pos_steps[2] = 17;
  EXPECT_FALSE(rig_config::from_configure(bad));
}

// Each broken rule is named by its field (a front end maps it to its option).
TEST(RigConfig, EachRuleNamesItsField) {
  const auto field_of = [](rig_config c) {
    const status s = c.check();
    return s ? std::string("ok") : s.err().parameter + ": " + s.err().message;
  };
  const auto with = [](auto f) {
    rig_config c;
    f(c);
    return c;
  };
  EXPECT_EQ(field_of(with([](rig_config& c) { c.n_avg = 0; })).rfind("n_avg:", 0), 0u);
  EXPECT_EQ(field_of(with([](rig_config& c) { c.n_avg = 70000; })).rfind("n_avg:", 0), 0u);
  EXPECT_EQ(field_of(with([](rig_config& c) { c.n_temp = 65; })).rfind("n_temp:", 0), 0u);
  EXPECT_EQ(field_of(with([](rig_config& c) { c.settle_s = 0.0805; })).rfind("settle_s:", 0), 0u);
  EXPECT_EQ(
      field_of(with([](rig_config& c) { c.start_rate_sps = 500; })).rfind("start_rate_sps:", 0),
      0u);
  EXPECT_EQ(field_of(with([](rig_config& c) { c.max_rate_sps = 6000; })).rfind("max_rate_sps:", 0),
            0u);
  EXPECT_EQ(field_of(with([](rig_config& c) { c.filter_word = 1; })).rfind("filter_word:", 0), 0u);
  EXPECT_EQ(field_of(with([](rig_config& c) { c.temp_channel = 0; })).rfind("gyro_channel:", 0),
            0u);
  const std::string not_step = field_of(with([](rig_config& c) {
    c.positions_deg = {0.0, 181.0};
  }));
  EXPECT_NE(not_step.find("positions_deg: position 1 at 181 deg is not a whole number of the "
                          "table's 1.8-deg steps"),
            std::string::npos)
      << not_step;
  EXPECT_NE(field_of(with([](rig_config& c) {
              c.positions_deg = {0.0, 0.0};
            })).find("would not turn"),
            std::string::npos);
  EXPECT_NE(field_of(with([](rig_config& c) { c.positions_deg = {0.0}; })).find("2 to 8"),
            std::string::npos);
  EXPECT_NE(field_of(with([](rig_config& c) {
              c.positions_deg = {0.0, 360.0};
            })).find("[0, 360)"),
            std::string::npos);
  EXPECT_EQ(field_of(with([](rig_config& c) {
              c.positions_deg = {0.0, 90.0};
              c.compensate = true;
            })).rfind("compensate:", 0),
            0u);
  // RAW of every conversion with 1-conversion dwells and 1-step turns: beyond the link.
  const std::string link = field_of(with([](rig_config& c) {
    c.raw = true;
    c.n_avg = 1;
    c.settle_s = 0;
    c.steps_per_rev = 360;
    c.positions_deg = {0.0, 1.0};
    c.max_rate_sps = c.start_rate_sps = 5000;
  }));
  EXPECT_NE(link.find("beyond the link's 11520 B/s"), std::string::npos) << link;
}

// The host's check accepts exactly what the device accepts (protocol::check_configure), over
// configurations drawn at random around the limits.
TEST(RigConfig, AcceptsWhatTheDeviceAccepts) {
  std::uint64_t x = 88172645463325252ULL;
  const auto next = [&x](int lo, int hi) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return lo + static_cast<int>(x % static_cast<std::uint64_t>(hi - lo + 1));
  };
  int accepted = 0;
  for (int k = 0; k < 20000; ++k) {
    rig_config c;
    c.n_avg = next(0, 300);
    c.n_temp = next(0, 70);
    c.settle_s = next(0, 100) / 1000.0;
    c.steps_per_rev = 2 * next(2, 200);
    c.max_rate_sps = next(1, 5200);
    c.start_rate_sps = next(1, 5200);
    c.accel_sps2 = next(1, 65535);
    c.filter_word = next(1, 128);
    c.raw = next(0, 1) == 1;
    c.compensate = next(0, 3) == 0;
    c.positions_deg = {0.0, 360.0 * next(1, c.steps_per_rev - 1) / c.steps_per_rev};
    if (std::abs(c.positions_deg[1] * 100.0 - std::round(c.positions_deg[1] * 100.0)) > 1e-6)
      continue;  // not representable in hundredths: a host-side rule only
    const bool host = static_cast<bool>(c.check());
    const bool device =
        protocol::check_configure(c.to_configure(), 6144000) == protocol::status::ok;
    ASSERT_EQ(host, device) << k;
    accepted += host ? 1 : 0;
  }
  EXPECT_GT(accepted, 1000);  // both sides of the rule were exercised
}

// The simulator turns as the device does: back from B by default, on to A with one_way.
TEST(RigConfig, TheSimulatorTurnsBackOrOneWayAsConfigured) {
  simulation_config c;
  c.sensor = sensor::find_builtin("adxrs150")->params;
  c.duration_s = 4.0;
  const auto rates = [](const simulation_config& cfg) {
    auto sim = simulator::make(cfg).value();
    double first_turn = 0.0, second_turn = 0.0;
    bool in_b = false;
    for (const auto& p : sim.sched().phases()) {
      if (p.dwell == 1) in_b = true;
      (in_b ? second_turn : first_turn) += p.table_rate_dps;
    }
    return std::pair{first_turn, second_turn};
  };
  const auto back = rates(c);
  EXPECT_GT(back.first, 0.0);
  EXPECT_NEAR(back.second, -back.first, 1e-9);
  c.rig.one_way = true;
  const auto on = rates(c);
  EXPECT_NEAR(on.second, on.first, 1e-9);
  // Three positions are swept (issue 33); a table the device refuses (9 positions) is refused.
  c.rig.positions_deg = {0.0, 90.0, 180.0};
  EXPECT_TRUE(simulator::make(c));
  c.rig.positions_deg = {0.0, 36.0, 72.0, 108.0, 144.0, 180.0, 216.0, 252.0, 288.0};
  EXPECT_FALSE(simulator::make(c));
  c.rig.positions_deg = {0.0, 180.0};
  c.rig.n_avg = 0;
  const auto e = simulator::make(c);
  ASSERT_FALSE(e);
  EXPECT_EQ(e.err().parameter, "n_avg");
}

// record --order (issue 33 item 2): the visiting order is written into the device's angle table.
// There and back is 0..N-1..1, a table the device accepts (consecutive entries differ, at most 8)
// whose positions are found again by angle (position_table::of_visits: N positions, entry k at
// its angle's index); within a period every position's visits are centred alike (mod the period),
// so a bias linear in time enters each position's mean alike over whole periods.
TEST(RigConfig, ADevicesVisitingOrderIsItsAngleTable) {
  using v = std::vector<double>;
  const auto visits = [](const v& p, device_order o, bool one_way = false) {
    auto r = device_visits(p, o, one_way);
    return r ? *r : v{-1.0};
  };
  EXPECT_EQ(visits({0, 90, 180, 270}, device_order::automatic), (v{0, 90, 180, 270, 180, 90}));
  EXPECT_EQ(visits({0, 72, 144, 216, 288}, device_order::there_and_back),
            (v{0, 72, 144, 216, 288, 216, 144, 72}));
  EXPECT_EQ(visits({0, 120, 240}, device_order::automatic), (v{0, 120, 240, 120}));
  // Two positions stay the paper's cycle; cycle, one-way turns and six positions take the table.
  EXPECT_EQ(visits({0, 180}, device_order::automatic), (v{0, 180}));
  EXPECT_EQ(visits({0, 90, 180, 270}, device_order::cycle), (v{0, 90, 180, 270}));
  EXPECT_EQ(visits({0, 90, 180, 270}, device_order::automatic, true), (v{0, 90, 180, 270}));
  EXPECT_EQ(visits({0, 60, 120, 180, 240, 300}, device_order::automatic),
            (v{0, 60, 120, 180, 240, 300}));
  // A visiting order given as the table is taken as written, except by there-and-back.
  EXPECT_EQ(visits({0, 90, 180, 90}, device_order::automatic), (v{0, 90, 180, 90}));
  EXPECT_FALSE(device_visits({0, 90, 180, 90}, device_order::there_and_back, false));
  EXPECT_FALSE(device_visits({0, 90, 180, 270}, device_order::there_and_back, true));
  EXPECT_FALSE(device_visits({0, 60, 120, 180, 240, 300}, device_order::there_and_back, false));
  for (std::size_t n = 3; n <= 5; ++n) {
    v p;
    for (std::size_t k = 0; k < n; ++k) p.push_back(static_cast<double>(36 * k));
    rig_config c;
    c.positions_deg = visits(p, device_order::there_and_back);
    ASSERT_EQ(c.positions_deg.size(), 2 * n - 2);
    EXPECT_TRUE(c.check()) << n;
    const auto m = c.to_configure();
    EXPECT_EQ(protocol::check_configure(m, 6'144'000), protocol::status::ok) << n;
    const position_table t = c.table();
    ASSERT_EQ(t.size(), n);
    // Each position's visits within a period of P = 2N - 2 dwells, centred on N - 1 (mod P):
    // entry k and entry P - k; the first at 0 = P, the last at N - 1.
    const std::size_t period = c.positions_deg.size();
    std::vector<double> sum(n, 0.0), count(n, 0.0);
    for (std::size_t k = 0; k < period; ++k) {
      const auto i = t.index_of(c.positions_deg[k]);
      ASSERT_TRUE(i);
      sum[static_cast<std::size_t>(*i)] += static_cast<double>(k == 0 ? period : k);
      count[static_cast<std::size_t>(*i)] += 1.0;
    }
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(t.angle_deg(static_cast<int>(i)), p[i]);
      if (i == 0) continue;  // at 0 and P: centred on N - 1 only with the closing dwell
      EXPECT_DOUBLE_EQ(sum[i] / count[i], static_cast<double>(n - 1)) << n << " " << i;
    }
  }
}

}  // namespace
}  // namespace gyroflip::rig

namespace gyroflip::rig {
namespace {

// "Is this the method's pair?" has one rule (protocol::is_method_pair): the host's settings
// (rig_config, which simulate, emulate and record check) and the device's CONFIGURE check agree
// on every table, so on-board compensation is refused or taken alike on both sides. Tables
// chosen around the rule's edges: a swapped pair, a pair off 0, one step short of 180 deg, three
// positions holding a pair.
TEST(RigConfig, OnBoardCompensationTakesTheOnePairRuleOfTheDevice) {
  struct table {
    std::vector<double> deg;
    bool pair;
  };
  const std::vector<table> tables{{{0.0, 180.0}, true},        {{180.0, 0.0}, true},
                                  {{90.0, 270.0}, true},       {{271.8, 91.8}, true},
                                  {{0.0, 178.2}, false},       {{0.0, 90.0}, false},
                                  {{0.0, 180.0, 90.0}, false}, {{45.0, 225.0, 0.0}, false}};
  for (const auto& t : tables) {
    rig_config c;
    c.positions_deg = t.deg;
    c.compensate = true;
    const auto m = c.to_configure();
    EXPECT_EQ(protocol::is_method_pair(m), t.pair) << t.deg[0] << "," << t.deg[1];
    EXPECT_EQ(static_cast<bool>(c.check()), t.pair) << t.deg[0] << "," << t.deg[1];
    EXPECT_EQ(protocol::check_configure(m, 6'144'000) == protocol::status::ok, t.pair)
        << t.deg[0] << "," << t.deg[1];
  }
}

}  // namespace
}  // namespace gyroflip::rig
