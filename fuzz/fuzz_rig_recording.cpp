/// \file
/// \brief libFuzzer target: the `.gfr` rig recording reader (rigdata: gfr::parse with its bit
/// repair and COPY records, rig_run's interpretation) on any bytes. What it accepts must
/// interpret without a crash; its records are never COPY records (they are used and dropped) and
/// its damaged regions lie inside the input, in order; every dwell it yields must have finite
/// time and value.
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
  for (const auto& r : f->records) check(r.type != gfr::kind::copy && r.offset < size);
  std::uint64_t last = 0;
  for (const auto& d : f->damaged) {
    check(d.offset >= last && d.bytes > 0 && d.offset + d.bytes <= size &&
          d.before <= f->records.size());
    last = d.offset + d.bytes;
  }
  auto run = gyroflip::rigdata::interpret(*f, "fuzz.gfr", true);
  if (!run) return 0;
  const auto table = gyroflip::rigdata::positions_of(*run);
  for (const auto& r : gyroflip::rigdata::dwell_rows(*run))
    check(std::isfinite(r.time_s) && std::isfinite(r.rate_dps) && r.n_avg > 0 &&
          table.holds(r.position));
  for (const auto& d : run->dwells) check(std::isfinite(d.time_s) && std::isfinite(d.angle_deg));
  for (const auto& c : run->conversions)
    check(std::isfinite(c.time_s) && std::isfinite(c.rate_dps));
  return 0;
}
