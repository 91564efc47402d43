/// \file
/// \brief Any recording as the method's input (recordings.hpp).
#include "gyroflip/workflow/recordings.hpp"

#include <utility>

#include "gyroflip/method/dwells.hpp"
#include "gyroflip/rigdata/rig_run.hpp"

namespace gyroflip::workflow {

namespace {

bool is_rig_recording(const std::string& path) {
  return path.ends_with(".gfr");
}

}  // namespace

result<io::recording_cycles> read_cycles(const std::string& path, method::pairing p,
                                         const progress_fn& on_progress,
                                         double angle_tolerance_deg) {
  // A CSV recording may be far larger than memory: streamed. A rig recording holds dwells.
  if (!is_rig_recording(path)) return io::read_cycles(path, p, on_progress, angle_tolerance_deg);
  auto rr = rigdata::read_recording_rows(path, angle_tolerance_deg);
  if (!rr) return rr.err();
  auto rc = io::cycles_of_rows(path, rr->rows, p, std::move(rr->metadata));
  if (rc) rc->warnings = std::move(rr->warnings);
  return rc;
}

result<recording_run> run_of_rows(const std::string& name, std::vector<method::row> rows,
                                  std::vector<io::csv_metadata> metadata) {
  recording_run r;
  r.file = name;
  r.dwells = method::extract_dwells(rows);
  for (const auto p : {method::pairing::simple, method::pairing::abba}) {
    auto c = io::cycles_of_rows(name, rows, p, metadata);
    if (!c) return c.err();
    r.has_temp = c->has_temp;
    (p == method::pairing::abba ? r.abba : r.simple) = std::move(c->cycles);
  }
  r.metadata = std::move(metadata);
  return r;
}

result<recording_run> read_run(const std::string& path, double angle_tolerance_deg) {
  auto rr = rigdata::read_recording_rows(path, angle_tolerance_deg);
  if (!rr) return rr.err();
  auto r = run_of_rows(path, std::move(rr->rows), std::move(rr->metadata));
  if (r) r->warnings = std::move(rr->warnings);
  return r;
}

std::string metadata_value(std::span<const io::csv_metadata> metadata, std::string_view key) {
  for (const auto& e : metadata)
    if (e.key == key) return e.value;
  return {};
}

}  // namespace gyroflip::workflow
