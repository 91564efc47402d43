// `gyroflip plan` (docs/PLANNER.md): the preset route against the library's planner and the
// closed form, the static-record route against the preset it was simulated from, usage errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gyroflip/method/plan.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/plan.hpp"
#include "support/run_cli.hpp"

using gyroflip::test::run_cli;

TEST(CliPlan, APresetsPlanIsTheLibrarysWithItsClosedFormAndThePapersDwell) {
  const auto r = run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto noise =
      gyroflip::workflow::plan_noise_of(gyroflip::sensor::find_builtin("adxrs150")->params);
  const auto p = gyroflip::method::plan_flip(noise, 0.4, 3600);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(j.at("dwell_s").get<double>(), p->dwell_s);
  EXPECT_DOUBLE_EQ(j.at("period_s").get<double>(), 2 * (p->dwell_s + 0.4));
  EXPECT_DOUBLE_EQ(j.at("predicted_sigma_dps").get<double>(), p->sigma_dps);
  // tau_c = N^2/(0.4413 B^2) with the preset's N = 0.05/sqrt 2 and B = 0.02 deg/s: 7.08 s.
  EXPECT_NEAR(j.at("closed_form").at("corner_tau_s").get<double>(), 7.082, 0.01);
  EXPECT_NEAR(j.at("closed_form").at("dwell_s").get<double>(), std::sqrt(0.4 * 7.082), 0.01);
  // The paper's 0.512-s dwell is worse than the plan's for this preset and dead time.
  EXPECT_GT(j.at("reference_dwell").at("sigma_dps").get<double>(), 1.1 * p->sigma_dps);
  EXPECT_EQ(j.at("schema").get<std::string>(), "gyroflip.plan/1");
  EXPECT_DOUBLE_EQ(j.at("reference_dwell").at("dwell_s").get<double>(), 0.512);
  EXPECT_GE(j.at("by_dwell").size(), 3u);
  EXPECT_GE(j.at("by_duration").size(), 3u);
  // the text says the same numbers
  const auto t = run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4"});
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("dwell"), std::string::npos);
  EXPECT_NE(t.out.find("0.512 s"), std::string::npos);
}

TEST(CliPlan, AStaticRecordPlansAsItsPresetDoes) {
  // 30 min of the simulated adxrs150 at rest, every conversion: its fitted terms give the
  // preset's plan within the fit's error, and its own gap variance agrees with the model.
  const auto dir = std::filesystem::temp_directory_path() / "gyroflip_plan_static";
  std::filesystem::create_directories(dir);
  const auto csv = (dir / "static.csv").string();
  ASSERT_EQ(run_cli({"simulate", "--sensor", "adxrs150", "--no-flip", "--raw", "--duration", "1800",
                     "--power-on-before", "3600", "--seed", "3", "-o", csv})
                .exit_code,
            0);
  const auto r = run_cli({"plan", "--static", csv, "--dead-time", "0.4", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto s = run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--json"});
  const auto k = nlohmann::json::parse(s.out);
  EXPECT_NEAR(j.at("dwell_s").get<double>() / k.at("dwell_s").get<double>(), 1.0, 0.15);
  EXPECT_NEAR(j.at("predicted_sigma_dps").get<double>() / k.at("predicted_sigma_dps").get<double>(),
              1.0, 0.1);
  EXPECT_NEAR(std::sqrt(j.at("record_over_model_avar").get<double>()), 1.0, 0.15);
  std::filesystem::remove_all(dir);
}

TEST(CliPlan, UsageErrorsExitTwo) {
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150"}).exit_code, 2);  // --dead-time required
  EXPECT_EQ(run_cli({"plan", "--dead-time", "0.4"}).exit_code, 2);    // no noise source
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150", "--static", "x.csv", "--dead-time", "0.4"})
                .exit_code,
            2);
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "-1"}).exit_code, 2);
  EXPECT_EQ(run_cli({"plan", "--sensor", "nosuch", "--dead-time", "0.4"}).exit_code, 2);
  const auto short_run =
      run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--duration", "1"});
  EXPECT_EQ(short_run.exit_code, 2);
  EXPECT_NE(short_run.err.find("two pairs"), std::string::npos) << short_run.err;
  EXPECT_TRUE(short_run.out.empty());
}

