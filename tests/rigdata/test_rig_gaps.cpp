// A lost dwell in a rig recording's Allan analysis (issue 32 item 5): `adev` and `noise` refused
// a recording with a single lost dwell even with --gaps split (its cycles fell off the uniform
// grid). A lost dwell is a gap on the grid of cycles, as a missing time stamp is in a CSV: named
// by default, split off with --gaps split, bridged by --kind gradev; each says how much.
#include <gtest/gtest.h>

#include <string>

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
    EXPECT_NE(noise.err.find("analysed the longest gap-free stretch: 190 of 301"),
              std::string::npos)
        << noise.err;
  }
}

}  // namespace
