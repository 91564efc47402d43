// A recording's columns held in memory (io::rows_of_columns, the Python module's input): the
// same rows and checks as the CSV reader, errors naming the column and the 0-based row.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/cycles.hpp"

namespace {

using gyroflip::io::recording_columns;
using gyroflip::io::rows_of_columns;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

TEST(RowsOfColumns, RowsAsTheCsvReaderGivesThem) {
  const std::vector<double> t{0, 1, 2, 3}, a{0, nan, 180.3, 359.8}, r{1, 2, 3, 4},
      temp{20, 20, 21, 21}, n{256, 1, 128, 256};
  const auto rows = rows_of_columns({t, a, r, temp, n}, 0.5);
  ASSERT_TRUE(rows) << rows.err().message;
  ASSERT_EQ(rows->rows.size(), 4u);
  // With a tolerance and no table, the paper's 0/180 (index 0 at 0 deg, 1 at 180 deg).
  EXPECT_EQ(rows->positions, gyroflip::position_table::pair_0_180());
  EXPECT_EQ(rows->rows[0].position, 0);
  EXPECT_EQ(rows->rows[1].position, gyroflip::table_moving);  // the table turning
  EXPECT_EQ(rows->rows[2].position, 1);                       // encoder angles within the tolerance
  EXPECT_EQ(rows->rows[3].position, 0);
  EXPECT_EQ(rows->rows[2].n_avg, 128u);
  EXPECT_EQ(rows->rows[3].temp_c, 21.0);
  const auto bare = rows_of_columns({t, std::vector<double>{0, 180, 0, 180}, r, {}, {}});
  ASSERT_TRUE(bare);
  EXPECT_TRUE(std::isnan(bare->rows[0].temp_c));
  EXPECT_EQ(bare->rows[0].n_avg, 1u);
}

TEST(RowsOfColumns, ErrorsNameColumnAndRow) {
  const std::vector<double> t{0, 1, 2}, a{0, 180, 0}, r{1, 2, 3};
  const auto msg = [](const recording_columns& c, double tol = 0.0) {
    const auto rows = rows_of_columns(c, tol);
    return rows ? std::string("accepted") : rows.err().message;
  };
  const std::vector<double> pair{0, 180};
  EXPECT_EQ(msg({t, std::vector<double>{0, 90, 0}, r, {}, {}, pair})
                .rfind("angle_deg[1]: angle 90 deg is not supported: only 0 and 180", 0),
            0u);
  EXPECT_EQ(msg({t, std::vector<double>{0, 90, 0}, r, {}, {}}, 0.5)
                .rfind("angle_deg[1]: angle 90 deg is not supported: only 0 and 180", 0),
            0u);
  EXPECT_EQ(msg({std::vector<double>{0, 2, 1}, a, r, {}, {}}),
            "time_s[2]: time goes backwards: 1 after 2");
  EXPECT_EQ(msg({std::vector<double>{0, nan, 1}, a, r, {}, {}}),
            "time_s[1]: not a finite number within +-1e100");
  // Issue 21: the bound of a CSV cell, for columns in memory too (1e300 was taken).
  EXPECT_EQ(msg({std::vector<double>{0, 1, 1e101}, a, r, {}, {}}),
            "time_s[2]: not a finite number within +-1e100");
  EXPECT_EQ(msg({t, a, std::vector<double>{1, INFINITY, 3}, {}, {}}),
            "rate_dps[1]: not a finite number within +-1e100");
  EXPECT_EQ(
      msg({t, a, r, std::vector<double>{20, -300, 20}, {}}).rfind("temp_c[1]: temperature -300", 0),
      0u);
  EXPECT_EQ(msg({t, a, r, {}, std::vector<double>{1, 2.5, 1}}),
            "n_avg[1]: n_avg 2.5 is not a whole number >= 1");
  EXPECT_EQ(msg({t, a, std::vector<double>{1, 2}, {}, {}}),
            "rate_dps has 2 values but time_s has 3: one per row");
  EXPECT_NE(msg({t, a, r, {}, {}}, 11.0).find("angle tolerance"), std::string::npos);
}

TEST(RowsOfColumns, CyclesEqualThoseOfTheSameCsvRows) {
  std::vector<double> t, a, r;
  for (int k = 0; k < 40; ++k) {
    t.push_back(k * 0.9);
    a.push_back(k % 2 == 0 ? 0.0 : 180.0);
    r.push_back((k % 2 == 0 ? 0.4 : -0.4) + 0.1 + 1e-3 * k);
  }
  const auto rows = rows_of_columns({t, a, r, {}, {}});
  ASSERT_TRUE(rows);
  const auto c = gyroflip::method::cycles_of_rows(
      "<arrays>", rows->rows, gyroflip::method::pairing::abba, {}, rows->positions);
  ASSERT_TRUE(c) << c.err().message;
  for (const auto& cy : c->cycles) EXPECT_NEAR(cy.rate_dps, 0.4, 1e-12);  // abba cancels the ramp
}

}  // namespace
