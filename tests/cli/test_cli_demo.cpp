// The demo recordings (tests/vectors/demo, PROVENANCE.md): what `scripts/demo` shows must hold.
#include <cmath>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

const std::string demo_dir = std::string(GYROFLIP_VECTORS_DIR) + "/demo/";

TEST(Demo, CalibrateThenCompensateRecoverTheTruth) {
  temp_dir d;
  const auto cal = run_cli({"calibrate", demo_dir + "cal_stationary_20c.csv", "--latitude", "42.6",
                            "--axis", "north", "--json", "-o", d.file("cal.json")});
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  const auto j = nlohmann::json::parse(cal.out);
  const double se = j["stderr_correlated_dps"].get<double>();
  EXPECT_GT(se, 5e-4);  // 0.05 deg/s dwell noise over 1000 cycles: ~1e-3
  EXPECT_LT(se, 2e-3);
  EXPECT_LT(std::abs(j["delta_n_dps"].get<double>() - 0.3930754682), 4 * se);
  EXPECT_LT(std::abs(j["g_term_dps"].get<double>() - 0.39), 4 * se);

  const auto comp = run_cli({"compensate", demo_dir + "run_rate_table_20c.csv", "--calibration",
                             d.file("cal.json"), "--json", "-o", d.file("out.csv")});
  ASSERT_EQ(comp.exit_code, 0) << comp.err;
  const auto k = nlohmann::json::parse(comp.out);
  // The calibration's own error adds to the run's: both enter w = r - dN.
  const double total = std::hypot(k["stderr_correlated_dps"].get<double>(), se);
  EXPECT_LT(std::abs(k["mean_dps"].get<double>() - 0.25), 4 * total);
  EXPECT_EQ(k["cycles"], 340);
  EXPECT_TRUE(exists(d.file("out.csv")));
}

}  // namespace
}  // namespace gyroflip::test
