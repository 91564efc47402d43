// `gyroflip heading` (docs/NORTH.md) on simulated runs with known truth: one run and its
// tilt caveat, two base azimuths, the JSON keys, and what it refuses (exit 2).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using gyroflip::test::run_cli;

namespace {

std::string simulate_north(const gyroflip::test::temp_dir& dir, const std::string& name,
                           const std::string& azimuth, const std::string& seed) {
  const auto csv = dir.file(name);
  const auto r = run_cli(
      {"simulate",     "--sensor",     "adxrs150", "--duration", "1800",  "--power-on-before",
       "3600",         "--table-axis", "up",       "--azimuth",  azimuth, "--positions",
       "0,90,180,270", "--tilt-mrad",  "1",        "--n-avg",    "585",   "--seed",
       seed,           "-o",           csv});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return csv;
}

}  // namespace

// ADXRS150, 2 x 30 min: the white limit is 15.5 / sqrt(1) deg; the true heading 40 deg; each
// error checked at 4 reported sigma (fixed seeds). One run flags the tilt x g term (7.3 deg per
// mrad); two runs at base azimuths 180 deg apart remove it (|G| = g_z x 1 mrad within 4 sigma).
TEST(CliHeading, FindsTheSimulatedAzimuthWithItsOwnSigma) {
  const gyroflip::test::temp_dir dir;
  const auto a = simulate_north(dir, "a.csv", "40", "21");
  const auto b = simulate_north(dir, "b.csv", "220", "22");
  const auto one = run_cli({"heading", a, "--latitude", "42.6", "--json"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto j1 = nlohmann::json::parse(one.out);
  for (const char* key : {"heading_deg", "sigma_deg", "limit_deg", "ratio_to_limit", "scheme"})
    EXPECT_TRUE(j1.contains(key)) << key;
  EXPECT_EQ(j1.at("schema"), "gyroflip.heading/1");
  bool flagged = false;
  for (const auto& c : j1.at("caveats"))
    flagged = flagged || c.get<std::string>().find("tilt") != std::string::npos;
  EXPECT_TRUE(flagged);
  // The limit is sqrt(2) N / (W_H sqrt(T)) with the data's own N (near the preset's 0.0354).
  EXPECT_NEAR(j1.at("arw_dps_rthz").get<double>() / 0.0354, 1.0, 0.15);
  const auto two = run_cli({"heading", a, b, "--latitude", "42.6", "--json"});
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const auto j2 = nlohmann::json::parse(two.out);
  const double err = std::remainder(j2.at("heading_deg").get<double>() - 40.0, 360.0);
  EXPECT_LT(std::abs(err), 4.0 * j2.at("sigma_deg").get<double>()) << err;
  EXPECT_EQ(j2.at("base_turn_deg").get<double>(), 180.0);  // from the recordings' azimuths
  EXPECT_GT(j2.at("table_term_dps").get<double>(), 0.0);
  // Text output names the scheme and the limit.
  const auto text = run_cli({"heading", a, b, "--latitude", "42.6", "--sensor", "adxrs150"});
  ASSERT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("white-noise limit"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("dead-time bound"), std::string::npos) << text.out;
}

TEST(CliHeading, RefusesWhatCannotGiveAHeading) {
  const gyroflip::test::temp_dir dir;
  const auto pair = dir.file("pair.csv");
  ASSERT_EQ(
      run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "120", "-o", pair}).exit_code,
      0);
  const auto r = run_cli({"heading", pair, "--latitude", "42.6"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("at least 3"), std::string::npos) << r.err;
  EXPECT_EQ(run_cli({"heading", pair, "--latitude", "89"}).exit_code, 2);
  EXPECT_EQ(run_cli({"heading", pair}).exit_code, 2);  // --latitude required
}
