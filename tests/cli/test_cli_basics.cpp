// The CLI's global contract: --help, --version, exit codes, `earth`.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/run_cli.hpp"

namespace gyroflip::test {
namespace {

TEST(CliBasics, VersionAndHelp) {
  const auto v = run_cli({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("gyroflip 0."), std::string::npos);
  const auto h = run_cli({"--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("earth"), std::string::npos);
  EXPECT_EQ(run_cli({"earth", "--help"}).exit_code, 0);
}

TEST(CliBasics, UsageErrorsExitTwo) {
  EXPECT_EQ(run_cli({}).exit_code, 2);
  EXPECT_EQ(run_cli({"no-such-command"}).exit_code, 2);
  EXPECT_EQ(run_cli({"no-such-command", "--help"}).exit_code, 2);  // probes must not see success
  EXPECT_EQ(run_cli({"earth"}).exit_code, 2);                      // --latitude is required
  const auto bad = run_cli({"earth", "--latitude", "95"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("latitude"), std::string::npos);
  EXPECT_EQ(run_cli({"earth", "--latitude", "10", "--axis", "sideways"}).exit_code, 2);
}

TEST(CliBasics, EarthPrintsPaperValue) {
  const auto r = run_cli({"earth", "--latitude", "42.6", "--axis", "north", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j.at("earth_rate_dps").get<double>(), 3.0755e-3, 0.5e-7);  // paper eqn 9
  const auto text = run_cli({"earth", "--latitude", "42.6", "--axis", "up"});
  ASSERT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("2.82"), std::string::npos);
}

}  // namespace
}  // namespace gyroflip::test

#include <cstdio>

namespace gyroflip::test {
namespace {

TEST(CliBasics, BrokenPipeExitsZero) {
  // `gyroflip compensate ... | head -1`: the writer must not die of SIGPIPE or report an error.
  const std::string cmd = std::string(GYROFLIP_EXE) + " compensate " + GYROFLIP_VECTORS_DIR +
                          "/demo/cal_stationary_20c.csv --delta-n 0.39 | head -c 10 >/dev/null; "
                          "echo \"${PIPESTATUS[0]}\"";
  std::FILE* p = ::popen(("bash -c '" + cmd + "'").c_str(), "r");
  ASSERT_NE(p, nullptr);
  char buf[16] = {};
  ASSERT_NE(std::fgets(buf, sizeof buf, p), nullptr);
  ::pclose(p);
  EXPECT_EQ(std::string(buf), "0\n");
}

}  // namespace
}  // namespace gyroflip::test
