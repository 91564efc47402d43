// Finite but extreme inputs (issue 13 items 8 and 9, reviewed 2026-11-22: 68 cases gave non-finite
// output with exit 0). Every case through every command it feeds must end in one of two ways:
// exit 0 with every number written finite, or exit 2 with a `gyroflip: error:` message and no
// output file. Neither a crash, nor exit 0 with `inf`/`nan`, nor a half-written file.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

// A 60-dwell recording whose column `col` is replaced by `value` (rate alternates its sign).
std::string recording(const std::string& col, const std::string& value) {
  std::string s = "time_s,angle_deg,rate_dps,temp_c,n_avg\n";
  for (int k = 0; k < 60; ++k) {
    std::string t = std::to_string(k * 0.9);
    std::string a = k % 2 == 0 ? "0" : "180";
    std::string r = k % 2 == 0 ? "0.21" : "0.19";
    std::string c = "20";
    std::string n = "256";
    if (col == "time_s")
      t = value == "step" ? std::to_string(k) + "e-300" : value + std::to_string(k);
    if (col == "rate_dps") r = (k % 2 == 0 || value[0] == '0') ? value : "-" + value;
    if (col == "temp_c") c = value;
    if (col == "n_avg") n = value;
    s += t + "," + a + "," + r + "," + c + "," + n + "\n";
  }
  return s;
}

std::string npy(const std::vector<double>& v) {
  std::string h =
      "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(v.size()) + ",), }";
  while ((10 + h.size() + 1) % 64 != 0) h += ' ';
  h += '\n';
  std::string out = "\x93NUMPY\x01";
  out += '\0';
  out += static_cast<char>(h.size() & 0xff);
  out += static_cast<char>(h.size() >> 8);
  out += h;
  for (double x : v) out.append(reinterpret_cast<const char*>(&x), 8);  // NOLINT
  return out;
}

// No token of `text` is a non-finite number.
bool all_finite(const std::string& text) {
  std::string tok;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const char c = i < text.size() ? text[i] : ',';
    if (c == ',' || c == '\n' || c == ' ' || c == ':' || c == '[' || c == ']' || c == '{' ||
        c == '}' || c == '"') {
      std::string t = tok;
      if (!t.empty() && (t[0] == '-' || t[0] == '+')) t.erase(0, 1);
      for (auto& ch : t) ch = static_cast<char>(std::tolower(ch));
      if (t == "nan" || t == "inf" || t == "infinity") return false;
      tok.clear();
    } else {
      tok += c;
    }
  }
  return true;
}

struct outcome_counts {
  int ok = 0;
  int refused = 0;
};

// Runs `args` (an output file `out` among them, or none) and checks the contract; `also` is a
// second output of the same run, which must exist exactly when `out` does (all or none).
void check(const std::vector<std::string>& args, const std::string& out, outcome_counts& n,
           const std::string& also = {}) {
  const auto r = run_cli(args);
  std::string what;
  for (const auto& a : args) what += a.substr(0, 60) + " ";
  if (r.exit_code == 0) {
    ++n.ok;
    EXPECT_TRUE(all_finite(r.out)) << what << "\n" << r.out.substr(0, 400);
    if (!out.empty()) {
      EXPECT_TRUE(all_finite(read_text(out))) << what;
    }
  } else {
    ++n.refused;
    EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("gyroflip: error: ", 0), 0u) << what << "\n" << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    if (!out.empty()) {
      EXPECT_FALSE(exists(out)) << what;
    }
  }
  if (!also.empty()) {
    EXPECT_EQ(exists(also), exists(out)) << what;
    std::remove(also.c_str());
  }
  if (!out.empty()) std::remove(out.c_str());
}

