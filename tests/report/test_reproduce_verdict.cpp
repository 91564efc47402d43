// The reproduction's verdict (issue 22) is on the independent tests of the model only (what the
// simulator predicts from values not fitted to the data it is compared with) and can fail: a
// sensor model whose prediction is wrong on purpose fails it, and exactly the tests it breaks
// fail, while the calibration targets (fitted) and the in-sample tests of the model's
// assumptions on the paper's own data do not count; a test the seed may decide is
// "inconclusive", not a pass or a fail.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/reproduce.hpp"

namespace gyroflip {
namespace {

using nlohmann::json;

json failed_predictions(const workflow::reproduction& r) {
  json failed = json::array();
  const auto summary = json::parse(r.summary_json);  // alive through the loop
  for (const auto& p : summary["predictions"])
    if (!p["pass"].get<bool>()) failed.push_back(p["id"]);
  return failed;
}

json ids(const json& tests, const std::string& outcome) {
  json out = json::array();
  for (const auto& p : tests)
    if (outcome.empty() || p["outcome"].get<std::string>() == outcome) out.push_back(p["id"]);
  return out;
}

TEST(ReproduceVerdict, HoldsForTheModelAndFailsWhenAPredictionIsBrokenOnPurpose) {
  workflow::reproduce_request req;
  req.quick = true;
  req.seed = 1;
  const auto good = workflow::reproduce(req);
  ASSERT_TRUE(good) << good.err().message;
  EXPECT_TRUE(good->reproduced) << failed_predictions(*good);
  const auto summary = json::parse(good->summary_json);
  // The verdict's tests are the independent ones (review of issue 22: the 4 degC std from the
  // 20-degC-only model hands back the 20 degC table's std, and the figure runs are rows of the
  // tables whose spread the model was fitted to): the ADXRS150's per-cycle std from its
  // datasheet ARW. The in-sample tests of the model's assumptions are apart and not counted.
  EXPECT_EQ(ids(summary["predictions"], ""), json({"fig4_std", "fig6_std"}));
  EXPECT_EQ(ids(summary["in_sample_tests"], ""),
            json({"tab3_4c_std_from_20c", "tab3_4c_mean_vs_20c", "tab3_20c_loo", "tab3_4c_loo",
                  "tab4_20c_loo", "fig4_mean", "fig6_mean", "fig8_mean", "fig10_mean"}));
  for (const auto& p : summary["in_sample_tests"])
    if (std::string(p["id"]).ends_with("_mean") && std::string(p["id"]).starts_with("fig")) {
      EXPECT_EQ(p["u_observed"].get<double>(), 0.0) << p;
      EXPECT_GT(p["u_predicted"].get<double>(), 0.0) << p;
    }
  EXPECT_EQ(summary["verdict"], "reproduced");
  EXPECT_NE(good->text.find("verdict (quick check of the pipeline, not the reproduction): "
                            "reproduced (2 of 2 independent tests of the model hold)"),
            std::string::npos)
      << good->text;
  // Outcomes: "inconclusive" when the miss lies within two of its own simulation standard
  // errors of the limit (one quick campaign: the 4 degC std at -1.84 sigma of 2 is, with a
  // simulation error of 0.41 sigma), "pass (marginal)" with less than a fifth of the limit to
  // spare; each named in the verdict.
  const auto verdict = good->text.substr(good->text.find("\nverdict ("));
  for (const auto* tests : {&summary["predictions"], &summary["in_sample_tests"]})
    for (const auto& p : *tests) {
      const double score = std::abs(p["score"].get<double>());
      const double shift = p["score_sim_error"].get<double>();
      const std::string id = p["id"];
      if (id == "tab3_4c_std_from_20c") {
        EXPECT_EQ(p["inconclusive"].get<bool>(), std::abs(score - 2.0) <= 2.0 * shift) << p;
        EXPECT_TRUE(p["inconclusive"].get<bool>()) << p;
      }
      const bool named = verdict.find(p["quantity"].get<std::string>()) != std::string::npos;
      EXPECT_EQ(named, p["outcome"].get<std::string>() != "pass") << p << verdict;
    }

  // The ADXRS150 with twice its datasheet ARW: the Tab. 4 targets (g-term, turn-on spread) are
  // untouched, the per-cycle std of Figs 4/6 (a prediction) doubles.
  auto adxrs = *sensor::find_builtin("adxrs150");
  adxrs.params.arw_dps_rthz *= 2.0;
  req.sensors = {adxrs};
  const auto noisy = workflow::reproduce(req);
  ASSERT_TRUE(noisy) << noisy.err().message;
  EXPECT_FALSE(noisy->reproduced);
  const auto ns = json::parse(noisy->summary_json);
  EXPECT_EQ(ns["verdict"], "NOT reproduced");
  // A model given instead of the preset was not fitted here: its Tab. 4 values count too (and
  // hold: the ARW does not move them).
  EXPECT_EQ(failed_predictions(*noisy), json({"fig4_std", "fig6_std"}));
  EXPECT_EQ(ids(ns["predictions"], ""),
            json({"fig4_std", "fig6_std", "tab4_20c_mean", "tab4_20c_std"}));

  // The HZ1 with a tenth of its turn-on spread (a new power-up's g-term moves 10 times less):
  // given instead of the preset, its Tab. 3 stds are tests it fails; in-sample, the figure runs
  // simulated with it predict compensated means 10 times tighter than the paper's Figs 8/10
  // show, and the 4 degC std from the 20-degC-only model falls far below the paper's.
  auto hz1 = *sensor::find_builtin("hz1-90-100a");
  hz1.params.g_sens_turn_on_sigma_dps_per_g *= 0.1;
  hz1.params.g_sens_tc_turn_on_sigma_dps_per_g_c *= 0.1;
  req.sensors = {hz1};
  const auto tight = workflow::reproduce(req);
  ASSERT_TRUE(tight) << tight.err().message;
  EXPECT_FALSE(tight->reproduced);
  EXPECT_EQ(failed_predictions(*tight), json({"tab3_20c_std", "tab3_4c_std"}));
  const auto ts = json::parse(tight->summary_json);
  EXPECT_EQ(ids(ts["in_sample_tests"], "FAIL"),
            json({"tab3_4c_std_from_20c", "fig8_mean", "fig10_mean"}));
}

}  // namespace
}  // namespace gyroflip
