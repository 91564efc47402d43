// Earth rate and its projection: WGS84 value, paper eqn 9 at the paper's site, sign laws.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "gyroflip/earth/earth.hpp"

namespace gyroflip::earth {
namespace {

TEST(Earth, Wgs84RateMatchesPaper) {
  // Paper section 2 quotes psi_E = 4.178074e-3 deg/s (7 significant digits).
  EXPECT_NEAR(earth_rate_wgs84_dps, 4.178074e-3, 0.5e-9);
  EXPECT_DOUBLE_EQ(earth_rate_wgs84_rad_s, 7.2921150e-5);  // GeographicLib WGS84_omega
}

TEST(Earth, NorthAxisIsPaperEqn9) {
  // Paper: phi = 42.6 deg N gives psi_Earth ~= 3.0755e-3 deg/s (eqn 9).
  const auto n = parse_axis("north");
  ASSERT_TRUE(n);
  const double w = earth_rate_component_dps(42.6, *n);
  EXPECT_NEAR(w, 3.0755e-3, 0.5e-7);
  EXPECT_DOUBLE_EQ(w, earth_rate_wgs84_dps * std::cos(42.6 * std::numbers::pi / 180.0));
}

TEST(Earth, UpAxisIsSine) {
  // FACTS §2: vertical axis gives W_E sin(lat), 2.828e-3 deg/s at 42.6 deg N.
  const double w = earth_rate_component_dps(42.6, *parse_axis("up"));
  EXPECT_NEAR(w, 2.828e-3, 0.5e-6);
  EXPECT_DOUBLE_EQ(earth_rate_component_dps(42.6, *parse_axis("down")), -w);
}

TEST(Earth, LatitudeSignFlipsVerticalComponentOnly) {
  const auto up = *parse_axis("up");
  const auto north = *parse_axis("north");
  for (double lat : {5.0, 33.3, 42.6, 89.0}) {
    EXPECT_DOUBLE_EQ(earth_rate_component_dps(-lat, up), -earth_rate_component_dps(lat, up));
    EXPECT_DOUBLE_EQ(earth_rate_component_dps(-lat, north), earth_rate_component_dps(lat, north));
  }
}

TEST(Earth, EastAxisSeesNothingAndPolesAreExact) {
  EXPECT_EQ(earth_rate_component_dps(42.6, *parse_axis("east")), 0.0);
  EXPECT_EQ(earth_rate_component_dps(90.0, *parse_axis("north")), 0.0);
  EXPECT_EQ(earth_rate_component_dps(0.0, *parse_axis("up")), 0.0);
  EXPECT_DOUBLE_EQ(earth_rate_component_dps(90.0, *parse_axis("up")), earth_rate_wgs84_dps);
}

TEST(Earth, VectorAxisIsNormalisedAndMatchesNamedAxes) {
  const auto v = parse_axis("3, 0, -4");  // 0.6 north, 0.8 up
  ASSERT_TRUE(v);
  EXPECT_DOUBLE_EQ(v->north, 0.6);
  EXPECT_DOUBLE_EQ(v->down, -0.8);
  const double w = earth_rate_component_dps(42.6, *v);
  EXPECT_NEAR(w,
              0.6 * earth_rate_component_dps(42.6, *parse_axis("N")) +
                  0.8 * earth_rate_component_dps(42.6, *parse_axis("Up")),
              1e-18);
}

TEST(Earth, BadAxesAreErrors) {
  for (const char* bad : {"", "sideways", "1,2", "1,2,3,4", "0,0,0", "1,x,0", "nan,0,1", "1,,0"}) {
    const auto r = parse_axis(bad);
    EXPECT_FALSE(r) << bad;
    if (!r) {
      EXPECT_EQ(r.err().code, errc::bad_input);
    }
  }
}

TEST(Earth, LatitudeRange) {
  EXPECT_TRUE(check_latitude(-90.0));
  EXPECT_TRUE(check_latitude(90.0));
  EXPECT_FALSE(check_latitude(90.5));
  EXPECT_FALSE(check_latitude(std::nan("")));
}

}  // namespace
}  // namespace gyroflip::earth
