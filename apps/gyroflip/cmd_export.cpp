/// \file
/// \brief `gyroflip export` (docs/FORMATS.md, "Rig recording"): a `.gfr` recording as a
/// recording CSV, one row per dwell (or per RAW conversion), with the accelerometer and the
/// device's own dwell fields as extra columns the CSV readers ignore.
#include <array>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cmd_record.hpp"
#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/hdf5_table.hpp"
#include "gyroflip/io/recording_writer.hpp"
#include "gyroflip/rigdata/rig_run.hpp"

namespace gyroflip::app {

namespace {

// A field that may be absent (NaN): written empty.
void field(std::string& out, double v) {
  if (std::isfinite(v))
    fmt::format_to(std::back_inserter(out), ",{}", v);
  else
    out += ',';
}

// The run's metadata and its table (`# positions_deg:`, which the CSV readers take the angles'
// positions from: docs/FORMATS.md).
std::vector<io::csv_metadata> export_metadata(const rigdata::rig_run& run) {
  auto m = rigdata::csv_metadata(run);
  if (const auto table = rigdata::positions_of(run); !table.empty())
    m.push_back({"positions_deg", table.describe(false)});
  return m;
}

std::string dwell_csv(const rigdata::rig_run& run) {
  bool temp = true, accel = false;
  for (const auto& d : run.dwells) {
    if (d.d.n == 0) continue;
    temp = temp && std::isfinite(d.temp_c);
    accel = accel || std::isfinite(d.accel_x_g) || std::isfinite(d.accel_y_g);
  }
  std::string out;
  io::append_metadata(out, export_metadata(run));
  out += temp ? "time_s,angle_deg,rate_dps,temp_c,n_avg" : "time_s,angle_deg,rate_dps,n_avg";
  if (accel) out += ",accel_x_g,accel_y_g";
  out += ",cycle,position,flags,segment,seq\n";
  for (const auto& d : run.dwells) {
    if (d.d.n == 0) continue;  // no conversion: no value (its flags say why)
    fmt::format_to(std::back_inserter(out), "{}", d.time_s);
    // A table that did not reach its position has no angle: the readers skip the row.
    field(out, (d.d.flags & protocol::dwell_step_fault) != 0 ? method::no_value : d.angle_deg);
    field(out, d.rate_dps);
    if (temp) field(out, d.temp_c);
    fmt::format_to(std::back_inserter(out), ",{}", d.d.n);
    if (accel) {
      field(out, d.accel_x_g);
      field(out, d.accel_y_g);
    }
    fmt::format_to(std::back_inserter(out), ",{},{},{},{},{}\n", d.d.cycle, d.d.position, d.d.flags,
                   d.segment, d.seq);
  }
  return out;
}

std::string raw_csv(const rigdata::rig_run& run) {
  std::string out;
  io::append_metadata(out, export_metadata(run));
  out += "time_s,angle_deg,rate_dps,n_avg,code\n";
  for (const auto& c : run.conversions)
    fmt::format_to(std::back_inserter(out), "{},{},{},1,{}\n", c.time_s, c.angle_deg, c.rate_dps,
                   c.code);
  return out;
}

bool is_hdf5(const std::string& path) {
  return path.ends_with(".h5") || path.ends_with(".hdf5");
}

// The same rows as the CSV, as HDF5 datasets with units. Rows without an angle (a step fault)
// are left out: HDF5 has no empty field, and nothing written is NaN.
result<std::vector<std::uint8_t>> hdf5_of(const rigdata::rig_run& run, bool raw) {
  std::vector<io::hdf5_column> cols;
  const auto col = [&cols](const char* name, const char* unit) -> std::vector<double>& {
    cols.push_back({name, unit, {}});
    return cols.back().values;
  };
  if (raw) {
    auto& t = col("time_s", "s");
    auto& a = col("angle_deg", "deg");
    auto& r = col("rate_dps", "deg/s");
    auto& k = col("code", "1");
    for (const auto& c : run.conversions) {
      t.push_back(c.time_s);
      a.push_back(c.angle_deg);
      r.push_back(c.rate_dps);
      k.push_back(c.code);
    }
    return io::hdf5_table_image(cols, export_metadata(run));
  }
  std::vector<const rigdata::rig_dwell*> rows;
  bool temp = true, accel = true;
  const auto table = rigdata::positions_of(run);
  for (const auto& d : run.dwells) {
    if (!rigdata::dwell_row(d, table)) continue;
    rows.push_back(&d);
    temp = temp && std::isfinite(d.temp_c);
    accel = accel && std::isfinite(d.accel_x_g) && std::isfinite(d.accel_y_g);
  }
  cols.reserve(12);
  const auto add = [&](const char* name, const char* unit, auto get) {
    auto& v = col(name, unit);
    for (const auto* d : rows) v.push_back(static_cast<double>(get(*d)));
  };
  add("time_s", "s", [](const rigdata::rig_dwell& d) { return d.time_s; });
  add("angle_deg", "deg", [](const rigdata::rig_dwell& d) { return d.angle_deg; });
  add("rate_dps", "deg/s", [](const rigdata::rig_dwell& d) { return d.rate_dps; });
  if (temp) add("temp_c", "degC", [](const rigdata::rig_dwell& d) { return d.temp_c; });
  add("n_avg", "1", [](const rigdata::rig_dwell& d) { return d.d.n; });
  if (accel) {
    add("accel_x_g", "g", [](const rigdata::rig_dwell& d) { return d.accel_x_g; });
    add("accel_y_g", "g", [](const rigdata::rig_dwell& d) { return d.accel_y_g; });
  }
  add("cycle", "1", [](const rigdata::rig_dwell& d) { return d.d.cycle; });
  add("position", "1", [](const rigdata::rig_dwell& d) { return d.d.position; });
  add("flags", "1", [](const rigdata::rig_dwell& d) { return d.d.flags; });
  return io::hdf5_table_image(cols, export_metadata(run));
}

}  // namespace

int run_export(const export_options& o) {
  if (auto s = io::check_outputs(std::array{o.file}, std::array{o.output}); !s)
    return report(s.err());
  auto run = rigdata::read_rig_run(o.file, o.raw, o.strict);
  if (!run) return report(run.err());
  for (const auto& w : run->warnings) warn(w);
  // Dwells the file holds but no run of the device can be established for: with none left to
  // write, an empty CSV would look like a recording of nothing (issue 32: one bit in START).
  const std::size_t held = run->outside_runs + run->unknown_config + run->unidentified +
                           run->other_board + run->unknown_boot + run->unconverted;
  if (run->dwells.empty() && held != 0)
    return report(input_error(
        {o.file}, fmt::format("none of its {} dwells can be placed in a run of its board with "
                              "their angles (the warnings above say why): nothing written",
                              held)));
  // A dwell missing from a file with damaged regions may have been stored in one of them: it
  // is not said to have never arrived.
  if (run->lost_dwells != 0 && run->damaged_regions == 0)
    warn(
        fmt::format("{}: {} dwells never arrived (the device no longer had them when they were "
                    "asked for again); the gap records count them",
                    o.file, run->lost_dwells));
  else if (run->lost_dwells != 0)
    warn(
        fmt::format("{}: {} dwells are missing: lost on the line (the gap records count those) "
                    "or stored in the {} damaged regions of the file",
                    o.file, run->lost_dwells, run->damaged_regions));
  if (o.raw && run->conversions.empty())
    return report(input_error(
        {o.file}, "no RAW conversions in this recording (record with --raw to keep them)"));
  if (o.raw && run->unplaced_conversions != 0)
    warn(
        fmt::format("{}: {} RAW conversions belong to dwells whose DWELL frame was lost: they "
                    "have no time or angle and are not exported",
                    o.file, run->unplaced_conversions));
  std::string text;
  if (is_hdf5(o.output)) {
    auto image = hdf5_of(*run, o.raw);
    if (!image) return report(image.err());
    text.assign(image->begin(), image->end());
  } else {
    text = o.raw ? raw_csv(*run) : dwell_csv(*run);
    if (auto s = check_finite(text, o.output); !s) return report(s.err());
  }
  auto out = io::atomic_file::create(o.output);
  if (!out) return report(out.err());
  out->write(text);
  if (auto s = out->commit(); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
