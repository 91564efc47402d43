// `gyroflip adev` and `gyroflip noise`: output contract, input formats (CSV, .npy, raw float64),
// rate vs angle input, and bad input (exit 2, file:line, no output file).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/reference_data.hpp"
#include "support/run_cli.hpp"
#include "support/series_files.hpp"
#include "support/synth.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

using nlohmann::json;

std::string fmt_double(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string csv_of(const std::vector<double>& y, double dt) {
  std::string s = "time_s,rate_dps\n";
  for (std::size_t i = 0; i < y.size(); ++i)
    s += std::to_string(static_cast<double>(i) * dt) + "," + fmt_double(y[i]) + "\n";
  return s;
}

TEST(CliAdev, JsonCsvNpyAndRawAgree) {
  temp_dir d;
  const auto y = nbs14_1000();
  write_text(d.file("y.csv"), csv_of(y, 1.0));
  write_npy(d.file("y.npy"), y);
  write_f64(d.file("y.f64"), y);
  const auto j = run_cli({"adev", d.file("y.csv"), "--kind", "oadev", "--json"});
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto doc = json::parse(j.out);
  EXPECT_EQ(doc["kind"], "oadev");
  EXPECT_EQ(doc["input"], "rate");
  const auto& pts = doc["points"];
  ASSERT_EQ(pts.size(), 8u);  // octave up to (N-1)/4 = 250: 1..128
  for (const auto& p : pts)
    for (const char* k : {"tau_s", "dev", "ci_lo", "ci_hi", "edf", "n"})
      EXPECT_TRUE(p.contains(k)) << k;
  EXPECT_NEAR(pts[0]["dev"].get<double>(), 0.2922319, 1e-6);  // NBS14 1000-point, tau = 1
  EXPECT_LT(pts[3]["ci_lo"].get<double>(), pts[3]["dev"].get<double>());
  EXPECT_GT(pts[3]["ci_hi"].get<double>(), pts[3]["dev"].get<double>());

  for (const auto& file : {d.file("y.npy"), d.file("y.f64")}) {
    const auto b = run_cli({"adev", file, "--rate", "1", "--json"});
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const auto bp = json::parse(b.out)["points"];
    ASSERT_EQ(bp.size(), pts.size());
    for (std::size_t i = 0; i < bp.size(); ++i)
      EXPECT_NEAR(bp[i]["dev"].get<double>() / pts[i]["dev"].get<double>(), 1.0, 1e-12) << file;
  }

  const auto o = run_cli(
      {"adev", d.file("y.csv"), "--kind", "mdev", "--taus", "decade", "-o", d.file("out.csv")});
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const std::string out = read_text(d.file("out.csv"));
  EXPECT_EQ(out.substr(0, out.find('\n')), "tau_s,dev,ci_lo,ci_hi,edf,n,alpha");
  EXPECT_NE(out.find("\n# units: deg/s\n"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'),
            2 + 8);  // header, units, then 1, 2, 4, 10, 20, 40, 100, 200 (<= 250)
}

TEST(CliAdev, Hdf5DatasetInput) {
  temp_dir d;
  auto y = nbs14_1000();
  for (auto& v : y) v = static_cast<double>(static_cast<float>(v));  // what float32 storage keeps
  write_h5(d.file("log.h5"), "/gyro/rate_x", y, 1.0, true);
  write_npy(d.file("y.npy"), y);
  const auto h = run_cli({"adev", d.file("log.h5") + ":/gyro/rate_x", "--json"});
  ASSERT_EQ(h.exit_code, 0) << h.err;
  const auto hp = json::parse(h.out)["points"];
  const auto np =
      json::parse(run_cli({"adev", d.file("y.npy"), "--rate", "1", "--json"}).out)["points"];
  ASSERT_EQ(hp.size(), np.size());
  for (std::size_t i = 0; i < hp.size(); ++i) EXPECT_EQ(hp[i]["dev"], np[i]["dev"]);
  const auto same = run_cli({"adev", d.file("log.h5"), "--dataset", "/gyro/rate_x", "--json"});
  EXPECT_EQ(same.exit_code, 0) << same.err;
  const auto missing = run_cli({"adev", d.file("log.h5") + ":/gyro/nope"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("log.h5: no dataset '/gyro/nope'"), std::string::npos) << missing.err;
  const auto noset = run_cli({"adev", d.file("log.h5")});
  EXPECT_EQ(noset.exit_code, 2);
  write_text(d.file("fake.h5"), "not hdf5");
  const auto fake = run_cli({"adev", d.file("fake.h5") + ":/x"});
  EXPECT_EQ(fake.exit_code, 2);
  EXPECT_NE(fake.err.find("fake.h5: not an HDF5 file"), std::string::npos) << fake.err;
}

// Issue 21: a file's own sample_rate_hz of 0 or NaN was reported as "(option --rate)", an option
// never given; `FILE.h5:/a --dataset /b` silently read /a.
TEST(CliAdev, Hdf5RateAttributeAndDatasetConflictAreNamedForWhatTheyAre) {
  temp_dir d;
  const auto y = nbs14_1000();
  for (const double bad : {0.0, std::nan(""), -5.0}) {
    write_h5(d.file("bad.h5"), "/gyro/rate_x", y, bad);
    const auto r = run_cli({"adev", d.file("bad.h5") + ":/gyro/rate_x"});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_EQ(r.err.find("--rate"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("bad.h5: dataset '/gyro/rate_x': its sample_rate_hz attribute is"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("give the sample rate instead"), std::string::npos) << r.err;
    // Given, the rate overrides the file's.
    EXPECT_EQ(run_cli({"adev", d.file("bad.h5") + ":/gyro/rate_x", "--rate", "1"}).exit_code, 0);
  }
  write_h5(d.file("two.h5"), "/a", y, 1.0);
  const auto conflict = run_cli({"adev", d.file("two.h5") + ":/a", "--dataset", "/b"});
  EXPECT_EQ(conflict.exit_code, 2);
  EXPECT_NE(conflict.err.find("names dataset '/a', but the dataset parameter says '/b': give it "
                              "once (option --dataset)"),
            std::string::npos)
      << conflict.err;
  EXPECT_EQ(run_cli({"adev", d.file("two.h5") + ":/a", "--dataset", "/a"}).exit_code, 0);
  EXPECT_EQ(run_cli({"noise", d.file("two.h5") + ":/a", "--dataset", "/b"}).exit_code, 2);
}

TEST(CliAdev, RateAndAngleColumnsGiveTheSameCurve) {
  temp_dir d;
  const auto y = nbs14_1000();
  std::string s = "time_s,rate_dps,angle_int_deg\n";
  double angle = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    s += std::to_string(i) + "," + fmt_double(y[i]) + "," + fmt_double(angle) + "\n";
    angle += y[i];
  }
  write_text(d.file("both.csv"), s);
  const auto r = json::parse(run_cli({"adev", d.file("both.csv"), "--json"}).out)["points"];
  const auto a = run_cli(
      {"adev", d.file("both.csv"), "--input", "angle", "--column", "angle_int_deg", "--json"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto ap = json::parse(a.out)["points"];
  // The angle series has one point fewer than the rate series integrated, so compare the
  // shared taus only; the deviations agree to the 1e-4 of a 999- vs 1000-term sum.
  for (std::size_t i = 0; i + 1 < std::min(r.size(), ap.size()); ++i)
    EXPECT_NEAR(ap[i]["dev"].get<double>() / r[i]["dev"].get<double>(), 1.0, 2e-3) << i;
}

TEST(CliAdev, BadInput) {
  temp_dir d;
  write_text(d.file("gap.csv"),
             "time_s,rate_dps\n0,1\n1,2\n2,3\n7,4\n8,5\n9,6\n10,7\n11,1\n12,2\n");
  write_text(d.file("nocol.csv"), "time_s,gx\n0,1\n1,2\n2,3\n");
  write_text(d.file("bad.csv"), "time_s,rate_dps\n0,1\n1,x\n2,3\n");
  write_npy(d.file("f4.npy"), {1.0, 2.0}, "<f2");  // half precision: not read
  write_npy(d.file("nan.npy"), {1.0, 2.0, std::nan(""), 3.0});
  struct c {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<c> cases = {
      {{"adev", d.file("gap.csv")},
       "gap.csv:5:1: the time stamps have 1 gap (period 1 s): after sample 3 (time 2 s)"},
      {{"adev", d.file("nocol.csv")}, "nocol.csv:1:1: missing required column 'rate_dps'"},
      {{"adev", d.file("bad.csv")}, "bad.csv:3:3: 'x' is not a number"},
      {{"adev", d.file("f4.npy"), "--rate", "1"},
       "f4.npy: .npy dtype must be little-endian float64"},
      {{"adev", d.file("f4.npy")},
       "f4.npy: binary input has no time column: the sample rate must be given (option --rate)"},
      {{"adev", d.file("nan.npy"), "--rate", "1"}, "nan.npy: sample 2 (0-based) is not finite"},
      {{"adev", d.file("none.csv")}, "none.csv: No such file"},
      {{"adev", d.file("bad.csv"), "--taus", "1,zz"},
       "'1,zz': expected octave, decade, all or averaging factors"},
      {{"noise", d.file("nocol.csv")}, "missing required column"},
  };
  for (const auto& k : cases) {
    auto args = k.args;
    args.insert(args.end(), {"-o", d.file("o.csv")});
    if (args[0] == "noise") args.resize(args.size() - 2);
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << k.expect;
    EXPECT_NE(r.err.find(k.expect), std::string::npos) << r.err;
    EXPECT_FALSE(exists(d.file("o.csv")));
  }
  EXPECT_EQ(run_cli({"adev", d.file("gap.csv"), "--kind", "pdev"}).exit_code, 2);
  EXPECT_EQ(run_cli({"adev", d.file("gap.csv"), "--ci", "1"}).exit_code, 2);
}

TEST(CliNoise, JsonKeysAndWhiteNoiseArw) {
  temp_dir d;
  normal_source n(5);
  std::vector<double> y(100000);
  for (auto& v : y) v = 0.05 * n();
  write_npy(d.file("w.npy"), y);
  const auto r = run_cli({"noise", d.file("w.npy"), "--rate", "100", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(r.out);
  for (const char* k :
       {"arw_dps_rthz", "arw_deg_rth", "bias_instability_dps", "bias_instability_deg_h",
        "rrw_deg_h_rth", "quantization_deg", "rate_ramp_deg_h2"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["arw_dps_rthz"].get<double>() / 0.005, 1.0, 0.03);
  EXPECT_NEAR(j["arw_deg_rth"].get<double>() / 0.3, 1.0, 0.03);
  EXPECT_TRUE(j.contains("arw_dps_rthz_lo"));
  EXPECT_TRUE(j["rrw_deg_h_rth"].is_null());
  EXPECT_TRUE(j.contains("rrw_deg_h_rth_upper"));
  EXPECT_DOUBLE_EQ(j["ci"].get<double>(), 0.683);
  const auto text = run_cli({"noise", d.file("w.npy"), "--rate", "100"});
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("angle random walk"), std::string::npos);
  // A wider level widens the interval around the same value; a level outside (0, 1) is usage.
  const auto wide = json::parse(
      run_cli({"noise", d.file("w.npy"), "--rate", "100", "--ci", "0.95", "--json"}).out);
  EXPECT_EQ(wide["arw_dps_rthz"].get<double>(), j["arw_dps_rthz"].get<double>());
  EXPECT_LT(wide["arw_dps_rthz_lo"].get<double>(), j["arw_dps_rthz_lo"].get<double>());
  EXPECT_GT(wide["arw_dps_rthz_hi"].get<double>(), j["arw_dps_rthz_hi"].get<double>());
  // The OADEV points it prints carry bounds at the same level ("ci").
  EXPECT_LT(wide["oadev"][0]["ci_lo"].get<double>(), j["oadev"][0]["ci_lo"].get<double>());
  EXPECT_EQ(run_cli({"noise", d.file("w.npy"), "--rate", "100", "--ci", "1.5"}).exit_code, 2);
}

// Issue 34 item 2: `noise --plot` draws every column's curve with its fitted lines, in deg/h by
// default, the key inside the frame, the given title; --long-taus adds the points to
// m <= (N-1)/2 (open, not fitted) and says where Stable32 stops; a unit it cannot draw is usage.
TEST(CliNoise, PlotDrawsEveryColumnWithTheKeyInside) {
  temp_dir d;
  normal_source n(8);
  std::string csv = "time_s,gx_dps,gy_dps\n";
  for (int k = 0; k < 20000; ++k) {
    char row[96];
    std::snprintf(row, sizeof row, "%.2f,%.9g,%.9g\n", k * 0.01, 0.05 * n(), 0.07 * n());
    csv += row;
  }
  write_text(d.file("g.csv"), csv);
  const auto r = run_cli({"noise", d.file("g.csv"), "--columns", "all-numeric", "--plot",
                          d.file("fig.svg"), "--title", "two axes", "--long-taus", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(exists(d.file("fig.svg")));
  const auto gp = read_text(d.file("fig.gp"));
  EXPECT_NE(gp.find("set key inside"), std::string::npos);
  EXPECT_NE(gp.find("two axes"), std::string::npos);
  EXPECT_NE(gp.find("Allan deviation (°/h)"), std::string::npos);
  EXPECT_NE(gp.find("gx_dps: N = "), std::string::npos);
  EXPECT_NE(gp.find("gy_dps: N = "), std::string::npos);
  EXPECT_NE(gp.find("Stable32 stops"), std::string::npos);
  const auto j = json::parse(r.out);
  for (const auto& c : j["columns"]) {
    ASSERT_FALSE(c["long_oadev"].empty());
    // Beyond (N-1)/4 and within (N-1)/2 of the 20 001 phase points.
    EXPECT_GT(c["long_oadev"].back()["tau_s"].get<double>(),
              c["oadev"].back()["tau_s"].get<double>());
    EXPECT_LE(c["long_oadev"].back()["tau_s"].get<double>(), 100.0);
  }
  const auto rad = run_cli({"noise", d.file("g.csv"), "--column", "gx_dps", "--plot",
                            d.file("r.png"), "--plot-units", "rad/s"});
  ASSERT_EQ(rad.exit_code, 0) << rad.err;
  EXPECT_NE(read_text(d.file("r.gp")).find("Allan deviation (rad/s)"), std::string::npos);
  EXPECT_EQ(run_cli({"noise", d.file("g.csv"), "--plot", d.file("x.png"), "--plot-units", "mg"})
                .exit_code,
            2);
  EXPECT_EQ(run_cli({"noise", d.file("g.csv"), "--plot", d.file("x.txt")}).exit_code, 2);
}

// Regression (issue 13 item 15, 2026-11-23): the demo printed `B 3.854 [3.149, 4.449] deg/h (OADEV
// floor ... at tau 229 s)` for the abba-compensated simulated run, whose OADEV still falls at its
// last point, while the same run compensated with the simple pairing is white. Now the abba
// cycles' known correlation is in the model (compensate's CSV says `pairing: abba`): B is not
// resolved for either pairing, the two ARW values agree within their intervals, and the output
// says there is no floor.
TEST(CliNoise, AbbaCompensatedRunHasNoFalseFloor) {
  temp_dir d;
  const auto sim = [&](const char* out, const char* seed, const char* duration,
                       std::vector<std::string> extra) {
    std::vector<std::string> a{"simulate", "--sensor", "hz1-90-100a", "--duration",
                               duration,   "--temp",   "20",          "--seed",
                               seed,       "-o",       d.file(out)};
    a.insert(a.end(), extra.begin(), extra.end());
    ASSERT_EQ(run_cli(a).exit_code, 0);
  };
  sim("cal.csv", "11", "1800", {});
  sim("run.csv", "12", "1200", {"--rate-profile", "0.5"});
  ASSERT_EQ(run_cli({"calibrate", d.file("cal.csv"), "-o", d.file("cal.json")}).exit_code, 0);
  double arw[2][3];
  int k = 0;
  for (const char* p : {"abba", "simple"}) {
    const auto out = d.file(std::string("comp_") + p + ".csv");
    ASSERT_EQ(run_cli({"compensate", d.file("run.csv"), "--calibration", d.file("cal.json"),
                       "--pairing", p, "-o", out})
                  .exit_code,
              0);
    const auto r = run_cli({"noise", out, "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["bias_instability_dps"].is_null()) << p << " " << r.out.substr(0, 400);
    EXPECT_FALSE(j["bias_floor_reached"].get<bool>()) << p;
    EXPECT_EQ(j["abba_cycles"].get<bool>(), std::string(p) == "abba");
    EXPECT_LT(j["chi2_per_dof"].get<double>(), 2.0) << p;
    EXPECT_TRUE(j["misfit"].is_array());
    arw[k][0] = j["arw_dps_rthz"].get<double>();
    arw[k][1] = j["arw_dps_rthz_lo"].get<double>();
    arw[k][2] = j["arw_dps_rthz_hi"].get<double>();
    ++k;
    const auto text = run_cli({"noise", out}).out;
    EXPECT_NE(text.find("no floor: OADEV still falls"), std::string::npos) << text;
  }
  // The intervals of the two pairings' ARW overlap (one truth).
  EXPECT_LT(arw[0][1], arw[1][2]);
  EXPECT_LT(arw[1][1], arw[0][2]);
}

// Regression (issue 13 item 12, 2026-11-23): `noise`/`adev` on an uncompensated flip recording
// printed a "resolved" K = 717 deg/h/sqrt(h) and Q = 0.16 deg - the flipping's square wave. Now
// they refuse it and say what to do; a compensated or an unflipped recording is analysed.
TEST(CliNoise, UncompensatedFlipRecordingIsRefusedWithAdvice) {
  temp_dir d;
  for (const char* sensor : {"adxrs150", "hz1-90-100a"}) {
    const auto rec = d.file(std::string(sensor) + ".csv");
    // Seed 2: a power-up whose HZ1 dN (0.0038 deg/s) stands out of 900 s of noise; dN changes
    // from power-up to power-up (paper Tab. 3), and one near zero rightly does not "switch".
    ASSERT_EQ(
        run_cli({"simulate", "--sensor", sensor, "--duration", "900", "--seed", "2", "-o", rec})
            .exit_code,
        0);
    for (const char* cmd : {"noise", "adev"}) {
      const auto r = run_cli({cmd, rec});
      EXPECT_EQ(r.exit_code, 2) << sensor << " " << cmd;
      EXPECT_NE(r.err.find("switches with angle_deg"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("gyroflip compensate"), std::string::npos) << r.err;
      EXPECT_EQ(run_cli({cmd, rec, "--ignore-flip"}).exit_code, 0) << sensor << " " << cmd;
    }
    ASSERT_EQ(run_cli({"calibrate", rec, "-o", d.file("cal.json")}).exit_code, 0);
    ASSERT_EQ(
        run_cli({"compensate", rec, "--calibration", d.file("cal.json"), "-o", d.file("comp.csv")})
            .exit_code,
        0);
    EXPECT_EQ(run_cli({"noise", d.file("comp.csv")}).exit_code, 0) << sensor;
  }
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--no-flip", "--duration", "900", "-o",
                     d.file("still.csv")})
                .exit_code,
            0);
  EXPECT_EQ(run_cli({"noise", d.file("still.csv")}).exit_code, 0);
  // The temperature column of a flip recording does not switch with the angle.
  EXPECT_EQ(run_cli({"adev", d.file("adxrs150.csv"), "--column", "temp_c"}).exit_code, 0);
}

// Review of issue 23 (/tmp/rev23b M1): `# units` and JSON `units` give the statistic's unit: the
// frequency-like deviations in the rate unit, TDEV, TTOTDEV, MTIE and TIE rms in the angle unit.
TEST(CliAdev, UnitsAreTheStatisticsNotTheSamples) {
  temp_dir d;
  const auto y = nbs14_1000();
  write_text(d.file("y.csv"), csv_of(y, 1.0));
  const auto units = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{"adev", d.file("y.csv"), "--taus", "1,2", "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? json::parse(r.out)["units"].get<std::string>() : std::string();
  };
  EXPECT_EQ(units({}), "deg/s");
  EXPECT_EQ(units({"--kind", "mtie"}), "deg");
  EXPECT_EQ(units({"--kind", "tdev", "--units", "rad/s"}), "rad");
  EXPECT_EQ(units({"--kind", "tierms", "--units", "deg/h"}), "deg/h*s");
  EXPECT_EQ(units({"--input", "angle", "--units", "deg"}), "deg/s");
  EXPECT_EQ(units({"--input", "angle", "--kind", "ttotdev"}), "deg");
  const auto csv = run_cli({"adev", d.file("y.csv"), "--kind", "tdev"});
  EXPECT_NE(csv.out.find("\n# units: deg\n"), std::string::npos) << csv.out;
}

// Review M4: MTIE and TIE rms are of x itself (ITU-T G.810): a constant rate (a gyro's bias)
// adds bias*tau to every time error, so a rate record and its integrated angle agree.
TEST(CliAdev, MtieOfARateRecordKeepsItsBiasAndAgreesWithTheAngle) {
  temp_dir d;
  auto y = nbs14_1000();
  for (double& v : y) v = 5.0 + (v - 0.5);  // a 5 deg/s bias on white rate noise
  std::string angle = "angle_deg\n0\n";
  double a = 0.0;
  for (const double v : y) angle += fmt_double(a += v) + "\n";
  write_text(d.file("rate.csv"), csv_of(y, 1.0));
  write_text(d.file("angle.csv"), angle);
  for (const char* kind : {"mtie", "tierms"}) {
    const auto r =
        run_cli({"adev", d.file("rate.csv"), "--kind", kind, "--taus", "1,10,100", "--json"});
    const auto g =
        run_cli({"adev", d.file("angle.csv"), "--input", "angle", "--column", "angle_deg", "--rate",
                 "1", "--kind", kind, "--taus", "1,10,100", "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(g.exit_code, 0) << g.err;
    const auto rp = json::parse(r.out)["points"], gp = json::parse(g.out)["points"];
    ASSERT_EQ(rp.size(), 3u);
    ASSERT_EQ(gp.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_NEAR(rp[i]["dev"].get<double>() / gp[i]["dev"].get<double>(), 1.0, 1e-7) << kind;
      // The bias dominates: 5 deg/s over tau, within the noise's share (|y - 5| < 0.5 each).
      const double tau = rp[i]["tau_s"].get<double>();
      EXPECT_NEAR(rp[i]["dev"].get<double>(), 5.0 * tau, 0.5 * tau + 1e-9) << kind << " " << tau;
    }
  }
}

// Review H2: GRADEV in the CLI. An empty field or nan is a missing sample for --kind gradev only;
// without gaps it is OADEV; with them it keeps the terms without a gap.
TEST(CliAdev, GradevReadsGapsAndEveryOtherKindRefusesThem) {
  temp_dir d;
  const auto y = nbs14_1000();
  write_text(d.file("full.csv"), csv_of(y, 1.0));
  std::string gappy = "time_s,rate_dps\n";
  for (std::size_t i = 0; i < y.size(); ++i)
    gappy += std::to_string(i) + "," +
             (i == 100   ? std::string()
              : i == 500 ? "nan"
              : i == 700 ? "-nan"  // glibc's printf of a NaN with its sign bit (re-review N-L1)
                         : fmt_double(y[i])) +
             "\n";
  write_text(d.file("gappy.csv"), gappy);
  const auto full =
      run_cli({"adev", d.file("full.csv"), "--kind", "gradev", "--taus", "1,4", "--json"});
  const auto oadev =
      run_cli({"adev", d.file("full.csv"), "--taus", "1,4", "--ci", "none", "--json"});
  const auto gap =
      run_cli({"adev", d.file("gappy.csv"), "--kind", "gradev", "--taus", "1,4", "--json"});
  ASSERT_EQ(full.exit_code, 0) << full.err;
  ASSERT_EQ(gap.exit_code, 0) << gap.err;
  const auto fp = json::parse(full.out)["points"], op = json::parse(oadev.out)["points"],
             gp = json::parse(gap.out)["points"];
  ASSERT_EQ(fp.size(), 2u);
  ASSERT_EQ(gp.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(fp[i]["dev"].get<double>() / op[i]["dev"].get<double>(), 1.0, 1e-12);
    EXPECT_LT(gp[i]["n"].get<std::size_t>(), fp[i]["n"].get<std::size_t>());
    EXPECT_NEAR(gp[i]["dev"].get<double>() / fp[i]["dev"].get<double>(), 1.0, 0.05);
    EXPECT_TRUE(gp[i]["ci_lo"].is_null());
  }
  const auto refused =
      run_cli({"adev", d.file("gappy.csv"), "--kind", "oadev", "-o", d.file("o.csv")});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("gappy.csv:102:"), std::string::npos) << refused.err;
  EXPECT_FALSE(exists(d.file("o.csv")));
  // Review R-L1: a lone sign (a truncated write) is not a gap, even for gradev.
  write_text(d.file("sign.csv"), "time_s,rate_dps\n0,1\n1,2\n2,-\n3,1\n");
  const auto sign = run_cli({"adev", d.file("sign.csv"), "--kind", "gradev", "--taus", "1"});
  EXPECT_EQ(sign.exit_code, 2);
  EXPECT_NE(sign.err.find("sign.csv:4:"), std::string::npos) << sign.err;
}

// Review M2, L5, L3: options that do not combine are refused (exit 2, nothing written), not
// ignored; a series too short for every tau is the input's error.
TEST(CliAdev, OptionsThatDoNotCombineAreRefused) {
  temp_dir d;
  const auto y = nbs14_1000();
  std::string s = "a,b,c\n";
  for (std::size_t i = 0; i + 2 < y.size(); ++i)
    s += fmt_double(y[i]) + "," + fmt_double(y[i + 1]) + "," + fmt_double(y[i + 2]) + "\n";
  write_text(d.file("abc.csv"), s);
  const std::string f = d.file("abc.csv");
  const std::vector<std::vector<std::string>> bad = {
      {"--column", "a,b", "--codev", "--kind", "mtie"},
      {"--column", "a,b", "--codev", "--plot", d.file("c.png")},
      {"--column", "a,b", "--codev", "--three-cornered-hat"},
      {"--column", "a,b", "--codev", "--ci-guard"},
      {"--column", "a,b,c", "--three-cornered-hat", "--kind", "mtie"},
      {"--column", "a,b,c", "--three-cornered-hat", "--dynamic", "100"},
      {"--column", "a", "--dynamic", "100", "--ci-guard"},
      {"--column", "a", "--kind", "gradev", "--ci-guard"},
      {"--column", "a", "--kind", "gradev", "--dynamic", "100"},
      // Re-review N-M1, N-L2 and L6: TIE rms keeps each pair's offset (not separable); an
      // interval level where none is given; a noise type with nothing to set.
      {"--column", "a,b,c", "--three-cornered-hat", "--kind", "tierms"},
      {"--column", "a,b", "--codev", "--ci", "0.9"},
      {"--column", "a,b,c", "--three-cornered-hat", "--ci", "0.683"},
      {"--column", "a", "--kind", "gradev", "--ci", "0.9"},
      {"--column", "a", "--kind", "pdev", "--ci", "0.9"},
      {"--column", "a", "--kind", "mtie", "--alpha", "0"},
      {"--column", "a", "--alpha", "0", "--ci", "none"},
      {"--column", "a", "--alpha", "0", "--ci-guard"},
      {"--column", "a", "--ci", "none", "--ci-guard"},  // review R-L2: nothing to guard
      {"--column", "a", "--kind", "mtie", "--ci-guard"},
      {"--column", "a", "--alpha", "0", "--dynamic", "100"},
      {"--column", "a", "--alpha", "3"},
      // Review E-L4: a step (or window) below one sample interval is not silently one sample.
      {"--column", "a", "--dynamic", "50:0.4"},
      {"--column", "a", "--dynamic", "0.3"},
  };
  for (const auto& extra : bad) {
    std::vector<std::string> args{"adev", f, "--rate", "1", "-o", d.file("o.csv")};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << extra[2] << " " << r.err;
    EXPECT_FALSE(exists(d.file("o.csv")));
    EXPECT_FALSE(exists(d.file("c.png")));
  }
  const auto short_ =
      run_cli({"adev", f, "--rate", "1", "--column", "a", "--kind", "totdev", "--taus", "5000"});
  EXPECT_EQ(short_.exit_code, 2);
  EXPECT_NE(short_.err.find("abc.csv: no averaging time fits"), std::string::npos) << short_.err;
  // Review E-L4: the same for the codeviation and the hat (they exited 1 without the file).
  for (const auto& cols : {std::vector<std::string>{"a,b", "--codev"},
                           std::vector<std::string>{"a,b,c", "--three-cornered-hat"}}) {
    const auto r =
        run_cli({"adev", f, "--rate", "1", "--column", cols[0], cols[1], "--taus", "5000"});
    EXPECT_EQ(r.exit_code, 2) << cols[1];
    EXPECT_NE(r.err.find("abc.csv: no averaging time fits"), std::string::npos) << r.err;
    // One factor too long in a list: said, not dropped silently (review F-L6).
    const auto part =
        run_cli({"adev", f, "--rate", "1", "--column", cols[0], cols[1], "--taus", "10,5000"});
    EXPECT_EQ(part.exit_code, 0) << part.err;
    EXPECT_NE(part.err.find("averaging factor 5000 dropped"), std::string::npos) << part.err;
  }
  // A step far beyond the series (1e20 s overflowed a size_t and read as 0 samples): refused by
  // name, as a window beyond it; a default step below one sample is named as the default.
  const auto far = run_cli({"adev", f, "--rate", "1", "--column", "a", "--dynamic", "500:1e20"});
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.err.find("a step of 1e+20 s is longer than the series (998 samples"),
            std::string::npos)
      << far.err;
  const auto tiny = run_cli({"adev", f, "--rate", "1", "--column", "a", "--dynamic", "1"});
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_NE(tiny.err.find("a step (a quarter window) of 0.25 s is shorter than one sample"),
            std::string::npos)
      << tiny.err;
}

// Review L5, M2: the hat leaves a clock it cannot resolve empty (a negative variance estimate is
// not a zero), says so, and draws its clocks with --plot.
TEST(CliAdev, TheHatLeavesUnresolvedClocksEmptyAndDrawsTheRest) {
  temp_dir d;
  const auto y = nbs14_1000();
  // Clock A is perfect, B and C noisy: AB = -B, BC = B - C, CA = C. With independent B and C of
  // equal size A's estimate is about 0, negative at some taus.
  std::string s = "ab,bc,ca\n";
  for (std::size_t i = 0; i + 500 < y.size(); ++i) {
    const double b = y[i] - 0.5, c = y[i + 500] - 0.5;
    s += fmt_double(-b) + "," + fmt_double(b - c) + "," + fmt_double(c) + "\n";
  }
  write_text(d.file("hat.csv"), s);
  const auto r = run_cli({"adev", d.file("hat.csv"), "--rate", "1", "--column", "ab,bc,ca",
                          "--three-cornered-hat", "--taus", "1,2,4,8,16,32", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(r.out);
  std::size_t empty = 0;
  for (const auto& p : j["curves"][0]["points"]) {
    if (p["dev"].is_null()) {
      ++empty;
    } else {
      EXPECT_GT(p["dev"].get<double>(), 0.0);
    }
  }
  for (const auto& p : j["curves"][1]["points"]) EXPECT_FALSE(p["dev"].is_null());
  if (empty > 0) {
    EXPECT_NE(r.err.find("clock A: not resolved"), std::string::npos) << r.err;
  }
  if (run_program({"gnuplot", "--version"}).exit_code != 0) return;
  const auto plot =
      run_cli({"adev", d.file("hat.csv"), "--rate", "1", "--column", "ab,bc,ca",
               "--three-cornered-hat", "--plot", d.file("hat.svg"), "-o", d.file("hat_out.csv")});
  ASSERT_EQ(plot.exit_code, 0) << plot.err;
  EXPECT_TRUE(exists(d.file("hat.svg")));
}

// Review L2, L4: what the numbers depend on is in the output; factors no window holds are said.
TEST(CliAdev, TheIntervalRuleAndBiasCorrectionAreRecorded) {
  temp_dir d;
  write_text(d.file("y.csv"), csv_of(nbs14_1000(), 1.0));
  const auto g = run_cli({"adev", d.file("y.csv"), "--kind", "htotdev", "--taus", "16",
                          "--bias-correction", "--ci-guard", "--json"});
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_EQ(json::parse(g.out)["ci_rule"], "guarded");
  EXPECT_EQ(json::parse(g.out)["bias_correction"], true);
  const auto plain = run_cli({"adev", d.file("y.csv"), "--taus", "16", "--json"});
  EXPECT_EQ(json::parse(plain.out)["ci_rule"], "stable32");
  EXPECT_EQ(json::parse(plain.out)["bias_correction"], false);
  const auto csv = run_cli({"adev", d.file("y.csv"), "--kind", "htotdev", "--taus", "16",
                            "--bias-correction", "--ci-guard"});
  EXPECT_NE(csv.out.find("\n# ci_rule: guarded\n# bias_correction: stable32\n"), std::string::npos)
      << csv.out;
  const auto dyn = run_cli({"adev", d.file("y.csv"), "--dynamic", "100", "--taus", "1,400"});
  ASSERT_EQ(dyn.exit_code, 0) << dyn.err;
  EXPECT_NE(dyn.err.find("averaging factor 400 dropped from every window"), std::string::npos)
      << dyn.err;
  // Review M3: each window's points carry their intervals; --ci none leaves them out.
  const auto wj = run_cli({"adev", d.file("y.csv"), "--dynamic", "500", "--json"});
  ASSERT_EQ(wj.exit_code, 0) << wj.err;
  const auto wjson = json::parse(wj.out);  // kept: a range-for over a temporary's member dangles
  for (const auto& w : wjson["windows"])
    for (const auto& p : w["points"]) {
      ASSERT_TRUE(p["ci_lo"].is_number()) << p;
      EXPECT_LT(p["ci_lo"].get<double>(), p["dev"].get<double>());
      EXPECT_GT(p["ci_hi"].get<double>(), p["dev"].get<double>());
    }
  const auto wn = run_cli({"adev", d.file("y.csv"), "--dynamic", "500", "--ci", "none", "--json"});
  ASSERT_EQ(wn.exit_code, 0) << wn.err;
  EXPECT_TRUE(json::parse(wn.out)["windows"][0]["points"][0]["ci_lo"].is_null());
}

// Re-review N-H1 and L6: beyond half the all-tau limit the identified type is the nearest shorter
// listed tau's, as in Stable32's own tables (MTOTDEV of PHASE.DAT at AF 200: alpha 1 in its
// decade table, 0 in its all-tau table), so the bias-corrected value there depends on the list;
// --alpha gives every tau one known type, and the value no longer does. Truth: Stable32 1.53's
// all-tau bias-corrected MTOTDEV at AF 170, 1.3547e-02 with alpha 0 (tests/vectors/stable32).
TEST(CliAdev, AGivenNoiseTypeMakesEachTauIndependentOfTheList) {
  const std::string file = std::string(GYROFLIP_VECTORS_DIR) + "/stable32/phasedat/PHASE.DAT";
  const auto at_170 = [&](const std::string& taus, bool given) {
    std::vector<std::string> args{"adev",        file,       "--input", "angle",
                                  "--units",     "deg",      "--rate",  "1",
                                  "--no-header", "--column", "1",       "--kind",
                                  "mtotdev",     "--taus",   taus,      "--bias-correction",
                                  "--json"};
    if (given) args.insert(args.end(), {"--alpha", "0"});
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto j = json::parse(r.out);
    for (const auto& p : j["points"])
      if (p["m"] == 170)
        return std::pair<double, int>(p["dev"].get<double>(), p["alpha"].get<int>());
    return std::pair<double, int>(0.0, -9);
  };
  // Identified: AF 100 reads flicker PM, carried to 170 (Stable32's rule, its decade table).
  EXPECT_EQ(at_170("100,170", false).second, 1);
  EXPECT_NEAR(at_170("100,170", false).first / 1.3547e-02, 1.0 / std::sqrt(0.83 / 0.73), 1e-4);
  // Review L2: without intervals the type that scaled a bias-corrected value is still reported.
  const auto bare = run_cli({"adev", file, "--input", "angle", "--units", "deg", "--rate", "1",
                             "--no-header", "--column", "1", "--kind", "mtotdev", "--taus",
                             "100,170", "--bias-correction", "--ci", "none", "--json"});
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  const auto bj = json::parse(bare.out);
  EXPECT_EQ(bj["points"][1]["alpha"], 1);
  EXPECT_TRUE(bj["points"][1]["ci_lo"].is_null());
  for (const char* taus : {"170", "100,170", "10,170,180", "all"}) {
    const auto [dev, alpha] = at_170(taus, true);
    EXPECT_EQ(alpha, 0) << taus;
    EXPECT_NEAR(dev / 1.3547e-02, 1.0, 1e-4) << taus;
  }
}

}  // namespace
}  // namespace gyroflip::test
