/// \file
/// \brief libFuzzer target: the `.gfr` rig recording reader (rigdata: gfr::parse with its bit
/// repair and COPY records, rig_run's interpretation) on any bytes. What it accepts must
/// interpret without a crash; its records are never COPY records (they are used and dropped) and
/// its damaged regions lie inside the input, in order (a region listed again lies where its first
/// listing does); every dwell it yields must have finite
/// time and value.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

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
  // Damaged regions are listed in reading order (by `before`). A region among records read out
  // of the file's order is listed twice, the second marked `again` (gfr.hpp): the first listings
  // lie inside the file without overlapping; each `again` repeats a first listing.
  std::vector<gfr::damaged_region> first;
  std::size_t before = 0;
  for (const auto& d : f->damaged) {
    check(d.bytes > 0 && d.offset + d.bytes <= size && d.before <= f->records.size() &&
          d.before >= before);
    before = d.before;
    if (!d.again) first.push_back(d);
  }
  std::sort(first.begin(), first.end(),
            [](const auto& a, const auto& b) { return a.offset < b.offset; });
  for (std::size_t k = 1; k < first.size(); ++k)
    check(first[k].offset >= first[k - 1].offset + first[k - 1].bytes);
  for (const auto& d : f->damaged)
    check(!d.again || std::any_of(first.begin(), first.end(), [&](const auto& o) {
      return o.offset == d.offset && o.bytes == d.bytes;
    }));
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
