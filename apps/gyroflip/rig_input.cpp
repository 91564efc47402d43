/// \file
/// \brief `.gfr` rig recordings as input (rig_input.hpp).
#include "rig_input.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/method/flip_stream.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip::app {

bool is_rig_recording(const std::string& path) {
  return path.ends_with(".gfr");
}

result<method::recording_cycles> read_recording_cycles(const std::string& path, method::pairing p,
                                                       const progress_fn& on_progress,
                                                       double angle_tolerance_deg) {
  return workflow::read_cycles(path, p, on_progress, angle_tolerance_deg);
}

namespace {

// The run's dwells in gap-free stretches: consecutive places of one run of the device (a dwell
// at a position not the pair's is passed over, one at the pair's without a value is a gap), each
// beginning at the first of its cycle's pair of positions so that every stretch pairs its dwells
// in the same phase of the cycle. The pair is the pairings' (method::flip_pair_of).
struct stretch {
  std::uint32_t segment = 0;
  std::vector<method::row> rows;
};
double median_of(std::vector<double> d);

std::vector<stretch> stretches_of(const rigdata::rig_run& run, const position_table& table,
                                  const method::flip_pair& pair) {
  const auto in_pair = [&](const rigdata::rig_dwell& d) {
    const auto p = table.index_of(d.angle_deg);
    return p && pair.holds(*p);
  };
  // The run's cadence: the median time from a dwell to the next one of its run. Consecutive
  // places more than 1.5 of it apart (the device stood still: a stall, a restarted conversion)
  // are a gap too: a stretch is gap-free in time, not only in places (review of issue 32: a
  // stretch with a 3-s pause was handed on as uniform, its series' step taken as its span over
  // its count, and `noise --gaps split` refused it as off its grid or kept a small stretch).
  std::vector<double> steps;
  for (std::size_t k = 1; k < run.dwells.size(); ++k)
    if (run.dwells[k].segment == run.dwells[k - 1].segment &&
        run.dwells[k].index == run.dwells[k - 1].index + 1)
      steps.push_back(run.dwells[k].time_s - run.dwells[k - 1].time_s);
  const double cadence_s = median_of(std::move(steps));
  // Per run of the device: its first position of the pair (where a cycle's pair begins).
  std::vector<std::uint8_t> first(run.dwells.empty() ? 0 : run.dwells.back().segment + 1, 255);
  for (const auto& d : run.dwells)
    if (in_pair(d) && d.segment < first.size())
      first[d.segment] = std::min(first[d.segment], d.d.position);
  std::vector<stretch> out;
  const rigdata::rig_dwell* prev = nullptr;
  for (const auto& d : run.dwells) {
    const auto row = rigdata::dwell_row(d, table);
    const bool pair_angle = in_pair(d);
    if (prev == nullptr || prev->segment != d.segment || d.index != prev->index + 1 ||
        (cadence_s > 0.0 && d.time_s - prev->time_s > 1.5 * cadence_s))
      out.push_back({d.segment, {}});
    if (pair_angle && !row) {
      prev = nullptr;  // no value where the method needs one: a gap
      continue;
    }
    prev = &d;
    if (!row || !pair_angle) continue;
    if (out.back().rows.empty() && d.segment < first.size() && d.d.position != first[d.segment])
      continue;  // the second of a pair whose first is missing: no cycle of its own
    out.back().rows.push_back(*row);
  }
  std::erase_if(out, [](const stretch& s) { return s.rows.empty(); });
  return out;
}

// A stretch's samples of `column`: its dwells, or its cycles (abba).
struct samples {
  std::uint32_t segment = 0;
  std::vector<double> values, time_s, angle_deg;
};
samples samples_of(const stretch& st, const std::string& column, const position_table& table,
                   const method::flip_pair& pair) {
  samples s;
  s.segment = st.segment;
  if (column == "dwell_dps") {
    for (const auto& r : st.rows) {
      s.values.push_back(r.rate_dps);
      s.time_s.push_back(r.time_s);
      s.angle_deg.push_back(table.angle_deg(r.position));
    }
    return s;
  }
  method::flip_stream stream(method::pairing::abba, pair);
  const auto keep = [&](const method::cycle& c) {
    s.values.push_back(column == "rate_dps" ? c.rate_dps : c.bias_dps);
    s.time_s.push_back(c.time_s);
  };
  for (const auto& r : st.rows) stream.push(r, keep);
  stream.flush(keep);
  return s;
}

double median_of(std::vector<double> d) {
  if (d.empty()) return 0.0;
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid;
}

// Where each sample lies on the one grid of the stretches: within a run of the device by its
// time from the run's reference (its first sample moved by the median offset of its samples
// from a grid through it: an edge cycle is stamped a quarter step off, the interior ones not);
// a later run by the host's time between them, rounded to whole steps.
std::vector<std::vector<std::size_t>> grid_of(const std::vector<samples>& parts, double tau0_s) {
  std::map<std::uint32_t, double> ref;  // per run of the device
  for (const auto& p : parts) {
    if (ref.contains(p.segment)) continue;
    const double t0 = p.time_s.front();
    std::vector<double> off;
    for (const auto& q : parts)
      if (q.segment == p.segment)
        for (const double t : q.time_s)
          off.push_back((t - t0) - tau0_s * std::round((t - t0) / tau0_s));
    ref[p.segment] = t0 + median_of(std::move(off));
  }
  const double origin = ref.begin()->second;
  std::vector<std::vector<std::size_t>> at;
  for (const auto& p : parts) {
    const double r = ref[p.segment];
    const double base = std::round((r - origin) / tau0_s);
    auto& v = at.emplace_back();
    for (const double t : p.time_s)
      v.push_back(static_cast<std::size_t>(std::max(0.0, base + std::round((t - r) / tau0_s))));
  }
  return at;
}

}  // namespace

