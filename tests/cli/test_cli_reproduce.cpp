// `gyroflip reproduce` (issues 10, 22, 31): the paper's campaign on the simulator. The quick run's
// outputs and keys (the tests of the model's predictions apart from the comparisons with fitted
// data and the calibration targets, the main claim with raw beside compensated drift, every
// campaign's numbers in summary.json, the figures numbered as the paper's); the full ensemble
// keeps the fit to Tab. 3/4 (a regression on seed 1: the turn-on g-term variation fitted to the
// paper must keep the simulated spread at the paper's) and the sensitivity study covers every
// assumed value, the ARW convention and 1.79 s per position among them; `--sensor NAME=FILE.toml`
// puts a user's model to the same tests; and the new sensor parameters are visible in
// `gyroflip sensors`.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using gyroflip::test::read_page;
using gyroflip::test::run_cli;
using gyroflip::test::temp_dir;
using nlohmann::json;

TEST(ReproduceCli, QuickWritesTheTablesFiguresAndPage) {
  temp_dir d;
  const auto out = d.path() + "/repro";
  const auto r = run_cli({"reproduce", "--quick", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Tab. 3, HZ1-90-100A, 4 °C, 13 runs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Tests of the model's predictions (the verdict)"), std::string::npos);
  EXPECT_NE(r.out.find("Shown, not counted: a comparison with data the model was fitted to"),
            std::string::npos);
  EXPECT_NE(r.out.find("made "), std::string::npos);  // provenance in the text too
  // The verdict line itself says the run was quick (review R7): a quarter-length campaign is a
  // check of the pipeline, not the reproduction.
  ASSERT_NE(r.out.find("\nverdict (quick check of the pipeline, not the reproduction): "),
            std::string::npos)
      << r.out;
  const auto verdict = r.out.substr(r.out.find("\nverdict ("));
  EXPECT_NE(verdict.substr(0, verdict.find("\n", 1)).find("Quick run"), std::string::npos)
      << verdict;
  EXPECT_NE(r.out.find("Calibration targets: what the sensor model was fitted to"),
            std::string::npos);
  const auto j = json::parse(std::ifstream(out + "/summary.json"));
  EXPECT_EQ(j["schema"], "gyroflip.reproduce/5");
  ASSERT_EQ(j["tables"].size(), 3u);
  for (const auto& t : j["tables"]) {
    for (const char* k :
         {"sensor", "temp_c", "runs", "mean_dps", "std_dps", "paper_mean_dps", "paper_std_dps"})
      EXPECT_TRUE(t.contains(k)) << k;
    // Every campaign's numbers: its mean and std of dN are its runs' (issue 31).
    ASSERT_EQ(t["per_campaign"].size(), 1u) << t;
    const auto& c = t["per_campaign"][0];
    ASSERT_EQ(c["runs"].size(), t["runs"].get<std::size_t>()) << c;
    double sum = 0.0;
    for (const auto& run : c["runs"]) sum += run["delta_n_dps"].get<double>();
    EXPECT_NEAR(sum / static_cast<double>(c["runs"].size()), c["mean_dps"].get<double>(), 1e-12);
    EXPECT_NEAR(c["mean_dps"].get<double>(), t["mean_dps"].get<double>(), 1e-15);
    // Each run's stationarity verdict (issue 31 leftover): every statistic beside its limit and
    // its verdict, the g-term against the model's own specification at the simulated geometry.
    for (const auto& run : c["runs"]) {
      const auto& st = run["stationarity"];
      ASSERT_TRUE(st.is_object()) << run;
      ASSERT_TRUE(st["checked"].get<bool>()) << st;
      EXPECT_LE(st["scatter_ratio"].get<double>(), st["scatter_limit"].get<double>()) << st;
      EXPECT_GE(st["scatter_ratio"].get<double>(), st["scatter_low_limit"].get<double>()) << st;
      EXPECT_LE(st["drift_statistic"].get<double>(), st["drift_limit"].get<double>()) << st;
      ASSERT_TRUE(st["g_term"].is_object()) << st;
      EXPECT_TRUE(st["g_term"]["exact"].get<bool>()) << st;
      EXPECT_GT(st["g_term"]["limit_dps"].get<double>(), 0.0) << st;
      // Simulated at rest: each passes, and the verdict is its statistics'.
      EXPECT_TRUE(st["stationary"].get<bool>()) << st;
      EXPECT_FALSE(st["scatter_failed"].get<bool>() || st["drift_failed"].get<bool>() ||
                   st["temp_failed"].get<bool>() || st["g_term"]["failed"].get<bool>())
          << st;
    }
    // One quick campaign: within a factor 2 of the paper (sampling error ~20-40 %).
    EXPECT_GT(t["std_ratio"].get<double>(), 0.5) << t;
    EXPECT_LT(t["std_ratio"].get<double>(), 2.0) << t;
  }
  ASSERT_EQ(j["figures"].size(), 4u);
  for (const auto& f : j["figures"]) {
    // The compensated per-cycle std is the sensor's white noise (ARW fitted to these figures).
    EXPECT_NEAR(f["std_ratio"].get<double>(), 1.0, 0.15) << f;
    EXPECT_LT(f["abba_std_dps"].get<double>(), f["std_dps"].get<double>()) << f;
  }
  EXPECT_TRUE(j["beyond"].contains("north_finding"));
  EXPECT_NEAR(j["beyond"]["earth"]["eqn9_north_dps"].get<double>(), 3.0755e-3, 1e-6);
  EXPECT_TRUE(std::filesystem::exists(out + "/index.html"));
  EXPECT_TRUE(std::filesystem::exists(out + "/figures/tab3_4c.png"));
  // Figures numbered as the paper's: Fig. 3 is the ADXRS150's 0/180 outputs, Fig. 4 their
  // compensation; the main claim's Allan plots.
  for (const char* f : {"fig3_adxrs150_outputs", "fig4_adxrs150_compensated",
                        "fig5_adxrs150_outputs", "fig7_hz1-90-100a_outputs",
                        "fig10_hz1-90-100a_compensated", "allan_hz1-90-100a_off_before"})
    EXPECT_TRUE(std::filesystem::exists(out + "/figures/" + std::string(f) + ".png")) << f;
  ASSERT_EQ(j["tab3_4c_from_20c_model"].size(), 1u);
  EXPECT_EQ(j["tab3_4c_from_20c_model"][0]["runs"].size(), 13u);
  // The verdict is the predictions': none of them is a calibration target.
  ASSERT_EQ(j["predictions"].size(), 10u);
  ASSERT_EQ(j["not_counted"].size(), 1u);
  bool all = true;
  for (const auto& p : j["predictions"]) {
    all = all && p["pass"].get<bool>();
    for (const auto& t : j["targets"])
      EXPECT_NE(p["quantity"].get<std::string>(), t["quantity"].get<std::string>());
  }
  EXPECT_EQ(j["reproduced"].get<bool>(), all && j["verdict"] == "reproduced");
  // The main claim: the compensated Allan deviation below the raw at the longest common tau.
  ASSERT_EQ(j["claim"]["adev"].size(), 4u);
  for (const auto& a : j["claim"]["adev"])
    EXPECT_LT(a["compensated_dps"].get<double>(), a["raw_dps"].get<double>()) << a;
  // Each main-claim number with its spread over the figure's simulated runs (the figure run and
  // its replicates, max(1, 8) = 8 of them): the figure's own run inside the range, the range
  // not one run's (a table made from one realisation has min == max).
  ASSERT_EQ(j["claim"]["runs_per_figure"].get<int>(), 8);
  const auto within = [](double own, const json& s) {
    EXPECT_EQ(s["runs"].get<int>(), 8) << s;
    EXPECT_LE(s["min"].get<double>(), own) << s;
    EXPECT_GE(s["max"].get<double>(), own) << s;
    EXPECT_LT(s["min"].get<double>(), s["max"].get<double>()) << s;
  };
  for (const auto& a : j["claim"]["adev"]) {
    within(a["raw_dps"].get<double>(), a["runs_raw_dps"]);
    within(a["compensated_dps"].get<double>(), a["runs_compensated_dps"]);
    within(a["raw_dps"].get<double>() / a["compensated_dps"].get<double>(), a["runs_ratio"]);
  }
  // Raw beside compensated drift for each window (the paper's own comparison): the raw drift of
  // a sensor that is not flipped is larger at every window.
  for (const auto& row : j["claim"]["drift"])
    for (const std::string f : {"fig4", "fig6", "fig8", "fig10"}) {
      ASSERT_TRUE(row.contains("raw_" + f)) << row;
      if (row[f].is_number()) within(row[f].get<double>(), row[f + "_runs"]);
      if (row["raw_" + f].is_number()) {
        within(row["raw_" + f].get<double>(), row["raw_" + f + "_runs"]);
        EXPECT_GT(row["raw_" + f].get<double>(), row[f].get<double>()) << row;
      }
    }
  EXPECT_NE(r.out.find("The main claim: drift against the averaging window, ADXRS150"),
            std::string::npos);
  EXPECT_NE(r.out.find("Fig. 7 raw (0°)"), std::string::npos);
  for (const auto& f : j["figures"]) {
    ASSERT_EQ(f["runs"].size(), 8u) << f;
    EXPECT_NEAR(f["runs"][0]["std_dps"].get<double>(), f["std_dps"].get<double>(),
                1e-12 * f["std_dps"].get<double>())
        << f;
  }
  for (const char* f : {"fig8", "fig10"}) {
    const auto& w = j["claim"]["window_for_claim_runs"][f];
    EXPECT_EQ(w["runs"].get<int>(), 8) << w;
    if (j["claim"]["window_for_claim_s"][f].is_number()) {
      EXPECT_LE(w["min"].get<double>(), j["claim"]["window_for_claim_s"][f].get<double>());
    }
  }
  // Provenance in summary.json as on the page.
  for (const char* k : {"command", "made_utc", "version", "commit"})
    EXPECT_TRUE(j[k].is_string()) << k;
  EXPECT_NE(j["command"].get<std::string>().find("reproduce --quick"), std::string::npos) << j;
  EXPECT_FALSE(j.contains("sensitivity"));  // not with --quick
  EXPECT_EQ(j["verdict_scope"], "quick check");
}

// --campaigns 0 was taken as "the default"; a count outside 1..1000 is refused, before any
// simulation and without a folder.
TEST(ReproduceCli, ACampaignCountOutsideItsRangeIsRefused) {
  temp_dir d;
  for (const char* k : {"0", "1001"}) {
    const auto r = run_cli({"reproduce", "--quick", "--campaigns", k, "-o", d.file("r")});
    EXPECT_EQ(r.exit_code, 2) << k << r.err;
    EXPECT_NE(r.err.find("--campaigns"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(d.file("r"))) << k;
  }
}

// --sensor NAME=FILE.toml (issue 31): a user's model goes through the same tests as the preset,
// and what it states is fitted to nothing: an HZ1 with 3 times its ARW fails its noise tests (it
// read "reproduced" before). What it inherits from its base preset fitted to the paper is no
// prediction (fifth review of issue 31, F10: the 4 degC table, decided by the preset's fitted
// temperature coefficients, was counted as the model's): a calibration target, named in the
// headline and summary.json. The file is named on the page's provenance with its SHA-256 and in
// summary.json; the page's title and a banner say which model was given.
TEST(ReproduceCli, AGivenSensorModelGoesThroughTheSameTests) {
  temp_dir d;
  const auto toml = d.file("hz1_3x.toml");
  std::ofstream(toml)
      << "name = \"hz1-3x-arw\"\nbase = \"hz1-90-100a\"\narw_dps_rthz = 0.0138\n"
         "g_sens_z_dps_per_g = -1.45e-5\ng_sens_turn_on_sigma_dps_per_g = 0.000959\n";
  const auto r =
      run_cli({"reproduce", "--quick", "--sensor", "hz1-90-100a=" + toml, "-o", d.file("r")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(std::ifstream(d.file("r/summary.json")));
  EXPECT_EQ(j["verdict"], "NOT reproduced");
  EXPECT_FALSE(j["reproduced"].get<bool>());
  json failed = json::array();
  for (const auto& p : j["predictions"])
    if (p["outcome"] == "FAIL") failed.push_back(p["id"]);
  EXPECT_EQ(failed, json({"fig8_std", "fig10_std"})) << j["predictions"];
  // Restated: the 20 degC table is a test. Inherited fitted (its temperature coefficients): the
  // 4 degC table is not, but a target, and the 20-degC-only model's 4 degC test is counted.
  json ids = json::array();
  for (const auto& p : j["predictions"]) ids.push_back(p["id"]);
  for (const char* id : {"tab3_20c_mean", "tab3_20c_std", "tab3_4c_mean_from_20c"})
    EXPECT_NE(std::find(ids.begin(), ids.end(), id), ids.end()) << id << ids;
  for (const char* id : {"tab3_4c_mean", "tab3_4c_std"})
    EXPECT_EQ(std::find(ids.begin(), ids.end(), id), ids.end()) << id << ids;
  EXPECT_EQ(j["inherited_fitted"],
            json({{{"sensor", "hz1-90-100a"}, {"key", "g_sens_tc_z_dps_per_g_c"}},
                  {{"sensor", "hz1-90-100a"}, {"key", "g_sens_tc_turn_on_sigma_dps_per_g_c"}}}));
  EXPECT_NE(j["headline"].get<std::string>().find("g_sens_tc_z_dps_per_g_c"), std::string::npos);
  ASSERT_EQ(j["given_sensor_models"].size(), 1u);
  EXPECT_EQ(j["given_sensor_models"][0]["sensor"], "hz1-90-100a");
  EXPECT_EQ(j["given_sensor_models"][0]["sha256"].get<std::string>().size(), 64u);
  EXPECT_NE(r.out.find("given sensor model: HZ1-90-100A (" + toml), std::string::npos) << r.out;
  const auto html = read_page(d.file("r/index.html"));
  EXPECT_NE(html.find("given models of the HZ1-90-100A</h1>"), std::string::npos);
  EXPECT_NE(html.find(j["given_sensor_models"][0]["sha256"].get<std::string>()), std::string::npos);
  EXPECT_NE(html.find("Given sensor model: the HZ1-90-100A of " + toml), std::string::npos);
  // Every ± is a real standard error (review of issue 31: "0.00319 ± 0" for the mean of one
  // --quick campaign, the spread of one campaign mean): the mean of k campaigns of n runs has
  // s / sqrt(n k), s the runs' pooled std within their campaigns, and nothing prints "± 0".
  for (const auto& t : j["tables"]) {
    if (t["sensor"] != "hz1-90-100a") continue;
    double var = 0.0;
    for (const auto& c : t["per_campaign"])
      var += std::pow(c["std_dps"].get<double>(), 2) / static_cast<double>(t["campaigns"]);
    const double se = std::sqrt(var / (t["runs"].get<double>() * t["campaigns"].get<double>()));
    const auto p = std::find_if(
        j["predictions"].begin(), j["predictions"].end(),
        [&](const json& q) { return q["id"] == t["id"].get<std::string>() + "_mean"; });
    if (t["id"] == "tab3_4c") {  // inherited fitted: no test
      EXPECT_EQ(p, j["predictions"].end());
      continue;
    }
    ASSERT_NE(p, j["predictions"].end()) << t["id"];
    EXPECT_GT(se, 0.0);
    EXPECT_NEAR((*p)["u_predicted"].get<double>(), se, 1e-12 * se) << t["id"];
  }
  const std::regex zero("± 0(?![.0-9])");
  EXPECT_FALSE(std::regex_search(r.out, zero)) << r.out;
  EXPECT_FALSE(std::regex_search(html, zero));
}

// A model named other than the paper's sensors, given twice, a built-in name for a file, an
// option without '=', a missing file, and a TOML error: each refused (exit 2) before any
// simulation, naming the option or the file (and line), with no folder.
TEST(ReproduceCli, ABadSensorModelIsRefusedBeforeAnySimulation) {
  temp_dir d;
  const auto good = d.file("good.toml"), bad = d.file("bad.toml");
  std::ofstream(good) << "name = \"x\"\nbase = \"adxrs150\"\n";
  std::ofstream(bad) << "name = \"x\"\nbase = \"adxrs150\"\narw_dps_rthz = \"loud\"\n";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--sensor", "adxrs300=" + good}, "'adxrs300' is not one of the paper's sensors"},
      {{"--sensor", "adxrs150=" + good, "--sensor", "adxrs150=" + good}, "given twice"},
      {{"--sensor", "adxrs150=hz1-90-100a"}, "a TOML file is expected"},
      {{"--sensor", good}, "expected NAME=FILE.toml"},
      {{"--sensor", "adxrs150=" + d.file("none.toml")}, d.file("none.toml")},
      {{"--sensor", "adxrs150=" + bad}, bad + ":3:"}};
  for (const auto& [args, message] : cases) {
    std::vector<std::string> cmd{"reproduce", "--quick", "-o", d.file("r")};
    cmd.insert(cmd.end(), args.begin(), args.end());
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 2) << message << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    if (message.find("NAME=FILE") != std::string::npos ||
        message.find("twice") != std::string::npos) {
      EXPECT_NE(r.err.find("(option --sensor)"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(d.file("r"))) << message;
  }
}

// Seed 1, ten campaigns: every test holds but the HZ1's 4 degC std from the 20-degC-only model,
// which lies at -1.98 sigma of its 2-sigma limit within twice its simulation error (0.15 sigma):
// the verdict is "inconclusive" (without the simulation's error it would lie at about -1.99
// sigma: the paper's 4 degC spread is at the edge of what its 20 degC spread predicts).
TEST(ReproduceCli, TenCampaignsKeepTheFitAndTheirVerdictSaysWhatItCovers) {
#if defined(__SANITIZE_ADDRESS__)
  // 90 s in the Release suite, several times that under the sanitizers (the CI's budget): the
  // Release suite checks these numbers; the other ReproduceCli tests run the same code here.
  GTEST_SKIP() << "ten campaigns: checked by the Release suite";
#endif
  temp_dir d;
  const auto r = run_cli({"reproduce", "--campaigns", "10", "--seed", "1", "-o", d.file("r")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("verdict: inconclusive: 6 of 7 tests of the model's predictions hold, and "
                       "3 of 3 leave-one-run-out tests"),
            std::string::npos)
      << r.out;
  const auto j = json::parse(std::ifstream(d.file("r/summary.json")));
  json not_passed = json::array();
  for (const auto& p : j["predictions"])
    if (p["outcome"] != "pass" && p["outcome"] != "pass (marginal)") not_passed.push_back(p["id"]);
  EXPECT_EQ(not_passed, json({"tab3_4c_std_from_20c"}));
  ASSERT_EQ(j["tables"][0]["per_campaign"].size(), 10u);
  ASSERT_EQ(j["tab3_4c_from_20c_model"].size(), 10u);
  ASSERT_EQ(j["figures"][0]["runs"].size(), 10u);
  // The fit (a regression): ensemble means within 15 %, stds within 25 % of the paper's.
  for (const auto& t : j["tables"]) {
    EXPECT_NEAR(t["mean_ratio"].get<double>(), 1.0, 0.15) << t;
    EXPECT_NEAR(t["std_ratio"].get<double>(), 1.0, 0.25) << t;
  }
  // The sensitivity study: the baseline and every assumed value changed.
  ASSERT_EQ(j["sensitivity"].size(), 13u);
  // Every row can move a column (review R9): the time on before the warm-start figures moves
  // their raw side, and the campaigns' warm-up their mean dN (fitted targets, shown not judged).
  const auto& base = j["sensitivity"][0];
  for (const auto& row : j["sensitivity"]) {
    const auto name = row["assumption"].get<std::string>();
    const auto moved = [&](const char* key) {
      return std::abs(row[key].get<double>() / base[key].get<double>() - 1.0);
    };
    if (name.starts_with("\"on before\" = 10 min")) {
      EXPECT_GT(std::max(moved("fig6_raw_adev_dps"), moved("fig10_raw_adev_dps")), 0.01) << row;
    }
    if (name.starts_with("campaign runs on 5 min")) {
      EXPECT_GT(std::max(moved("tab3_20c_mean_dps"), moved("tab4_mean_dps")), 0.0) << row;
    }
    // The ADXRS150's datasheet density read as N (not N/sqrt 2): its per-cycle std grows by
    // sqrt 2 and fails the verdict's noise tests (review of issue 31: +39 %, +43 %).
    if (name.starts_with("ADXRS150 datasheet density read as N")) {
      EXPECT_NEAR(row["fig4_std_ratio"].get<double>() / base["fig4_std_ratio"].get<double>(),
                  std::sqrt(2.0), 0.05)
          << row;
      EXPECT_GT(row["fig4_std_ratio"].get<double>(), 1.15) << row;
      EXPECT_GT(row["fig6_std_ratio"].get<double>(), 1.15) << row;
      EXPECT_EQ(row["verdict"], "NOT reproduced") << row;
    }
    // 1.79 s per position (a cycle of two positions, 256 conversions per dwell): the per-cycle
    // std stays (the same dwells), half as many cycles per second need a moving mean about
    // twice as long for 0.002 deg/s (review of issue 31: ~310 s -> ~590 s).
    if (name.starts_with("1.79 s per position")) {
      EXPECT_NEAR(moved("fig4_std_ratio"), 0.0, 0.05) << row;
      EXPECT_GT(row["fig8_window_s"].get<double>(), 1.5 * base["fig8_window_s"].get<double>());
      EXPECT_GT(row["fig10_window_s"].get<double>(), 1.5 * base["fig10_window_s"].get<double>());
    }
  }
  const std::string headline = j["headline"];
  EXPECT_NE(headline.find("read as N = 0.05 the per-cycle std of Figs 4/6 misses by +"),
            std::string::npos)
      << headline;
  // "0.002 deg/s over 2.5 h": the HZ1 runs reach it from some averaging window on.
  EXPECT_TRUE(j["claim"]["window_for_claim_s"]["fig8"].is_number());
  EXPECT_TRUE(j["claim"]["window_for_claim_s"]["fig10"].is_number());
}

TEST(ReproduceCli, TurnOnVariationIsVisibleWithItsSource) {
  const auto r = run_cli({"sensors"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("g_sens_turn_on_sigma_dps_per_g"), std::string::npos);
  EXPECT_NE(r.out.find("fitted to paper Tab. 4"), std::string::npos);
  EXPECT_NE(r.out.find("fitted to paper Tab. 3"), std::string::npos);
}

}  // namespace
