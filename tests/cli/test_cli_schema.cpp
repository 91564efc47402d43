// One JSON convention for every command (issue 22): every object gyroflip prints with --json or
// writes as JSON carries "schema": "gyroflip.<what>/<N>" and "version" (io/schema.hpp). Before,
// earth, sensors, adev and noise carried neither and compensate had its own "schema_version".
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/version.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using gyroflip::test::run_cli;
using gyroflip::test::temp_dir;
using nlohmann::json;

void expect_schema(const json& j, const std::string& schema, const std::string& what) {
  ASSERT_TRUE(j.is_object()) << what;
  EXPECT_EQ(j.value("schema", ""), schema) << what;
  EXPECT_EQ(j.value("version", ""), std::string(gyroflip::version())) << what;
}

json printed(const std::vector<std::string>& args) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? json::parse(r.out) : json();
}

TEST(CliSchema, EveryJsonOutputCarriesItsSchemaAndVersion) {
  temp_dir d;
  const auto rec = d.file("rec.csv"), cal = d.file("cal.json");
  ASSERT_EQ(
      run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "600", "-o", rec}).exit_code,
      0);
  // A series of two numeric columns for adev/noise.
  std::string two = "time_s,a,b\n";
  for (int k = 0; k < 4000; ++k)
    two += std::to_string(0.01 * k) + "," + std::to_string((k * 7919 % 1000) / 1000.0) + "," +
           std::to_string((k * 104729 % 997) / 997.0) + "\n";
  gyroflip::test::write_text(d.file("two.csv"), two);
  const auto s2 = d.file("two.csv");
  expect_schema(printed({"earth", "--latitude", "42.6", "--json"}), "gyroflip.earth/1", "earth");
  expect_schema(printed({"sensors", "--json"}), "gyroflip.sensors/1", "sensors");
  expect_schema(printed({"calibrate", rec, "--json"}), "gyroflip.calibration/5", "calibrate");
  ASSERT_EQ(run_cli({"calibrate", rec, "-o", cal}).exit_code, 0);
  expect_schema(json::parse(std::ifstream(cal)), "gyroflip.calibration/5", "calibrate -o");
  expect_schema(printed({"compensate", rec, "--calibration", cal, "--json"}),
                "gyroflip.compensate/2", "compensate");
  expect_schema(printed({"adev", s2, "--column", "a", "--json"}), "gyroflip.adev/1", "adev");
  const auto cols = printed({"adev", s2, "--column", "a,b", "--json"});
  expect_schema(cols, "gyroflip.adev_columns/1", "adev columns");
  expect_schema(cols["columns"][1], "gyroflip.adev/1", "adev column");
  expect_schema(printed({"adev", s2, "--column", "a", "--dynamic", "10", "--json"}),
                "gyroflip.adev_dynamic/1", "adev --dynamic");
  expect_schema(printed({"adev", s2, "--column", "a,b", "--codev", "--json"}),
                "gyroflip.adev_curves/1", "adev --codev");
  expect_schema(printed({"noise", s2, "--column", "a", "--json"}), "gyroflip.noise/1", "noise");
  const auto ncols = printed({"noise", s2, "--column", "a,b", "--json"});
  expect_schema(ncols, "gyroflip.noise_columns/1", "noise columns");
  expect_schema(ncols["columns"][0], "gyroflip.noise/1", "noise column");
  // The report folders' summary.json (they need gnuplot to draw their figures).
  if (gyroflip::test::run_program({"gnuplot", "--version"}).exit_code != 0) return;
  ASSERT_EQ(run_cli({"report", rec, "-o", d.file("rep")}).exit_code, 0);
  expect_schema(json::parse(std::ifstream(d.file("rep/summary.json"))), "gyroflip.report/3",
                "report");
  const auto rep = run_cli({"reproduce", "--quick", "-o", d.file("repro")});
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  expect_schema(json::parse(std::ifstream(d.file("repro/summary.json"))), "gyroflip.reproduce/5",
                "reproduce");
}

}  // namespace
