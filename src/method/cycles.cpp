/// \file
/// \brief The pairing pipeline over any row source (see cycles.hpp, row_source.hpp).
#include "gyroflip/method/cycles.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/flip_stream.hpp"

namespace gyroflip::method {

rows_in_memory::rows_in_memory(std::string name, std::span<const row> rows,
                               std::vector<metadata_entry> metadata,
                               std::vector<std::string> warnings, position_table positions)
    : name_(std::move(name)),
      rows_(rows),
      metadata_(std::move(metadata)),
      warnings_(std::move(warnings)),
      positions_(std::move(positions)),
      has_temp_(!rows.empty()) {
  for (const auto& r : rows_) has_temp_ = has_temp_ && !std::isnan(r.temp_c);
}

result<std::size_t> rows_in_memory::read(std::span<row> out) {
  const std::size_t n = std::min(out.size(), rows_.size() - next_);
  std::copy_n(rows_.begin() + static_cast<std::ptrdiff_t>(next_), n, out.begin());
  next_ += n;
  return n;
}

namespace {

// The checks every source of rows shares: data at all, both positions of the pair, enough
// cycles.
status check_cycles(const recording_cycles& rc, const flip_stream& stream, pairing p) {
  const auto& path = rc.path;
  if (rc.rows == 0) return input_error({path}, "no data rows after the header");
  if (stream.dwells_at(rc.pair.plus) == 0 || stream.dwells_at(rc.pair.minus) == 0) {
    const double plus = rc.positions.angle_deg(rc.pair.plus);
    const double minus = rc.positions.angle_deg(rc.pair.minus);
    return input_error(
        {path}, fmt::format("the table never turns (every row is at {} deg): the method needs "
                            "dwells at both {} and {} deg (an unflipped recording is for adev and "
                            "noise, not for calibrate or compensate)",
                            stream.dwells_at(rc.pair.plus) == 0 ? minus : plus, plus, minus));
  }
  if (rc.cycles.size() < min_cycles)
    return input_error(
        {path}, fmt::format("only {} cycle{} ({} dwells) with pairing '{}'; at least {} are needed",
                            rc.cycles.size(), rc.cycles.size() == 1 ? "" : "s", rc.dwells,
                            to_string(p), min_cycles));
  return ok();
}

}  // namespace

result<recording_cycles> read_cycles(row_source& source, pairing p,
                                     const progress_fn& on_progress) {
  recording_cycles rc;
  rc.path = source.name();
  rc.has_temp = source.has_temp();
  const auto meta = source.metadata();
  rc.metadata.assign(meta.begin(), meta.end());
  rc.positions = source.positions();
  // The table may name no pair (one position: an unflipped recording): the rows are still read,
  // so that a bad row or no rows at all is what is reported first.
  auto pair = flip_pair_of(rc.positions, rc.path);
  if (pair) rc.pair = *pair;
  auto demod = make_demodulator(p, rc.positions, rc.path);
  flip_stream stream(demod ? std::move(*demod) : make_flip_demodulator(p, rc.pair));
  stream.keep_dwell_rates(&rc.dwell_rates);
  const auto keep = [&rc](const cycle& c) { rc.cycles.push_back(c); };
  // A block at a time: one call through the interface per 4096 rows, and a progress report
  // per block (a report costs a call through std::function).
  std::vector<row> block(4096);
  for (;;) {
    auto n = source.read(block);
    if (!n) return n.err();
    if (*n == 0) break;
    if (demod)
      for (std::size_t k = 0; k < *n; ++k) stream.push(block[k], keep);
    rc.rows += *n;
    if (on_progress)
      on_progress(static_cast<std::size_t>(source.done()),
                  static_cast<std::size_t>(source.total()));
  }
  if (rc.rows == 0) return input_error({rc.path}, "no data rows after the header");
  if (!demod) return demod.err();
  stream.flush(keep);
  rc.dwells = stream.dwells();
  const auto w = source.warnings();
  rc.warnings.assign(w.begin(), w.end());
  if (const auto off = stream.dwells_off_pair(); off != 0)
    rc.warnings.push_back(fmt::format(
        "{}: {} dwell{} at table positions other than {} and {} deg: the pairing '{}' pairs those "
        "two and leaves the others out",
        rc.path, off, off == 1 ? "" : "s", rc.positions.angle_deg(rc.pair.plus),
        rc.positions.angle_deg(rc.pair.minus), to_string(p)));
  if (auto s = check_cycles(rc, stream, p); !s) return s.err();
  return rc;
}

result<recording_cycles> cycles_of_rows(const std::string& name, std::span<const row> rows,
                                        pairing p, std::vector<metadata_entry> metadata,
                                        const position_table& positions) {
  rows_in_memory source(name, rows, std::move(metadata), {}, positions);
  return read_cycles(source, p);
}

}  // namespace gyroflip::method
