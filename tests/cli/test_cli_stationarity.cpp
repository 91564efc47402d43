// Issue 31 item 1: nothing non-stationary passes as a calibration. The issue's reproductions (a
// run on a turning table, a 0.1 deg/s input, a zero-mean sine) are warned about by `calibrate`,
// refused by `calibrate --strict` (exit 2, no file), recorded in the calibration JSON (schema 3),
// and a report compensating with such a calibration does not vouch for it; an older calibration
// reads as "not checked".
#include <string>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

using nlohmann::json;

std::string simulate(const temp_dir& d, const std::string& name, const std::string& seed,
                     const std::string& rate) {
  const auto f = d.file(name);
  const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "900", "--temp",
                          "20", "--seed", seed, "--rate-profile", rate, "-o", f});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return f;
}

json stationarity_of(const std::string& calibrate_json) {
  return json::parse(calibrate_json)["files"][0]["stationarity"];
}

TEST(CliStationarity, TheIssuesRunsAreWarnedAboutRefusedWithStrictAndRecorded) {
  temp_dir d;
  const auto still = simulate(d, "still.csv", "32", "0");
  const auto turning = simulate(d, "turning.csv", "31", "0.5");
  const auto slow = simulate(d, "slow.csv", "33", "0.1");
  const auto sine = simulate(d, "sine.csv", "34", "sine:0.5:0.002");

  const auto ok = run_cli({"calibrate", still, "--json"});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("not a stationary run"), std::string::npos) << ok.err;
  const auto st = stationarity_of(ok.out);
  EXPECT_EQ(st["checked"], true);
  EXPECT_EQ(st["stationary"], true);
  EXPECT_EQ(json::parse(ok.out)["schema"], "gyroflip.calibration/3");

  struct case_ {
    std::string file, statistic;
    bool scatter, g_term;
  };
  for (const auto& c : {case_{turning, "g-term", false, true}, case_{slow, "g-term", false, true},
                        case_{sine, "scatter", true, false}}) {
    const auto r = run_cli({"calibrate", c.file, "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find(c.file + ": not a stationary run"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.statistic), std::string::npos) << r.err;
    const auto s = stationarity_of(r.out);
    EXPECT_EQ(s["stationary"], false) << c.file;
    EXPECT_EQ(s["scatter_failed"], c.scatter) << c.file;
    EXPECT_EQ(!s["g_term"].is_null() && s["g_term"]["failed"].get<bool>(), c.g_term) << c.file;
    // --strict refuses it: bad input, and no calibration file.
    const auto strict = run_cli({"calibrate", c.file, "--strict", "-o", d.file("bad.json")});
    EXPECT_EQ(strict.exit_code, 2) << strict.err;
    EXPECT_FALSE(exists(d.file("bad.json")));
    EXPECT_NE(strict.err.find(c.statistic), std::string::npos) << strict.err;
  }
  // The human text does not call the turning run's mean the sensor's dN, gives nothing to quote,
  // and with a good run among the failed ones names the command without them.
  const auto text = run_cli({"calibrate", turning});
  EXPECT_NE(text.out.find("NOT A CALIBRATION"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("quote:"), std::string::npos) << text.out;
  const auto mixed = run_cli({"calibrate", still, turning});
  EXPECT_NE(mixed.out.find("leave the failed runs out: gyroflip calibrate " + still + "\n"),
            std::string::npos)
      << mixed.out;
}

// Review of issue 31: `compensate` applied a calibration its own file marks as not stationary,
// without a word; a hand-edited negative statistic was read.
TEST(CliStationarity, CompensateWarnsAboutAndStrictRefusesACalibrationOfATurningRun) {
  temp_dir d;
  const auto still = simulate(d, "still.csv", "32", "0");
  const auto turning = simulate(d, "turning.csv", "31", "0.5");
  ASSERT_EQ(run_cli({"calibrate", turning, "-o", d.file("bad.json")}).exit_code, 0);
  const auto warned = run_cli({"compensate", still, "--calibration", d.file("bad.json"), "--json"});
  ASSERT_EQ(warned.exit_code, 0) << warned.err;
  EXPECT_NE(warned.err.find(d.file("bad.json") + ": its run " + turning + ": not a stationary run"),
            std::string::npos)
      << warned.err;
  const auto strict = run_cli({"compensate", still, "--calibration", d.file("bad.json"), "--strict",
                               "-o", d.file("out.csv")});
  EXPECT_EQ(strict.exit_code, 2) << strict.err;
  EXPECT_NE(strict.err.find("g-term"), std::string::npos) << strict.err;
  EXPECT_FALSE(exists(d.file("out.csv")));
  // A good calibration passes --strict without a warning.
  ASSERT_EQ(run_cli({"calibrate", still, "-o", d.file("good.json")}).exit_code, 0);
  const auto good = run_cli({"compensate", still, "--calibration", d.file("good.json"), "--strict",
                             "-o", d.file("good.csv")});
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_EQ(good.err.find("stationary"), std::string::npos) << good.err;
  // calibrate says what its test cannot see: a constant input below the g-term limit.
  EXPECT_NE(run_cli({"calibrate", still}).out.find("cannot see a constant input below 0.06 deg/s"),
            std::string::npos);
  // A negative statistic in the file is refused, naming the file.
  auto cal = json::parse(read_text(d.file("good.json")));
  cal["files"][0]["stationarity"]["drift_statistic"] = -1.0;
  write_text(d.file("edited.json"), cal.dump());
  const auto edited = run_cli({"compensate", still, "--calibration", d.file("edited.json")});
  EXPECT_EQ(edited.exit_code, 2) << edited.err;
  EXPECT_NE(edited.err.find("negative"), std::string::npos) << edited.err;
}

TEST(CliStationarity, AReportNeverVouchesForACalibrationOfATurningRun) {
  temp_dir d;
  const auto still = simulate(d, "still.csv", "32", "0");
  const auto turning = simulate(d, "turning.csv", "31", "0.5");
  ASSERT_EQ(run_cli({"calibrate", turning, "-o", d.file("bad.json")}).exit_code, 0);
  const auto r =
      run_cli({"report", still, "--calibration", d.file("bad.json"), "-o", d.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto page = read_text(d.file("rep/index.html"));
  EXPECT_EQ(page.find("Nothing in the runs looks wrong"), std::string::npos);
  EXPECT_NE(page.find("is not the sensor's"), std::string::npos);
  // A calibration written before the test (schema 2, no stationarity) is "not checked".
  auto cal = json::parse(read_text(d.file("bad.json")));
  cal["schema"] = "gyroflip.calibration/2";
  cal["files"][0].erase("stationarity");
  cal.erase("uncertainty");
  write_text(d.file("old.json"), cal.dump());
  const auto old =
      run_cli({"report", still, "--calibration", d.file("old.json"), "-o", d.file("rep2")});
  ASSERT_EQ(old.exit_code, 0) << old.err;
  EXPECT_NE(old.err.find("not checked for stationarity"), std::string::npos) << old.err;
  // calibrate's own report of the turning run headlines no dN.
  const auto own = run_cli({"report", turning, "-o", d.file("rep3")});
  ASSERT_EQ(own.exit_code, 0) << own.err;
  EXPECT_NE(read_text(d.file("rep3/index.html")).find("These runs give no ΔN"), std::string::npos);
}

}  // namespace
}  // namespace gyroflip::test
