/// \file
/// \brief Simulate to a recording, with its truth (simulate.hpp).
#include "gyroflip/workflow/simulate.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/recording_writer.hpp"
#include "gyroflip/sensor/params.hpp"

namespace gyroflip::workflow {

namespace {

// One pass of the simulator: `sink` gets each block's rows (dwell averages, or with `raw` one
// row per conversion with n_avg 1). A sink error stops the run.
using row_sink = std::function<status(const std::vector<rig::dwell_row>&)>;

status run(rig::simulator& sim, int n_avg, bool raw, bool with_truth, const row_sink& sink,
           const progress_fn& on_progress) {
  rig::sample_block block(1U << 14, with_truth);
  rig::dwell_averager avg(n_avg);
  std::vector<rig::dwell_row> rows;
  while (sim.fill(block) > 0) {
    rows.clear();
    if (raw) {
      for (std::size_t i = 0; i < block.size; ++i) {
        // Conversions outside the dwells (turning and settling) carry no angle: the rig averages
        // only the dwell's conversions and its RAW frames carry only those.
        const double angle = block.dwell[i] < 0 ? method::no_value : block.angle_deg[i];
        rig::dwell_row r{block.time_s[i], angle, block.rate_dps[i], block.temp_c[i], 1};
        if (with_truth) {
          r.bias_dps = block.bias_dps[i];
          r.g_term_dps = block.g_term_dps[i];
          r.earth_dps = block.earth_dps[i];
          r.input_dps = block.input_dps[i];
        }
        rows.push_back(r);
      }
    } else {
      avg.add(block, rows);
    }
    if (auto s = sink(rows); !s) return s;
    if (on_progress)
      on_progress(static_cast<std::size_t>(sim.produced()),
                  static_cast<std::size_t>(sim.total_samples()));
  }
  return ok();
}

// The simulator's own metadata: what it derived from the configuration.
void add_simulator_metadata(std::vector<io::csv_metadata>& m, const rig::simulator& sim,
                            const rig::simulation_config& c) {
  const auto num = [](auto v) { return fmt::format("{}", v); };
  m.push_back({"conversion_time_s", num(sim.conversion_time_s())});
  m.push_back({"cycle_s", num(sim.sched().cycle_s())});
  m.push_back({"turn_s", num(sim.sched().turn_ab_s())});
  m.push_back({"scale_factor_v_per_dps", fmt::format("{} (nominal; rate_dps = ADC volts / this)",
                                                     c.sensor.scale_factor_v_per_dps)});
  for (const auto& f : sensor::fields())
    m.push_back({fmt::format("sensor.{}", f.key), num(c.sensor.*f.member)});
}

}  // namespace

simulation_truth truth_of(const rig::simulator& sim, const rig::simulation_config& c) {
  simulation_truth t;
  t.earth_dps = sim.earth_at_a_dps();
  auto temperature = c.temperature;  // a profile keeps its place (at() is not const)
  t.g_term_dps = sim.g_term_at_a_dps(temperature.at(0.0));
  t.delta_n_dps = t.earth_dps + t.g_term_dps;  // paper eqn 11
  t.indexed = c.rig.positions_deg.size() > 2 || c.order != rig::visit_order::automatic ||
              c.mount.azimuth_set() || c.mount.tilt_mrad != 0.0;
  const double temp0_c = temperature.at(0.0);
  // The terms' Fourier coefficients over the whole turn of the table, whatever its positions
  // (issue 33: "every term's true value", for any table): the discrete transform over
  // harmonic_truth_steps equally spaced angles is exact for a trigonometric polynomial of degree
  // below half of them, and the geometry gives degree 1 (a vector fixed in the world or in the
  // table's frame read along an axis turning about the table axis: rig/geometry.hpp), so c2 and
  // s2 are 0 to rounding. A fit of the run's positions (fit_harmonics) estimates these.
  for (int k = 0; k < harmonic_truth_steps; ++k) {
    const double deg = 360.0 * k / harmonic_truth_steps;
    const double a = deg * units::rad_per_deg;
    const double e = sim.earth_at_dps(deg), g = sim.g_term_at_dps(deg, temp0_c);
    t.earth_mean_dps += e / harmonic_truth_steps;
    t.g_mean_dps += g / harmonic_truth_steps;
    for (std::size_t h = 0; h < 2; ++h) {
      const double w = 2.0 / harmonic_truth_steps;
      const double ha = static_cast<double>(h + 1) * a;
      t.earth_c_dps[h] += w * e * std::cos(ha);
      t.earth_s_dps[h] += w * e * std::sin(ha);
      t.g_c_dps[h] += w * g * std::cos(ha);
      t.g_s_dps[h] += w * g * std::sin(ha);
    }
  }
  t.earth_c1_dps = t.earth_c_dps[0];
  t.earth_s1_dps = t.earth_s_dps[0];
  t.g_c1_dps = t.g_c_dps[0];
  t.g_s1_dps = t.g_s_dps[0];
  if (!t.indexed) return t;
  const position_table table = c.rig.table();
  for (const auto& p : table.positions()) {
    t.position_deg.push_back(p.angle_deg);
    t.earth_at_dps.push_back(sim.earth_at_dps(p.angle_deg));
    t.g_term_at_dps.push_back(sim.g_term_at_dps(p.angle_deg, temp0_c));
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto& geo = sim.geometry();
  t.earth_horizontal_dps = earth::earth_rate_wgs84_dps * std::cos(c.lat_deg * units::rad_per_deg);
  t.heading_deg = rig::azimuth_deg_of(geo.sensitive_axis);
  const auto& sp = c.sensor;
  const earth::ned_vector sensed{
      geo.sensitive_axis.north + sp.cross_axis_y * geo.y0.north + sp.cross_axis_z * geo.z0.north,
      geo.sensitive_axis.east + sp.cross_axis_y * geo.y0.east + sp.cross_axis_z * geo.z0.east, 0.0};
  t.sensed_heading_deg = rig::azimuth_deg_of(sensed);
  const bool vertical = std::abs(geo.table_axis.down) > 0.99;
  const bool up = geo.table_axis.down < 0.0;
  if (vertical) {
    const double sgn = up ? 1.0 : -1.0;
    double a = std::atan2(sgn * (t.earth_s1_dps + t.g_s1_dps), t.earth_c1_dps + t.g_c1_dps) /
               units::rad_per_deg;
    t.apparent_heading_deg = a < 0.0 ? a + 360.0 : a;
  } else {
    t.apparent_heading_deg = nan;
  }
  return t;
}

method::row recording_row(const rig::dwell_row& d, const position_table& table) {
  return {d.time_s, table.index_of(d.angle_deg).value_or(table_moving), d.rate_dps, d.temp_c,
          static_cast<std::uint32_t>(d.n_avg)};
}

std::vector<method::row> recording_rows(const std::vector<rig::dwell_row>& rows,
                                        const position_table& table) {
  std::vector<method::row> out;
  out.reserve(rows.size());
  for (const auto& d : rows) out.push_back(recording_row(d, table));
  return out;
}

result<simulation_truth> simulate_recording(const recording_request& r,
                                            const progress_fn& on_progress) {
  const auto& c = r.config;
  auto sim = rig::simulator::make(c);
  if (!sim) return sim.err();
  const auto truth = truth_of(*sim, c);
  std::vector<io::csv_metadata> meta{{r.made_by, "recording"}};
  meta.insert(meta.end(), r.metadata.begin(), r.metadata.end());
  add_simulator_metadata(meta, *sim, c);

  auto out = io::atomic_file::create(r.output);
  if (!out) return out.err();
  std::optional<io::atomic_file> tf;
  if (!r.truth.empty()) {
    auto t = io::atomic_file::create(r.truth);
    if (!t) return t.err();
    tf.emplace(std::move(*t));
  }
  std::string head;
  io::append_recording_header(head, meta);
  out->write(head);
  if (tf) {
    auto tmeta = meta;
    tmeta.front().value = "truth";
    head.clear();
    io::append_metadata(head, tmeta);
    tf->write(head);
    tf->write(fmt::format(
        "# sign convention: each term as seen by the sensor at that row's orientation (Earth, "
        "g-term and input reverse at 180 deg, bias does not); rate_dps ~ bias + g_term + earth + "
        "input + noise\n# dN expected at position A and the run's start temperature: earth {} + "
        "g_term {} deg/s\n",
        truth.earth_dps, truth.g_term_dps));
    tf->write(fmt::format(
        "# harmonics r(theta) = b + c1 cos(theta) + s1 sin(theta) + c2 cos(2 theta) + s2 "
        "sin(2 theta) over the table angle (Fourier over the whole turn, any table): earth c1 {} "
        "s1 {} c2 {} s2 {}; g_term c1 {} s1 {} c2 {} s2 {} deg/s\n"
        "# terms_dps (earth + g_term, what calibrate's harmonic pairing estimates besides the "
        "bias): c1 {} s1 {} c2 {} s2 {}\n",
        truth.earth_c_dps[0], truth.earth_s_dps[0], truth.earth_c_dps[1], truth.earth_s_dps[1],
        truth.g_c_dps[0], truth.g_s_dps[0], truth.g_c_dps[1], truth.g_s_dps[1], truth.c_dps(1),
        truth.s_dps(1), truth.c_dps(2), truth.s_dps(2)));
    if (truth.indexed) {
      std::string x = fmt::format(
          "# heading_deg: {} (azimuth of the sensitive axis at table 0, from north clockwise)\n"
          "# sensed_heading_deg: {} (of the axis the gyro senses, with its cross-axis "
          "sensitivity)\n"
          "# apparent_heading_deg: {} (what one run reads when the g-term's first harmonic, "
          "table tilt x g-sensitivity, is taken for Earth rate)\n"
          "# earth_horizontal_dps: {}\n"
          "# scale_factor_error_ppm: {}\n",
          truth.heading_deg, truth.sensed_heading_deg, truth.apparent_heading_deg,
          truth.earth_horizontal_dps, c.sensor.scale_factor_error_ppm);
      for (std::size_t i = 0; i < truth.position_deg.size(); ++i)
        x += fmt::format("# position {} at {} deg: earth {} g_term {} deg/s\n", i,
                         truth.position_deg[i], truth.earth_at_dps[i], truth.g_term_at_dps[i]);
      tf->write(x);
    }
    tf->write("time_s,bias_dps,g_term_dps,earth_dps,input_dps,temp_c\n");
  }
  std::string rec;
  fmt::memory_buffer tru;
  const position_table table = c.rig.table();
  const auto sink = [&](const std::vector<rig::dwell_row>& rows) -> status {
    rec.clear();
    tru.clear();
    for (const auto& w : rows) {
      io::append_recording_row(rec, recording_row(w, table), table);
      if (tf)
        fmt::format_to(std::back_inserter(tru), "{},{},{},{},{},{}\n", w.time_s, w.bias_dps,
                       w.g_term_dps, w.earth_dps, w.input_dps, w.temp_c);
    }
    // The gate of every written number (io/finite_output.hpp); on failure the temporaries go.
    if (auto s = io::check_finite(rec, r.output); !s) return s;
    if (auto s = io::check_finite({tru.data(), tru.size()}, r.truth); !s) return s;
    out->write(rec);
    if (tf) tf->write(std::string_view(tru.data(), tru.size()));
    return ok();
  };
  if (auto s = run(*sim, c.rig.n_avg, r.raw, tf.has_value(), sink, on_progress); !s) return s.err();
  // Both files or neither: a full disk on the truth must not leave a recording without it.
  if (auto s = io::commit_all({&*out, tf ? &*tf : nullptr}); !s) return s.err();
  return truth;
}

result<simulated_run> simulate_rows(const rig::simulation_config& c, bool with_truth,
                                    const progress_fn& on_progress) {
  auto sim = rig::simulator::make(c);
  if (!sim) return sim.err();
  simulated_run out;
  out.truth = truth_of(*sim, c);
  const auto sink = [&](const std::vector<rig::dwell_row>& rows) -> status {
    for (const auto& w : rows) {
      // As a recording file: nothing that is not finite.
      if (auto s = io::check_finite(std::array{w.time_s, w.rate_dps, w.temp_c}, "simulation"); !s)
        return s;
      if (with_truth)
        if (auto s = io::check_finite(
                std::array{w.bias_dps, w.g_term_dps, w.earth_dps, w.input_dps}, "simulation");
            !s)
          return s;
    }
    out.rows.insert(out.rows.end(), rows.begin(), rows.end());
    return ok();
  };
  if (auto s = run(*sim, c.rig.n_avg, false, with_truth, sink, on_progress); !s) return s.err();
  return out;
}

}  // namespace gyroflip::workflow
