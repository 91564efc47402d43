// The reproduction's verdict (issues 22, 31) is on the tests of the model's predictions alone:
// values the model was not fitted to, compared with data used in no fit. Since issue 31 these
// include the out-of-sample tests (the HZ1's 4 degC table from a model fitted at 20 degC alone,
// leave-one-run-out, the figure runs that are rows of no table), so a miss there makes the
// verdict "inconclusive" or "NOT reproduced"; a sensor model whose prediction is wrong on
// purpose fails it, and exactly the tests it breaks fail (a given HZ1 model's noise included:
// an HZ1 with 3 times its ARW read "reproduced"); the headline names what the verdict covers,
// the ADXRS150's ARW convention, what was fitted and what is only illustrated.
#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/reproduce.hpp"

namespace gyroflip {
namespace {

using nlohmann::json;

json ids(const json& tests, const std::string& outcome = "") {
  json out = json::array();
  for (const auto& p : tests)
    if (outcome.empty() || p["outcome"].get<std::string>() == outcome) out.push_back(p["id"]);
  return out;
}

bool has(const json& list, const char* id) {
  return std::find(list.begin(), list.end(), json(id)) != list.end();
}

// Each test's outcome follows its rule (docs/REPRODUCE.md, "The verdict"): s = |score|, L its
// own limit, F the family-wise one (Bonferroni over the verdict's m statistical tests), e twice
// its simulation error: FAIL from max(L, F) + e on, "inconclusive" within e of L, "miss"
// beyond L, "pass (marginal)" beyond 0.8 L; and every outcome but a plain pass is named in the
// headline.
void expect_outcomes_by_their_rules(const json& summary) {
  const auto& tests = summary["predictions"];
  const auto m =
      std::count_if(tests.begin(), tests.end(), [](const json& p) { return p["kind"] != "ratio"; });
  const double level = 0.05 / static_cast<double>(m);
  const std::string headline = summary["headline"];
  for (const auto* group : {&summary["predictions"], &summary["not_counted"]})
    for (const auto& p : *group) {
      const double s = std::abs(p["score"].get<double>()), lim = p["limit"].get<double>();
      const double e = 2.0 * p["score_sim_error"].get<double>();
      const double fam = p["family_limit"].is_number() ? p["family_limit"].get<double>() : 0.0;
      const std::string id = p["id"], outcome = p["outcome"];
      std::string want = "pass";
      if (s >= std::max(lim, fam) + e)
        want = "FAIL";
      else if (std::abs(s - lim) < e)
        want = "inconclusive";
      else if (s > lim)
        want = "miss";
      else if (s > 0.8 * lim)
        want = "pass (marginal)";
      EXPECT_EQ(outcome, want) << p;
      // The family-wise limits: a z test's at the two-sided level 5 %/m, a figure's prediction
      // interval Student's t at 1 - 2.5 %/m, a count's binomial.
      if (group == &summary["not_counted"]) {
        EXPECT_TRUE(p["family_limit"].is_null()) << p;
        continue;
      }
      if (p["kind"] == "z") {
        EXPECT_NEAR(fam, std::sqrt(analysis::chi2_quantile(1.0 - level, 1.0)), 1e-9) << p;
      }
      if (p["kind"] == "interval") {
        EXPECT_NEAR(fam, analysis::student_t_quantile(1.0 - level / 2.0, 7), 1e-9) << p;
      }
      EXPECT_EQ(headline.find(p["quantity"].get<std::string>()) != std::string::npos,
                outcome != "pass")
          << p << headline;
    }
}

workflow::reproduction run(const std::vector<sensor::preset>& sensors) {
  workflow::reproduce_request req;
  req.quick = true;
  req.seed = 1;
  req.sensors = sensors;
  auto r = workflow::reproduce(req);
  EXPECT_TRUE(r) << r.err().message;
  return r ? *r : workflow::reproduction{};
}

TEST(ReproduceVerdict, CountsTheOutOfSampleTestsAndNamesItsScope) {
  const auto good = run({});
  const auto summary = json::parse(good.summary_json);
  // The verdict's tests: the ADXRS150's per-cycle std from its datasheet's density, the HZ1's
  // 4 degC table from a model fitted at 20 degC alone, leave-one-run-out of each table (Tab. 4
  // on its 9 distinct rows), and the compensated means of the figures whose runs are rows of no
  // table. Fig. 8's run is Tab. 3's 20 degC row 13: shown, not counted.
  EXPECT_EQ(
      ids(summary["predictions"]),
      json({"fig4_std", "fig6_std", "tab3_4c_mean_from_20c", "tab3_4c_std_from_20c", "tab3_20c_loo",
            "tab3_4c_loo", "tab4_20c_loo", "fig4_mean", "fig6_mean", "fig10_mean"}));
  EXPECT_EQ(ids(summary["not_counted"]), json({"fig8_mean"}));
  EXPECT_NE(summary["not_counted"][0]["basis"].get<std::string>().find("row 13"),
            std::string::npos);
  for (const auto& p : summary["predictions"]) {
    if (p["id"] == "tab4_20c_loo") {
      EXPECT_NE(p["quantity"].get<std::string>().find("9 distinct runs"), std::string::npos);
    }
  }
  for (const auto& f : summary["figures"])
    EXPECT_EQ(f["paper_run_is_table_row"].is_number(), f["id"] == "fig8") << f;
  // One quick campaign: the 4 degC std from the 20 degC model lies at -1.84 sigma of 2, within
  // twice its simulation error (0.41 sigma): the seed decides it, so the verdict is
  // "inconclusive" (it read "reproduced" when the test was not counted).
  EXPECT_FALSE(good.reproduced);
  EXPECT_EQ(summary["verdict"], "inconclusive");
  EXPECT_EQ(ids(summary["predictions"], "inconclusive"), json({"tab3_4c_std_from_20c"}));
  expect_outcomes_by_their_rules(summary);
  // The headline: the verdict, what it covers, the ARW convention, what was fitted, what is
  // only illustrated.
  const std::string headline = summary["headline"];
  EXPECT_TRUE(
      headline.starts_with("inconclusive: 6 of 7 tests of the model's predictions hold, and 3 "
                           "of 3 leave-one-run-out tests, which test the paper's runs against "
                           "each other (the data and the Gaussian form of the turn-on change), "
                           "not the model's values."))
      << headline;
  for (const char* part :
       {"the ADXRS150's per-cycle noise (Figs 4/6) from its datasheet's density, read as "
        "one-sided (N = 0.05/√2)",
        "the HZ1's 4 °C mean and spread of ΔN from a model fitted at 20 °C alone",
        "each table's runs from the others", "the compensated means of Figs 4, 6 and 10",
        "Inconclusive (within twice its simulation error of its limit: the seed decides it)",
        "Not tested: the values the presets were fitted to",
        "Fig. 8: compensated mean (°/s) (compared with data it was fitted to",
        "Only illustrated: the main claim"})
    EXPECT_NE(headline.find(part), std::string::npos) << part << "\n" << headline;
  EXPECT_NE(
      good.text.find("\nverdict (quick check of the pipeline, not the reproduction): " + headline),
      std::string::npos);
}

// The ADXRS150 with its datasheet density read as N itself (ARW x sqrt 2, ADI's "ARW = 60 x
// density"): the per-cycle std of Figs 4/6 misses by about +41 %. Its g-term and turn-on spread
// are still the preset's, fitted to Tab. 4: the table is no test of it (fifth review of issue 31,
// F10: they were counted as the given model's predictions), but a calibration target.
TEST(ReproduceVerdict, TheOtherArwConventionFailsTheNoiseTest) {
  auto adxrs = *sensor::find_builtin("adxrs150");
  adxrs.params.arw_dps_rthz *= std::sqrt(2.0);
  const auto r = run({adxrs});
  EXPECT_FALSE(r.reproduced);
  const auto s = json::parse(r.summary_json);
  EXPECT_EQ(s["verdict"], "NOT reproduced");
  EXPECT_EQ(ids(s["predictions"], "FAIL"), json({"fig4_std", "fig6_std"}));
  for (const auto& p : s["predictions"])
    if (p["id"].get<std::string>().ends_with("_std") &&
        p["id"].get<std::string>().starts_with("fig")) {
      EXPECT_GT(p["score"].get<double>(), 0.3) << p;
      EXPECT_LT(p["score"].get<double>(), 0.55) << p;
      EXPECT_NE(p["basis"].get<std::string>().find("the given model's ARW, N = 0.05 °/s/√Hz"),
                std::string::npos)
          << p;
    }
  EXPECT_FALSE(has(ids(s["predictions"]), "tab4_20c_mean"));
  EXPECT_FALSE(has(ids(s["predictions"]), "tab4_20c_std"));
  EXPECT_EQ(s["inherited_fitted"],
            json({{{"sensor", "adxrs150"}, {"key", "g_sens_z_dps_per_g"}},
                  {{"sensor", "adxrs150"}, {"key", "g_sens_turn_on_sigma_dps_per_g"}}}));
  std::size_t targets = 0;
  for (const auto& t : s["targets"])
    targets +=
        t["fitted"].get<std::string>().find("not restated by the given model") != std::string::npos;
  EXPECT_EQ(targets, 2u) << s["targets"];
  EXPECT_NE(s["headline"].get<std::string>().find("The given model inherits from its base preset "
                                                  "values fitted to the paper"),
            std::string::npos);
  expect_outcomes_by_their_rules(s);
}

// A given HZ1 model's own ARW is fitted to nothing here, so its per-cycle std (the preset's ARW
// was fitted to Figs 8/10) is a test of it: an HZ1 with 3 times its ARW read "reproduced" before
// issue 31; it fails exactly its noise tests now. Its g-term and turn-on spread are the preset's,
// fitted to Tab. 3 (F10): the tables are calibration targets, the 4 degC ones tested from the
// 20 degC fit as for the preset, and Fig. 8 (a row of Tab. 3) shown, not counted.
TEST(ReproduceVerdict, AGivenHz1ModelsNoiseIsTested) {
  auto hz1 = *sensor::find_builtin("hz1-90-100a");
  hz1.params.arw_dps_rthz *= 3.0;
  const auto r = run({hz1});
  EXPECT_FALSE(r.reproduced);
  const auto s = json::parse(r.summary_json);
  EXPECT_EQ(s["verdict"], "NOT reproduced");
  EXPECT_EQ(ids(s["predictions"], "FAIL"), json({"fig8_std", "fig10_std"}));
  for (const char* id : {"tab3_20c_mean", "tab3_20c_std", "tab3_4c_mean", "tab3_4c_std"})
    EXPECT_FALSE(has(ids(s["predictions"]), id)) << id;
  for (const char* id : {"tab3_4c_mean_from_20c", "tab3_4c_std_from_20c", "fig10_mean"})
    EXPECT_TRUE(has(ids(s["predictions"]), id)) << id;
  EXPECT_EQ(ids(s["not_counted"]), json({"fig8_mean"}));
  std::size_t inherited = 0;
  for (const auto& t : s["targets"]) {
    // Its noise is its own: no per-cycle std target.
    EXPECT_EQ(t["quantity"].get<std::string>().find("per-cycle std"), std::string::npos) << t;
    inherited +=
        t["quantity"].get<std::string>().find("HZ1") != std::string::npos &&
        t["fitted"].get<std::string>().find("not restated by the given model") != std::string::npos;
  }
  EXPECT_EQ(inherited, 4u) << s["targets"];
  EXPECT_NE(s["headline"].get<std::string>().find(
                "the HZ1's per-cycle noise (Figs 8/10) from the given model"),
            std::string::npos);
  // The leave-one-run-out sets the paper's runs against each other: the given model does not
  // enter it, and the headline does not count it as a test of the model (review of issue 31,
  // L5: "9 of 10 tests of the model's predictions" counted its 3).
  std::size_t model_tests = 0;
  for (const auto& p : s["predictions"]) {
    const bool loo = p["id"].get<std::string>().ends_with("_loo");
    EXPECT_EQ(p["model_enters"], !loo) << p["id"];
    model_tests += !loo;
  }
  EXPECT_NE(s["headline"].get<std::string>().find(
                fmt::format("of {} tests of the model's predictions hold, and", model_tests)),
            std::string::npos)
      << s["headline"];
  EXPECT_NE(s["headline"].get<std::string>().find("leave-one-run-out tests, which test the "
                                                  "paper's runs against each other"),
            std::string::npos);
  expect_outcomes_by_their_rules(s);
}

// The HZ1 with a tenth of its turn-on spread (a new power-up's g-term moves 10 times less):
// given instead of the preset, its Tab. 3 stds fail, and so do the figure runs' compensated
// means, which it predicts 10 times tighter than the paper's Figs 8/10 show.
TEST(ReproduceVerdict, AGivenModelWithTheWrongSpreadFailsItsTablesAndFigures) {
  auto hz1 = *sensor::find_builtin("hz1-90-100a");
  hz1.params.g_sens_turn_on_sigma_dps_per_g *= 0.1;
  hz1.params.g_sens_tc_turn_on_sigma_dps_per_g_c *= 0.1;
  const auto r = run({hz1});
  EXPECT_FALSE(r.reproduced);
  const auto s = json::parse(r.summary_json);
  EXPECT_EQ(ids(s["predictions"], "FAIL"),
            json({"tab3_20c_std", "tab3_4c_std", "fig8_mean", "fig10_mean"}));
  expect_outcomes_by_their_rules(s);
}

}  // namespace
}  // namespace gyroflip
