// The reproduction's verdict (issue 22) is on the tests of the model only (what the simulator
// predicts and the paper measured) and can fail: a sensor model whose prediction is wrong on
// purpose fails it, and exactly the tests it breaks fail, while the calibration targets and the
// consistency checks of the paper's own data (which no model can pass or fail) do not count.
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

TEST(ReproduceVerdict, HoldsForTheModelAndFailsWhenAPredictionIsBrokenOnPurpose) {
  workflow::reproduce_request req;
  req.quick = true;
  req.seed = 1;
  const auto good = workflow::reproduce(req);
  ASSERT_TRUE(good) << good.err().message;
  EXPECT_TRUE(good->reproduced) << failed_predictions(*good);
  const auto summary = json::parse(good->summary_json);
  // The consistency checks of the paper's own data (the simulator does not enter them) are
  // apart and do not count; the paper's figure values carry no simulated uncertainty.
  json checks = json::array();
  for (const auto& c : summary["consistency_checks"]) checks.push_back(c["id"]);
  EXPECT_EQ(checks, json({"tab3_4c_mean_vs_20c", "tab3_20c_loo", "tab3_4c_loo", "tab4_20c_loo"}));
  for (const auto& p : summary["predictions"]) {
    EXPECT_EQ(std::string(p["id"]).find("_loo"), std::string::npos) << p;
    if (std::string(p["id"]).ends_with("_mean")) {
      EXPECT_EQ(p["u_observed"].get<double>(), 0.0) << p;
      EXPECT_GT(p["u_predicted"].get<double>(), 0.0) << p;
    }
  }
  EXPECT_NE(good->text.find("reproduced (7 of 7 tests of the model hold"), std::string::npos)
      << good->text;
  // A pass with less than a fifth of its limit to spare is named in the verdict, a comfortable
  // one is not (review of issue 22: the 4 degC std passed at -1.98 sigma of 2, unremarked).
  for (const auto& p : summary["predictions"]) {
    const double score = std::abs(p["score"].get<double>());
    const std::string id = p["id"];
    if (id == "fig4_std" || id == "fig6_std") {
      EXPECT_EQ(p["marginal"].get<bool>(), p["pass"].get<bool>() && score > 0.8 * 0.15) << p;
    } else if (id == "tab3_4c_std_from_20c") {
      EXPECT_EQ(p["marginal"].get<bool>(), p["pass"].get<bool>() && score > 0.8 * 2.0) << p;
    }
    const auto verdict = good->text.substr(good->text.find("\nverdict: "));
    EXPECT_EQ(verdict.find(p["quantity"].get<std::string>()) != std::string::npos,
              p["marginal"].get<bool>())
        << p << verdict;
  }

  // The ADXRS150 with twice its datasheet ARW: the Tab. 4 targets (g-term, turn-on spread) are
  // untouched, the per-cycle std of Figs 4/6 (a prediction) doubles.
  auto adxrs = *sensor::find_builtin("adxrs150");
  adxrs.params.arw_dps_rthz *= 2.0;
  req.sensors = {adxrs};
  const auto noisy = workflow::reproduce(req);
  ASSERT_TRUE(noisy) << noisy.err().message;
  EXPECT_FALSE(noisy->reproduced);
  EXPECT_EQ(failed_predictions(*noisy), json({"fig4_std", "fig6_std"}));

  // The HZ1 with a tenth of its turn-on spread (a new power-up's g-term moves 10 times less):
  // the Tab. 3 stds (targets) are missed, which is not judged, but the figure runs simulated
  // with it predict compensated means 10 times tighter than the paper's Figs 8/10 show, and the
  // 4 degC std from the 20-degC-only model falls far below the paper's: tests of the model.
  auto hz1 = *sensor::find_builtin("hz1-90-100a");
  hz1.params.g_sens_turn_on_sigma_dps_per_g *= 0.1;
  hz1.params.g_sens_tc_turn_on_sigma_dps_per_g_c *= 0.1;
  req.sensors = {hz1};
  const auto tight = workflow::reproduce(req);
  ASSERT_TRUE(tight) << tight.err().message;
  EXPECT_FALSE(tight->reproduced);
  EXPECT_EQ(failed_predictions(*tight), json({"tab3_4c_std_from_20c", "fig8_mean", "fig10_mean"}));
}

}  // namespace
}  // namespace gyroflip
