/// \file
/// \brief Any recording as the method's input (recordings.hpp).
#include "gyroflip/workflow/recordings.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/dwells.hpp"
#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/rigdata/recording_source.hpp"

namespace gyroflip::workflow {

namespace {

// The median spacing per conversion of consecutive rows at the same position (0: none).
double conversion_time_s(const std::vector<method::row>& rows) {
  std::vector<double> dt;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const auto &a = rows[k - 1], &b = rows[k];
    if (a.position == table_moving || a.position != b.position) continue;
    const double step = (b.time_s - a.time_s) / static_cast<double>(b.n_avg);
    if (step > 0.0) dt.push_back(step);
  }
  return dt.empty() ? 0.0 : analysis::upper_median(std::move(dt));
}

// The conversion time the recording's rig settings give (the AD7739's FW and CHOP at the rig's
// clock, rig/ad7739.hpp), for recordings of one row per dwell; 0 when they are not recorded.
double conversion_time_of_settings(std::span<const io::csv_metadata> metadata) {
  const std::string fw = metadata_value(metadata, "filter_word");
  const std::string chop = metadata_value(metadata, "chop");
  rig::ad7739_config c;
  const auto [end, ec] = std::from_chars(fw.data(), fw.data() + fw.size(), c.filter_word);
  if (fw.empty() || ec != std::errc{} || end != fw.data() + fw.size() ||
      c.filter_word < ad7739::fw_min || c.filter_word > ad7739::fw_max ||
      (chop != "on" && chop != "off"))
    return 0.0;
  c.chop = chop == "on";
  return rig::conversion_time_s(c);
}

}  // namespace

result<method::recording_cycles> read_cycles(const std::string& path, method::pairing p,
                                             const progress_fn& on_progress,
                                             double angle_tolerance_deg) {
  // A CSV recording may be far larger than memory: streamed. A rig recording holds dwells.
  auto source = rigdata::open_recording(path, angle_tolerance_deg);
  if (!source) return source.err();
  return method::read_cycles(**source, p, on_progress);
}

result<recording_run> run_of_rows(const std::string& name, std::vector<method::row> rows,
                                  std::vector<io::csv_metadata> metadata,
                                  const position_table& positions) {
  recording_run r;
  r.file = name;
  r.positions = positions;
  r.conversion_s = conversion_time_s(rows);
  if (r.conversion_s == 0.0) r.conversion_s = conversion_time_of_settings(metadata);
  for (const auto p : {method::pairing::simple, method::pairing::abba}) {
    auto c = method::cycles_of_rows(name, rows, p, metadata, positions);
    if (!c) return c.err();
    r.has_temp = c->has_temp;
    r.pair = c->pair;
    (p == method::pairing::abba ? r.abba : r.simple) = std::move(c->cycles);
  }
  r.dwells = method::extract_dwells(rows, r.pair);
  r.metadata = std::move(metadata);
  return r;
}

result<recording_run> read_run(const std::string& path, double angle_tolerance_deg) {
  auto rr = rigdata::read_recording_rows(path, angle_tolerance_deg);
  if (!rr) return rr.err();
  auto r = run_of_rows(path, std::move(rr->rows), std::move(rr->metadata), rr->positions);
  if (r) r->warnings = std::move(rr->warnings);
  return r;
}

std::string metadata_value(std::span<const io::csv_metadata> metadata, std::string_view key) {
  for (const auto& e : metadata)
    if (e.key == key) return e.value;
  return {};
}

io::run_source origin_of(const std::string& file, std::span<const io::csv_metadata> metadata) {
  io::run_source src;
  const auto m = [&](std::string_view key) { return metadata_value(metadata, key); };
  if (!m("gyroflip simulate").empty()) {
    src.origin = "simulated";
    src.origin_detail = fmt::format("gyroflip simulate (sensor {}, seed {}, {} s)", m("sensor"),
                                    m("seed"), m("duration_s"));
  } else if (const auto e = m("emulated"); !e.empty()) {
    src.origin = "emulated";
    src.origin_detail = fmt::format(
        "a rig recording{} of {} (device serial {}, firmware {}), not of a real board",
        file.ends_with(".gfr") ? " (.gfr)" : " exported to CSV", e, m("serial"), m("firmware"));
  } else if (file.ends_with(".gfr")) {
    src.origin = "rig";
    src.origin_detail = fmt::format("rig recording (.gfr): device serial {}, firmware {}",
                                    m("serial"), m("firmware"));
  } else {
    src.origin = "unknown";
    src.origin_detail = "recording (CSV); its metadata names no maker";
  }
  return src;
}

io::run_source source_of(const std::string& file, std::span<const io::csv_metadata> metadata,
                         const report::input_file& bytes) {
  auto src = origin_of(file, metadata);
  src.sha256 = bytes.sha256;
  src.size_bytes = bytes.size_bytes;
  return src;
}

repeat repeat_of(const io::calibration_entry& a, const io::calibration_entry& b) {
  if (a.source && b.source && a.source->sha256 == b.source->sha256) return repeat::same_bytes;
  if (a.cal.cycles == b.cal.cycles && a.cal.delta_n_dps == b.cal.delta_n_dps &&
      a.cal.std_dps == b.cal.std_dps)
    return repeat::same_cycles;
  return repeat::none;
}

status check_distinct_runs(std::span<const io::calibration_entry> runs) {
  for (std::size_t k = 1; k < runs.size(); ++k)
    for (std::size_t i = 0; i < k; ++i) {
      const auto& other = printable(runs[i].file, 200);
      switch (repeat_of(runs[i], runs[k])) {
        case repeat::none:
          break;
        case repeat::same_bytes:
          return input_error({runs[k].file},
                             fmt::format("has the same bytes as {} (SHA-256 {}): one recording "
                                         "given twice is not two runs",
                                         other, runs[k].source->sha256));
        case repeat::same_cycles:
          return input_error({runs[k].file},
                             fmt::format("gives the same {} cycles as {} (dN and std equal to the "
                                         "last digit): the same recording twice is not two runs",
                                         runs[k].cal.cycles, other));
      }
    }
  return ok();
}

std::vector<method::calibration> calibrations_of(std::span<const io::calibration_entry> runs) {
  std::vector<method::calibration> out;
  out.reserve(runs.size());
  for (const auto& r : runs) out.push_back(r.cal);
  return out;
}

std::string origin_words(const io::run_source& src) {
  if (src.origin == "simulated" || src.origin == "emulated")
    return src.origin + ": " + src.origin_detail;
  return src.origin_detail;
}

}  // namespace gyroflip::workflow