TEST(CliExtremes, RecordingsThroughEveryCommand) {
  temp_dir d;
  const std::vector<std::pair<std::string, std::string>> cases{
      {"rate_dps", "1e308"},   {"rate_dps", "1e100"},   {"rate_dps", "1e101"},
      {"rate_dps", "1e-320"},  {"rate_dps", "5e-324"},  {"rate_dps", "0"},
      {"n_avg", "4294967295"}, {"n_avg", "4294967296"}, {"n_avg", "1e300"},
      {"temp_c", "1e300"},     {"temp_c", "-300"},      {"temp_c", "1000"},
      {"temp_c", "-273.15"},   {"time_s", "1.7e18"},    {"time_s", "1e300"},
      {"time_s", "step"},      {"time_s", "-1e99"},
  };
  outcome_counts n;
  for (const auto& [col, value] : cases) {
    const auto f = d.file("rec.csv");
    write_text(f, recording(col, value));
    const auto o = d.file("out.csv");
    check({"calibrate", f, "-o", d.file("cal.json")}, d.file("cal.json"), n);
    check({"calibrate", f, "--json", "--latitude", "42.6", "--axis", "north"}, "", n);
    check({"compensate", f, "--delta-n", "0.01", "-o", o}, o, n);
    check({"compensate", f, "--delta-n", "0.01", "--json"}, "", n);
    check({"adev", f, "-o", o}, o, n);
    check({"adev", f, "--kind", "totdev", "--json"}, "", n);
    check({"noise", f, "--json"}, "", n);
    check({"noise", f}, "", n);
  }
  EXPECT_GT(n.ok, 0);
  EXPECT_GT(n.refused, 0);
}

TEST(CliExtremes, SeriesAndSampleRates) {
  temp_dir d;
  const auto f = d.file("s.npy");
  const std::vector<std::pair<std::vector<double>, std::string>> cases{
      {{1e200, -1e200, 1e200, -1e200, 1e200}, "100"},
      {{1e100, -1e100, 1e100, -1e100, 1e100}, "100"},
      {{1e-300, 2e-300, 3e-300, 1e-300, 2e-300}, "100"},
      {{0, 0, 0, 0, 0, 0}, "100"},
      {{1, 1, 1, 1, 1, 1}, "100"},
      {{1, 2, 1, 2, 1, 2}, "1e-300"},
      {{1, 2, 1, 2, 1, 2}, "1e300"},
      {{1, 2, 1, 2, 1, 2}, "1e-9"},
      {{1, 2, 1, 2, 1, 2}, "1e9"},
  };
  outcome_counts n;
  for (const auto& [v, rate] : cases) {
    write_text(f, npy(v));
    for (const char* kind : {"oadev", "mdev", "tdev", "hdev", "totdev", "adev", "ohdev"})
      check({"adev", f, "--rate", rate, "--kind", kind, "-o", d.file("o.csv")}, d.file("o.csv"), n);
    check({"adev", f, "--rate", rate, "--input", "angle", "--json"}, "", n);
    check({"noise", f, "--rate", rate, "--json"}, "", n);
  }
  EXPECT_GT(n.ok, 0);
  EXPECT_GT(n.refused, 0);
}

TEST(CliExtremes, CalibrationFiles) {
  temp_dir d;
  write_text(d.file("rec.csv"), recording("rate_dps", "0.2"));
  const std::vector<std::string> cals{
      R"({"delta_n_dps": 1e300})",
      R"({"delta_n_dps": 1e-320})",
      R"({"delta_n_dps": 0.01, "stderr_correlated_dps": -1})",
      R"({"delta_n_dps": 0.01, "model": {"kind": "poly", "coeffs_dps": [1e300, 1], "t_ref_c": 20, "temp_range_c": [0, 30]}})",
      R"({"delta_n_dps": 0.01, "model": {"kind": "poly", "coeffs_dps": [0.01, 1e90, 1e90, 1e90, 1e90, 1e90, 1e90], "t_ref_c": 20, "temp_range_c": [0, 30]}})",
      R"({"delta_n_dps": 0.01, "model": {"kind": "poly", "coeffs_dps": [0.01, 1e-3], "t_ref_c": 20, "temp_range_c": [30, 0]}})",
      R"({"delta_n_dps": 0.01, "model": {"kind": "poly", "coeffs_dps": [0.01, 1e-3], "t_ref_c": 1e300, "temp_range_c": [0, 30]}})",
      R"({"delta_n_dps": 0.01, "model": {"kind": "poly", "coeffs_dps": [0.01, 1, 1, 1, 1, 1, 1, 1, 1], "t_ref_c": 20, "temp_range_c": [0, 30]}})",
      R"({"delta_n_dps": 0.01, "model": {"kind": "poly", "coeffs_dps": [0.01, 1e-3], "t_ref_c": 20, "cov": [1e308, 1e308, 1e308, 1e308], "temp_range_c": [0, 30]}})",
  };
  outcome_counts n;
  for (const auto& c : cals) {
    write_text(d.file("cal.json"), c);
    check({"compensate", d.file("rec.csv"), "--calibration", d.file("cal.json"), "-o",
           d.file("o.csv")},
          d.file("o.csv"), n);
    check({"compensate", d.file("rec.csv"), "--calibration", d.file("cal.json"), "--json"}, "", n);
  }
  check({"compensate", d.file("rec.csv"), "--delta-n", "1e300", "-o", d.file("o.csv")},
        d.file("o.csv"), n);
  EXPECT_GT(n.ok, 0);
  EXPECT_GT(n.refused, 0);
}