TEST(CliPlan, AHeadingPlanIsTheIndexedPlanOverTheHorizontalEarthRate) {
  // plan --heading: the 4-position sweep's plan (method::plan_indexed), its error as a heading
  // over W_E cos(lat) (W_E = 7.292115e-5 rad/s, FACTS §2), and the white limit the issue states
  // for the hz1-90-100a at 42.6 deg: 2.0 deg/sqrt(T/h).
  const auto r = run_cli({"plan", "--sensor", "hz1-90-100a", "--dead-time", "0.257", "--duration",
                          "14400", "--heading", "--latitude", "42.6", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto noise =
      gyroflip::workflow::plan_noise_of(gyroflip::sensor::find_builtin("hz1-90-100a")->params);
  const auto visits = gyroflip::method::sweep_visits(std::vector<double>{0, 90, 180, 270});
  const auto p = gyroflip::method::plan_indexed(noise, visits, 0.257, 14400);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(j.at("dwell_s").get<double>(), p->dwell_s);
  EXPECT_NEAR(j.at("period_s").get<double>(), 8 * p->dwell_s + 6 * 0.257, 1e-9);
  EXPECT_DOUBLE_EQ(j.at("predicted_sigma_dps").get<double>(), p->sigma_dps);
  EXPECT_EQ(j.at("visiting_order_deg").size(), 8u);
  const double w_h_dps =
      7.292115e-5 * 180 / std::numbers::pi * std::cos(42.6 * std::numbers::pi / 180);
  const auto& h = j.at("heading");
  EXPECT_NEAR(h.at("predicted_sigma_deg").get<double>(),
              p->sigma_dps / w_h_dps * 180 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(h.at("white_limit_deg").get<double>(), 2.0 / std::sqrt(4.0), 0.02);
  EXPECT_NEAR(h.at("sigma_deg_rth").get<double>(), h.at("predicted_sigma_deg").get<double>() * 2,
              1e-9);
  // Dead time and flicker cost against the white limit, but not more than half again.
  EXPECT_GT(h.at("predicted_sigma_deg").get<double>(), h.at("white_limit_deg").get<double>());
  EXPECT_LT(h.at("predicted_sigma_deg").get<double>(), 1.5 * h.at("white_limit_deg").get<double>());
  EXPECT_EQ(h.at("by_duration").size(), j.at("by_duration").size());
  // --positions 0,90,180,270 without --heading: the same dwell
  const auto q = run_cli({"plan", "--sensor", "hz1-90-100a", "--dead-time", "0.257", "--duration",
                          "14400", "--positions", "0,90,180,270", "--json"});
  ASSERT_EQ(q.exit_code, 0) << q.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(q.out).at("dwell_s").get<double>(), p->dwell_s);
  EXPECT_FALSE(nlohmann::json::parse(q.out).contains("heading"));
}

TEST(CliPlan, TwoPositionsAreTheFlipPlanAndAHeadingNeedsThree) {
  const auto a = run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--json"});
  const auto b = run_cli(
      {"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--positions", "0,180", "--json"});
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  const auto h = run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--heading",
                          "--latitude", "42.6", "--positions", "0,180"});
  EXPECT_EQ(h.exit_code, 2);
  EXPECT_NE(h.err.find("projection"), std::string::npos) << h.err;
  EXPECT_TRUE(h.out.empty());
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--heading"}).exit_code,
            2);
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--heading",
                     "--latitude", "89"})
                .exit_code,
            2);
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--positions", "0,400"})
                .exit_code,
            2);
  EXPECT_EQ(run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--positions", "0,x"})
                .exit_code,
            2);
}

TEST(CliPlan, PlotDrawsTheErrorAgainstTheDwell) {
  const auto dir = std::filesystem::temp_directory_path() / "gyroflip_plan_plot";
  std::filesystem::create_directories(dir);
  const auto png = (dir / "plan.png").string();
  const auto r = run_cli({"plan", "--sensor", "adxrs150", "--dead-time", "0.4", "--heading",
                          "--latitude", "42.6", "--plot", png});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
  // the data file is the heading's curve: its lowest point is the plan's predicted error
  std::ifstream dat(dir / "plan_1.dat");
  std::string line;
  double lowest = 1e300;
  while (std::getline(dat, line)) {
    double x = 0, y = 0;
    if (line.empty() || line[0] == '#' || std::sscanf(line.c_str(), "%lf %lf", &x, &y) != 2)
      continue;
    lowest = std::min(lowest, y);
  }
  const auto j = nlohmann::json::parse(run_cli({"plan", "--sensor", "adxrs150", "--dead-time",
                                                "0.4", "--heading", "--latitude", "42.6", "--json"})
                                           .out);
  const double planned = j.at("heading").at("predicted_sigma_deg").get<double>();
  EXPECT_GE(lowest, planned * (1 - 1e-6));
  EXPECT_LT(lowest, planned * 1.05);
  std::filesystem::remove_all(dir);
}
