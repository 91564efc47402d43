/// \file
/// \brief Any recording as the method's row source (see recording_source.hpp).
#include "gyroflip/rigdata/recording_source.hpp"

#include <cmath>
#include <utility>

#include "gyroflip/io/recording.hpp"

namespace gyroflip::rigdata {

rig_rows::rig_rows(rig_run run)
    : run_(std::move(run)), table_(positions_of(run_)), metadata_(csv_metadata(run_)) {
  // As rows in memory: temperatures when there are rows and every one has its temperature.
  bool any = false;
  bool all = true;
  for (const auto& d : run_.dwells)
    if (const auto r = dwell_row(d, table_)) {
      any = true;
      all = all && !std::isnan(r->temp_c);
    }
  has_temp_ = any && all;
}

result<std::size_t> rig_rows::read(std::span<method::row> out) {
  std::size_t n = 0;
  for (; n < out.size() && next_ < run_.dwells.size(); ++next_)
    if (const auto r = dwell_row(run_.dwells[next_], table_)) out[n++] = *r;
  return n;
}

result<std::unique_ptr<method::row_source>> open_recording(const std::string& path,
                                                           double angle_tolerance_deg) {
  if (path.ends_with(".gfr")) {
    auto run = read_rig_run(path);
    if (!run) return run.err();
    return std::unique_ptr<method::row_source>(std::make_unique<rig_rows>(std::move(*run)));
  }
  auto reader = io::recording_reader::open(path, angle_tolerance_deg);
  if (!reader) return reader.err();
  return std::unique_ptr<method::row_source>(
      std::make_unique<io::recording_reader>(std::move(*reader)));
}

result<recording_rows> read_recording_rows(const std::string& path, double angle_tolerance_deg) {
  auto source = open_recording(path, angle_tolerance_deg);
  if (!source) return source.err();
  auto& src = **source;
  recording_rows out;
  std::vector<method::row> block(4096);
  for (;;) {
    auto n = src.read(block);
    if (!n) return n.err();
    if (*n == 0) break;
    out.rows.insert(out.rows.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(*n));
  }
  out.positions = src.positions();
  const auto m = src.metadata();
  out.metadata.assign(m.begin(), m.end());
  const auto w = src.warnings();
  out.warnings.assign(w.begin(), w.end());
  return out;
}

}  // namespace gyroflip::rigdata