TEST(CliExtremes, SimulatorOptionsAndPresets) {
  temp_dir d;
  const auto o = d.file("o.csv");
  const auto t = d.file("t.csv");
  const std::vector<std::vector<std::string>> opts{
      {"--duration", "1e300"},
      {"--duration", "1e-300"},
      {"--temp-profile", "fridge:20:5:1e-300"},
      {"--temp-profile", "ramp:20:1e300:60"},
      {"--temp-profile", "steps:0:20,1e300:30"},
      {"--temp", "1e9"},
      {"--temp", "-273.15"},
      {"--rate-profile", "sine:1e300:1"},
      {"--rate-profile", "sine:1:1e300"},
      {"--rate-profile", "1e300"},
      {"--n-avg", "2000000000"},
      {"--settle", "1e300"},
      {"--positions", "0,1e300"},
      {"--power-on-before", "1e300"},
      {"--step-rate", "1e300"},
      {"--accel", "1e300"},
      {"--start-rate", "1e-300"},
      {"--latitude", "1e300"},
      {"--axis", "1e300,0,0"},
      {"--axis", "1e-300,0,1e-300"},
      {"--table-axis", "0,1e-300,0"},
      {"--steps-per-rev", "2000000000"},
      {"--filter-word", "127"},
      {"--seed", "18446744073709551615"},
  };
  outcome_counts n;
  for (const auto& extra : opts) {
    std::vector<std::string> args{
        "simulate", "--sensor", "hz1-90-100a", "--duration", "30", "-o", o, "--truth", t};
    args.insert(args.end(), extra.begin(), extra.end());
    check(args, o, n, t);
  }
  for (const char* line :
       {"bias_dps = 1e300", "g_sens_z_dps_per_g = 1e300", "arw_dps_rthz = 1e300",
        "range_dps = 1e300", "scale_factor_v_per_dps = 1e300", "bias_tc_dps_per_c = 1e300",
        "warmup_amplitude_dps = -1e300", "rate_ramp_dps_per_s = 1e300", "quantisation_deg = 1e300",
        "bandwidth_hz = 1e300", "null_v = 1e300", "rrw_dps_per_rts = 1e300",
        "bias_instability_dps = 1e300", "turn_on_bias_sigma_dps = 1e300"}) {
    write_text(d.file("p.toml"),
               std::string("name = \"x\"\nbase = \"hz1-90-100a\"\n") + line + "\n");
    check({"simulate", "--sensor", d.file("p.toml"), "--duration", "30", "-o", o}, o, n);
  }
  EXPECT_GT(n.ok, 0);
  EXPECT_GT(n.refused, 0);
}

TEST(CliExtremes, EarthRate) {
  outcome_counts n;
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"earth", "--latitude", "90", "--axis", "north"},
           {"earth", "--latitude", "1e300", "--axis", "north"},
           {"earth", "--latitude", "0", "--axis", "1e300,0,0", "--json"},
           {"earth", "--latitude", "0", "--axis", "1e-300,0,1e-300", "--json"},
           {"earth", "--latitude", "0", "--axis", "5e-324,0,0"}})
    check(args, "", n);
  EXPECT_GT(n.ok, 0);
}

}  // namespace
}  // namespace gyroflip::test
