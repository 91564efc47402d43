// A lost dwell in a rig recording's Allan analysis (issue 32 item 5): `adev` and `noise` refused
// a recording with a single lost dwell even with --gaps split (its cycles fell off the uniform
// grid). A lost dwell is a gap on the grid of cycles, as a missing time stamp is in a CSV: named
// by default, split off with --gaps split, bridged by --kind gradev; each says how much.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_cli.hpp"
#include "support/synthetic_gfr.hpp"
#include "support/temp_dir.hpp"

namespace {

using gyroflip::test::run_cli;

// 600 dwells (300 cycles), dwell 380 lost: a stretch of 189 cycles, then one of 110.
std::string one_lost_dwell(const gyroflip::test::temp_dir& dir) {
  gyroflip::test::synthetic_options o;
  o.dwells = 600;
  o.lost = {380};
  const std::string path = dir.file("lost.gfr");
  static_cast<void>(gyroflip::test::make_synthetic_recording(o, path));
  return path;
}

TEST(RigGaps, ALostDwellIsAGapOnTheGridOfCycles) {
  gyroflip::test::temp_dir dir;
  const std::string path = one_lost_dwell(dir);
  const auto named = run_cli({"adev", path});
  EXPECT_EQ(named.exit_code, 2);
  EXPECT_NE(named.err.find("1 gap in its grid of cycles (1 of 300 samples missing; 1 dwell lost)"),
            std::string::npos)
      << named.err;
  EXPECT_NE(named.err.find("--gaps split"), std::string::npos) << named.err;

  const auto split = run_cli({"adev", path, "--gaps", "split"});
  EXPECT_EQ(split.exit_code, 0) << split.err;
  EXPECT_NE(split.err.find("analysed the longest gap-free stretch: 190 of 300"), std::string::npos)
      << split.err;
  const auto noise = run_cli({"noise", path, "--gaps", "split"});
  EXPECT_EQ(noise.exit_code, 0) << noise.err;

  const auto bridged = run_cli({"adev", path, "--kind", "gradev"});
  EXPECT_EQ(bridged.exit_code, 0) << bridged.err;
  EXPECT_NE(bridged.err.find("bridged as GRADEV gaps"), std::string::npos) << bridged.err;
  const auto dwells =
      run_cli({"adev", path, "--column", "dwell_dps", "--ignore-flip", "--gaps", "split"});
  EXPECT_EQ(dwells.exit_code, 0) << dwells.err;
  EXPECT_NE(dwells.err.find("grid of dwells"), std::string::npos) << dwells.err;
}

// A device that stood still between two consecutive dwells (3 s: a stall, a restarted
// conversion; the synthetic recording's lost port) leaves no place missing but a gap in time
// (review of issue 32: `noise --gaps split` on such a recording, of format 4 or 5, refused it as
// "off the uniform grid", the stretch's step taken as its span over its count, or kept a small
// stretch). A stretch is gap-free in time too: 190 cycles, the pause, 110 cycles.
TEST(RigGaps, ADeviceThatStoodStillIsAGapInTime) {
  for (const bool copies : {false, true}) {
    SCOPED_TRACE(copies ? "format 5" : "format 4");
    gyroflip::test::temp_dir dir;
    gyroflip::test::synthetic_options o;
    o.dwells = 600;
    o.link_losses_after = {379};
    o.copies = copies;
    const std::string path = dir.file("still.gfr");
    static_cast<void>(gyroflip::test::make_synthetic_recording(o, path));
    const auto named = run_cli({"adev", path});
    EXPECT_EQ(named.exit_code, 2);
    EXPECT_NE(named.err.find("1 gap in its grid of cycles (1 of 301 samples missing; 0 dwells "
                             "lost)"),
              std::string::npos)
        << named.err;
    const auto noise = run_cli({"noise", path, "--gaps", "split"});
    EXPECT_EQ(noise.exit_code, 0) << noise.err;
    EXPECT_NE(noise.err.find("analysed its 2 gap-free stretches pooled (300 of 301 samples"),
              std::string::npos)
        << noise.err;
  }
}

// `noise --gaps split` on a recording with many single lost dwells (the review of issue 32's
// old/f4b.gfr: 23 dwells lost of 661, a gap every ~15 cycles) analysed the longest gap-free
// stretch alone (48 of its 330 samples). It now pools every stretch: at each averaging factor
// the OADEV of every term that spans no gap, which is GRADEV's estimate (Sesia, Tavella et al.
// 2008; `adev --kind gradev`, a separate implementation on the grid with NaN between the
// stretches): the same values to rounding; and, the same dwells less 7 % of them, within 6 % of
// the whole recording's OADEV at each tau. Before: the longest stretch (13 cycles) was too short
// for a fit (exit 2). Both formats.
TEST(RigGaps, NoisePoolsEveryGapFreeStretch) {
  const auto points = [](const nlohmann::json& j) {
    std::vector<std::pair<double, double>> p;  // tau_s, dev
    for (const auto& q : j.contains("oadev") ? j["oadev"] : j["points"])
      p.emplace_back(q["tau_s"].get<double>(), q["dev"].get<double>());
    return p;
  };
  for (const bool copies : {false, true}) {
    SCOPED_TRACE(copies ? "format 5" : "format 4");
    gyroflip::test::temp_dir dir;
    gyroflip::test::synthetic_options o;
    o.dwells = 2000;
    o.copies = copies;
    o.seed = 5;
    const std::string whole = dir.file("whole.gfr");
    static_cast<void>(gyroflip::test::make_synthetic_recording(o, whole));
    for (std::size_t d = 41; d < o.dwells; d += 29) o.lost.push_back(d);
    const std::string path = dir.file("lost.gfr");
    static_cast<void>(gyroflip::test::make_synthetic_recording(o, path));
    const auto pooled = run_cli({"noise", path, "--gaps", "split", "--json"});
    ASSERT_EQ(pooled.exit_code, 0) << pooled.err;
    EXPECT_NE(pooled.err.find("gap-free stretches pooled"), std::string::npos) << pooled.err;
    const auto j = nlohmann::json::parse(pooled.out);
    EXPECT_GT(j["samples"].get<double>(), 0.9 * 1000) << pooled.out;
    EXPECT_TRUE(j["arw_dps_rthz"].is_number()) << pooled.out;
    const auto mine = points(j);
    ASSERT_GE(mine.size(), 3u) << pooled.out;
    // Point for point GRADEV's values, and near the whole recording's.
    const auto g = run_cli({"adev", path, "--kind", "gradev", "--json"});
    ASSERT_EQ(g.exit_code, 0) << g.err;
    const auto full = run_cli({"adev", whole, "--json"});
    ASSERT_EQ(full.exit_code, 0) << full.err;
    for (const auto& [other, tol] : {std::pair{points(nlohmann::json::parse(g.out)), 1e-9},
                                     std::pair{points(nlohmann::json::parse(full.out)), 0.06}}) {
      std::size_t compared = 0;
      for (const auto& [tau, dev] : mine)
        for (const auto& [tau_o, dev_o] : other)
          if (std::abs(tau / tau_o - 1.0) < 0.01) {
            EXPECT_NEAR(dev / dev_o, 1.0, tol) << "tau " << tau;
            ++compared;
          }
      EXPECT_EQ(compared, mine.size()) << pooled.out;
    }
  }
}

}  // namespace
