// Positions as an index (issue 33): the table type, the 0/180 demodulators' pair rule, a CSV's
// table (its `# positions_deg:` line, `auto`: its distinct angles) checked in one place, rows at
// other positions passed over by the pairings with the numbers of the pair's rows alone.
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gyroflip/core/positions.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip {
namespace {

position_table table_of(std::vector<double> angles) {
  auto t = position_table::of_angles(angles);
  EXPECT_TRUE(t) << t.err().message;
  return t ? *t : position_table{};
}

TEST(PositionTable, AnglesChecksAndTheCircle) {
  const auto t = table_of({0, 90, 180, 270});
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t.positions()[3].index, 3);
  EXPECT_EQ(t.angle_deg(3), 270.0);
  EXPECT_EQ(t.index_of(270.0), 3);       // 270 is a position, not "-1"
  EXPECT_EQ(t.index_of(359.9, 0.2), 0);  // on the circle: 0.1 deg from 0
  EXPECT_FALSE(t.index_of(359.9).has_value());
  EXPECT_EQ(t.index_of(-90.0), 3);  // -90 is 270
  EXPECT_EQ(t.describe(), "0, 90, 180 and 270");
  EXPECT_EQ(t.describe(false), "0,90,180,270");
  EXPECT_FALSE(position_table::of_angles(std::vector<double>{0, 360}));
  EXPECT_FALSE(position_table::of_angles(std::vector<double>{0, 180, 0}));
  EXPECT_FALSE(position_table::of_angles(std::vector<double>(9, 1.0)));
  EXPECT_FALSE(position_table::of_angles(std::vector<double>{}));
  // A device's visiting order may repeat an angle: each once, in the order first visited.
  const auto v = position_table::of_visits(std::vector<double>{0, 180, 0, 180},
                                           std::vector<std::int32_t>{0, 100, 200, 300});
  ASSERT_TRUE(v);
  EXPECT_EQ(v->size(), 2u);
  EXPECT_EQ(v->positions()[1].steps, 100);
}

TEST(FlipPair, PlusIsThePositionNearestZeroMinusTheOneOpposite) {
  struct want_pair {
    std::vector<double> angles;
    int plus, minus;
  };
  for (const auto& w :
       {want_pair{{0, 180}, 0, 1}, want_pair{{180, 0}, 1, 0}, want_pair{{0, 90, 180, 270}, 0, 2},
        want_pair{{90, 270}, 0, 1}, want_pair{{270, 90}, 1, 0}, want_pair{{179.9, 359.9}, 1, 0},
        want_pair{{0.5, 180.5}, 0, 1}, want_pair{{45, 100, 225}, 0, 2}}) {
    const auto p = method::flip_pair_of(table_of(w.angles), "t");
    ASSERT_TRUE(p) << p.err().message;
    EXPECT_EQ(p->plus, w.plus) << fmt::format("{}", fmt::join(w.angles, ","));
    EXPECT_EQ(p->minus, w.minus) << fmt::format("{}", fmt::join(w.angles, ","));
  }
  const auto none = method::flip_pair_of(table_of({0, 90}), "t.csv");
  ASSERT_FALSE(none);
  EXPECT_NE(none.err().message.find("hold none 180 deg from 0 deg"), std::string::npos)
      << none.err().message;
  const auto one = method::flip_pair_of(table_of({0}), "t.csv");
  ASSERT_FALSE(one);
  EXPECT_NE(one.err().message.find("the table never turns"), std::string::npos);
}

// A rig run's table is its CONFIGURE's, and a dwell's row carries its index there: 270 deg is
// position 3 of 0/90/180/270 (before, a dwell off 0 and 180 gave no row).
TEST(RigTable, ConfigureToRowIndices) {
  protocol::configure_msg c;
  c.n_positions = 4;
  const std::uint16_t cdeg[] = {0, 9000, 18000, 27000};
  const std::int16_t steps[] = {0, 50, 100, 150};
  for (int i = 0; i < 4; ++i) {
    c.pos_cdeg[i] = cdeg[i];
    c.pos_steps[i] = steps[i];
  }
  const auto table = rigdata::table_of_configure(c);
  ASSERT_EQ(table.describe(), "0, 90, 180 and 270");
  EXPECT_EQ(table.positions()[3].steps, 150);
  for (int i = 0; i < 4; ++i) {
    rigdata::rig_dwell d;
    d.d.n = 256;
    d.d.position = static_cast<std::uint8_t>(i);
    d.angle_deg = cdeg[i] / 100.0;
    d.rate_dps = 0.1 * i;
    const auto r = rigdata::dwell_row(d, table);
    ASSERT_TRUE(r.has_value()) << i;
    EXPECT_EQ(r->position, i);
    EXPECT_EQ(r->n_avg, 256u);
  }
  // A visiting order that names an angle twice (0,180,0,180): each angle once.
  c.pos_cdeg[1] = 18000;
  c.pos_cdeg[2] = 0;
  c.pos_cdeg[3] = 18000;
  EXPECT_EQ(rigdata::table_of_configure(c).size(), 2u);
}

// A flip recording at the positions `angles` visited in turn, `per` rows a dwell.
std::string csv_of(const std::string& head, const std::vector<double>& angles, int dwells) {
  std::string s = head + "time_s,angle_deg,rate_dps,n_avg\n";
  for (int k = 0; k < dwells; ++k) {
    const double a = angles[static_cast<std::size_t>(k) % angles.size()];
    const double sign = a == 0.0 ? 1.0 : a == 180.0 ? -1.0 : 0.0;
    s += fmt::format("{},{},{},256\n", 0.9 * k, a, 0.3 * sign + 0.5 + 1e-4 * k + 1e-3 * (k % 7));
  }
  return s;
}

TEST(RecordingTable, ALineNamesTheTableAndRowsCarryItsIndices) {
  test::temp_dir d;
  const std::string f = d.file("four.csv");
  test::write_text(f, csv_of("# positions_deg: 0, 90, 180, 270\n", {0, 90, 180, 270}, 8));
  auto r = io::recording_reader::open(f);
  ASSERT_TRUE(r) << r.err().message;
  EXPECT_EQ(r->origin(), io::table_origin::line);
  EXPECT_EQ(r->positions(), table_of({0, 90, 180, 270}));
  std::vector<method::row> rows(16);
  const auto n = r->read(rows);
  ASSERT_TRUE(n) << n.err().message;
  ASSERT_EQ(*n, 8u);
  for (std::size_t k = 0; k < 8; ++k) EXPECT_EQ(rows[k].position, static_cast<int>(k % 4)) << k;
}

TEST(RecordingTable, AutoTakesTheDistinctAnglesAscendingNoLineThePair) {
  test::temp_dir d;
  const std::string f = d.file("inferred.csv");
  test::write_text(f, csv_of("# positions_deg: auto\n", {270, 0, 90, 180}, 8));
  auto r = io::recording_reader::open(f);
  ASSERT_TRUE(r) << r.err().message;
  EXPECT_EQ(r->origin(), io::table_origin::rows);
  EXPECT_EQ(r->positions(), table_of({0, 90, 180, 270}));
  std::vector<method::row> rows(8);
  ASSERT_TRUE(r->read(rows));
  EXPECT_EQ(rows[0].position, 3);
  EXPECT_EQ(rows[1].position, 0);
  // An old recording (0 and 180, no line) reads as the paper's table, 180 first or not.
  const std::string old = d.file("old.csv");
  test::write_text(old, csv_of("", {180, 0}, 6));
  auto o = io::recording_reader::open(old);
  ASSERT_TRUE(o);
  EXPECT_EQ(o->origin(), io::table_origin::pair_0_180);
  EXPECT_EQ(o->positions(), position_table::pair_0_180());
  ASSERT_TRUE(o->read(rows));
  EXPECT_EQ(rows[0].position, 1);
}

TEST(RecordingTable, BadTablesAndAnglesNameFileLineAndColumn) {
  test::temp_dir d;
  const auto error_of = [&](const std::string& text, double tol = 0.0) {
    const std::string f = d.file("bad.csv");
    test::write_text(f, text);
    auto r = io::recording_reader::open(f, tol);
    if (!r) return r.err().message.substr(f.size());
    std::vector<method::row> rows(64);
    const auto n = r->read(rows);
    return n ? std::string("accepted") : n.err().message.substr(f.size());
  };
  // The line: a bad angle's column (the value begins at column 18).
  EXPECT_EQ(error_of(csv_of("# positions_deg: 0,abc\n", {0, 180}, 4)),
            ":1:20: positions_deg: 'abc' is not an angle in degrees (expected A,B,... or auto: "
            "the table's angles)");
  EXPECT_EQ(error_of(csv_of("# x: 1\n# positions_deg: 0, 360\n", {0, 180}, 4)),
            ":2:21: positions_deg: 360 is not an angle in [0, 360) deg");
  EXPECT_EQ(error_of(csv_of("# positions_deg: 0,180,0\n", {0, 180}, 4)),
            ":1:24: positions_deg: 0 deg is position 0 already: a table's angles differ");
  // A row's angle not in the table: its line and the angle_deg column (2). 180 was always read
  // before the table line; a table of 0 and 90 does not hold it.
  EXPECT_EQ(error_of(csv_of("# positions_deg: 0,90\n", {0, 180}, 4))
                .rfind(":4:5: angle 180 deg is not supported: only 0 and 90 (the positions of "
                       "its # positions_deg line)",
                       0),
            0u);
  // No line: the paper's pair, as before (with a tolerance or not).
  EXPECT_EQ(error_of(csv_of("", {0, 90}, 4))
                .rfind(":3:5: angle 90 deg is not supported: only 0 and 180 (the paper's pair", 0),
            0u);
  EXPECT_EQ(error_of(csv_of("", {0, 90}, 4), 0.5)
                .rfind(":3:5: angle 90 deg is not supported: only 0 and 180 (the paper's pair", 0),
            0u);
  // `auto`: nine distinct angles are refused at the ninth's row and column; angles as written,
  // so not with a tolerance.
  EXPECT_EQ(error_of(csv_of("# positions_deg: auto\n", {0, 180}, 4), 0.5),
            ":1:18: positions_deg: auto takes the angles as written; with an angle tolerance "
            "give the table's angles");
  EXPECT_EQ(error_of(csv_of("# positions_deg: auto\n", {0, 10, 20, 30, 40, 50, 60, 70, 80}, 9))
                .rfind(":11:5: angle 80 deg would be a table's 9th position", 0),
            0u);
}

// The pairings pass over the rows at the table's other positions: the cycles of a 0/90/180/270
// recording are those of its 0 and 180 deg rows alone, bit for bit, with a warning that counts
// the dwells left out.
TEST(RecordingTable, OtherPositionsArePassedOverBitForBit) {
  test::temp_dir d;
  const std::string four = d.file("four.csv"), two = d.file("two.csv");
  const std::string text = csv_of("# positions_deg: 0,90,180,270\n", {0, 90, 180, 270}, 400);
  test::write_text(four, text);
  std::string pair = "time_s,angle_deg,rate_dps,n_avg\n";
  for (std::size_t at = text.find("n_avg\n") + 6; at < text.size();) {
    const auto nl = text.find('\n', at);
    const std::string line = text.substr(at, nl + 1 - at);
    const auto c = line.find(',');
    const std::string a = line.substr(c + 1, line.find(',', c + 1) - c - 1);
    if (a == "0" || a == "180") pair += line;
    at = nl + 1;
  }
  test::write_text(two, pair);
  for (const auto p : {method::pairing::simple, method::pairing::abba}) {
    auto r4 = io::recording_reader::open(four);
    auto r2 = io::recording_reader::open(two);
    ASSERT_TRUE(r4 && r2);
    const auto c4 = method::read_cycles(*r4, p);
    const auto c2 = method::read_cycles(*r2, p);
    ASSERT_TRUE(c4) << c4.err().message;
    ASSERT_TRUE(c2) << c2.err().message;
    ASSERT_EQ(c4->cycles.size(), c2->cycles.size());
    ASSERT_EQ(c4->cycles.size(), 100u);
    for (std::size_t k = 0; k < c4->cycles.size(); ++k) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(c4->cycles[k].rate_dps),
                std::bit_cast<std::uint64_t>(c2->cycles[k].rate_dps));
      EXPECT_EQ(std::bit_cast<std::uint64_t>(c4->cycles[k].bias_dps),
                std::bit_cast<std::uint64_t>(c2->cycles[k].bias_dps));
    }
    EXPECT_EQ(c4->pair, (method::flip_pair{0, 2}));
    ASSERT_EQ(c4->warnings.size(), 1u);
    EXPECT_NE(c4->warnings[0].find("200 dwells at table positions other than 0 and 180 deg"),
              std::string::npos)
        << c4->warnings[0];
    EXPECT_TRUE(c2->warnings.empty());
  }
  // The CLI: calibrate gives the same dN from both (an older gyroflip refused the first).
  const auto j4 = test::run_cli({"calibrate", four, "--json"});
  const auto j2 = test::run_cli({"calibrate", two, "--json"});
  ASSERT_EQ(j4.exit_code, 0) << j4.err;
  ASSERT_EQ(j2.exit_code, 0) << j2.err;
  const auto dn = [](const std::string& json) {
    const auto at = json.find("\"delta_n_dps\":");
    return json.substr(at, json.find(',', at) - at);
  };
  EXPECT_EQ(dn(j4.out), dn(j2.out));
}

}  // namespace
}  // namespace gyroflip