result<io::series> read_rig_series(const std::string& path, const std::string& column,
                                   io::gap_policy gaps, bool bridge,
                                   std::vector<io::series>* all_parts) {
  if (column != "dwell_dps" && column != "rate_dps" && column != "bias_dps")
    return about_parameter(
        input_error({path}, fmt::format("a rig recording has no series '{}': use rate_dps (per "
                                        "cycle, flip-compensated), bias_dps or dwell_dps",
                                        printable(column, 60))),
        "column");
  auto run = rigdata::read_rig_run(path);
  if (!run) return run.err();
  // What the reader noticed (a damaged region skipped, a torn tail) is shown, not dropped.
  for (const auto& w : run->warnings) warn(w);
  const auto rows = rigdata::dwell_rows(*run);
  const auto table = rigdata::positions_of(*run);
  const auto pair = method::flip_pair_of(table, path);
  if (!pair) return pair.err();
  const auto stretches = stretches_of(*run, table, *pair);
  if (stretches.size() <= 1 && !bridge) {
    std::vector<double> values, time_s, angle_deg;
    if (column == "dwell_dps") {
      for (const auto& r : rows) {
        if (!pair->holds(r.position)) continue;  // the pair's dwells, as the method sees them
        values.push_back(r.rate_dps);
        time_s.push_back(r.time_s);
        angle_deg.push_back(table.angle_deg(r.position));
      }
    } else {
      auto rc = method::cycles_of_rows(path, rows, method::pairing::abba, {}, table);
      if (!rc) return rc.err();
      for (const auto& c : rc->cycles) {
        values.push_back(column == "rate_dps" ? c.rate_dps : c.bias_dps);
        time_s.push_back(c.time_s);
      }
    }
    return io::series_of_samples(path, std::move(values), time_s, std::move(angle_deg),
                                 rigdata::csv_metadata(*run));
  }
  // Gaps: each stretch's samples placed on the one grid of their spacing.
  std::vector<samples> parts;
  for (const auto& s : stretches) parts.push_back(samples_of(s, column, table, *pair));
  std::erase_if(parts, [](const samples& p) { return p.values.empty(); });
  // One stretch with samples: no gap between samples to speak of (the others held too few
  // dwells for a sample; review of issue 32: "0 gaps" was refused as a gap).
  if (parts.size() == 1 && !bridge) {
    samples& p = parts.front();
    note(
        fmt::format("{}: {} of its {} stretches between lost dwells held no whole sample; the "
                    "other is analysed",
                    path, stretches.size() - 1, stretches.size()));
    return io::series_of_samples(path, std::move(p.values), p.time_s, std::move(p.angle_deg),
                                 rigdata::csv_metadata(*run));
  }
  std::vector<double> steps;
  for (const auto& p : parts)
    for (std::size_t k = 1; k < p.time_s.size(); ++k)
      steps.push_back(p.time_s[k] - p.time_s[k - 1]);
  const double tau0_s = median_of(std::move(steps));
  if (parts.empty() || !(tau0_s > 0.0))
    return input_error({path}, "too few dwells between its gaps for a series");
  const auto at = grid_of(parts, tau0_s);
  std::size_t grid = 0, have = 0, longest = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    grid = std::max(grid, at[k].back() + 1);
    have += parts[k].values.size();
    if (parts[k].values.size() > parts[longest].values.size()) longest = k;
  }
  const std::size_t missing = grid > have ? grid - have : 0;
  const char* unit = column == "dwell_dps" ? "dwells" : "cycles";
  const std::string where =
      fmt::format("{} gap{} in its grid of {} ({} of {} samples missing; {} dwell{} lost{})",
                  parts.size() - 1, parts.size() == 2 ? "" : "s", unit, missing, grid,
                  run->lost_dwells, run->lost_dwells == 1 ? "" : "s",
                  run->dwells.back().segment != 0 ? ", and the device's runs apart" : "");
  if (bridge) {
    const double t0_s = parts.front().time_s.front();
    std::vector<double> values(grid, method::no_value), time_s(grid);
    for (std::size_t k = 0; k < grid; ++k) time_s[k] = t0_s + static_cast<double>(k) * tau0_s;
    for (std::size_t k = 0; k < parts.size(); ++k)
      for (std::size_t j = 0; j < parts[k].values.size(); ++j)
        if (std::isnan(values[at[k][j]])) values[at[k][j]] = parts[k].values[j];
    note(fmt::format("{}: {}; bridged as GRADEV gaps", path, where));
    return io::series_of_samples(path, std::move(values), time_s, {}, rigdata::csv_metadata(*run));
  }
  if (gaps == io::gap_policy::error)
    return input_error(
        {path}, fmt::format("{}, the first after time_s {:.6g}: give --gaps split to analyse the "
                            "longest gap-free stretch (adev also: --kind gradev to bridge them)",
                            where, parts.front().time_s.back()));
  if (all_parts != nullptr) {
    // noise: every stretch, pooled (analysis::analyse_noise over parts); the longest one still
    // returned for what is said of the series as a whole.
    all_parts->clear();
    const double t0_s = parts.front().time_s.front();
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const samples& q = parts[k];
      if (q.values.size() < 4) continue;  // too short for a term
      // On the one grid from its first place, one step a sample (a stretch is gap-free): every
      // part has the same tau0, whatever its own stamps' spacing (a short stretch's mean step
      // can be a percent off the median).
      std::vector<double> on_grid(q.values.size());
      for (std::size_t j = 0; j < on_grid.size(); ++j)
        on_grid[j] = t0_s + static_cast<double>(at[k][0] + j) * tau0_s;
      auto one =
          io::series_of_samples(path, q.values, on_grid, q.angle_deg, rigdata::csv_metadata(*run));
      if (!one) return one.err();
      all_parts->push_back(std::move(*one));
    }
    note(
        fmt::format("{}: {}; analysed its {} gap-free stretches pooled ({} of {} samples; no "
                    "term spans a gap)",
                    path, where, parts.size(), have, grid));
  } else {
    const samples& q = parts[longest];
    note(
        fmt::format("{}: {}; analysed the longest gap-free stretch: {} of {} samples, time_s "
                    "{:.6g} to {:.6g}",
                    path, where, q.values.size(), grid, q.time_s.front(), q.time_s.back()));
  }
  samples& p = parts[longest];
  return io::series_of_samples(path, std::move(p.values), p.time_s, std::move(p.angle_deg),
                               rigdata::csv_metadata(*run));
}

}  // namespace gyroflip::app
