/// \file
/// \brief A `.gfr` recording as a rig run (rig_run.hpp).
#include "gyroflip/rigdata/rig_run.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/protocol/frame.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/recording.hpp"

namespace gyroflip::rigdata {

double adc_lsb_v(std::uint8_t range_code) noexcept {
  return 2.0 * ad7739::full_scale_uv(range_code) * 1e-6 / 16777216.0;
}

namespace {

// ADXL202/ADXL210 duty cycle to g: A = (T1/T2 - 0.5) / 12.5 % (data sheet Rev. B, p. 1;
// docs/FACTS.md section 9), in double precision (protocol::adxl202_accel_mg rounds to milli-g).
double accel_g(std::uint32_t high_ticks, std::uint32_t period_ticks) {
  if (period_ticks == 0) return method::no_value;
  return (static_cast<double>(high_ticks) / period_ticks - 0.5) / 0.125;
}

// A stored payload (INFO, CONFIGURE) decoded as its message, as a frame of that type would be.
template <class M>
bool decode(const std::vector<std::uint8_t>& body, M& m) {
  return protocol::frame{static_cast<std::uint8_t>(M::type), 0, body.data(), body.size()}.as(m);
}

// INFO as stored: older firmware's INFO lacks fields that came before the configuration, read
// as 0. The 80-byte INFO of firmware 0.2 (files of format 3 and older) has no `board` (board
// unknown: read as 0, a board); the 81-byte INFO of firmware 0.3 has no `stored`, `delta_n_q8`,
// `prev_next_seq` and `prev_dwells` (firmware 0.4, issue 32: nothing stored, previous boot
// unknown).
bool decode_info(const std::vector<std::uint8_t>& body, protocol::info_msg& m) {
  constexpr std::size_t board_at = 26;
  constexpr std::size_t stored_at = 27;
  constexpr std::size_t without_board = 80;
  constexpr std::size_t without_stored = 81;
  constexpr std::size_t stored_fields = 11;  // u8 stored, i32, u16, u32
  if (body.size() != without_board && body.size() != without_stored) return decode(body, m);
  std::vector<std::uint8_t> b(body);
  if (b.size() == without_board) b.insert(b.begin() + board_at, std::uint8_t{0});
  b.insert(b.begin() + stored_at, stored_fields, std::uint8_t{0});
  return decode(b, m);
}

bool within(double v, double lo, double hi) {
  return std::isfinite(v) && v >= lo && v <= hi;
}

}  // namespace

status check_units(const device_units& u, const std::string& what) {
  if (!within(std::fabs(u.scale_factor_v_per_dps), 1e-6, 100.0))
    return input_error({what}, fmt::format("scale_factor_v_per_dps {} is not a gyro's scale "
                                           "factor (1e-6 to 100 V per deg/s)",
                                           u.scale_factor_v_per_dps));
  if (!within(std::fabs(u.temp_v_per_c), 1e-6, 10.0))
    return input_error({what}, fmt::format("temp_v_per_c {} is not a temperature output's slope "
                                           "(1e-6 to 10 V/degC)",
                                           u.temp_v_per_c));
  if (!within(u.temp_at_0v_c, io::recording_reader::min_temp_c, io::recording_reader::max_temp_c))
    return input_error({what}, fmt::format("temp_at_0v_c {} is outside what a recording may hold "
                                           "({} to {} degC)",
                                           u.temp_at_0v_c, io::recording_reader::min_temp_c,
                                           io::recording_reader::max_temp_c));
  return ok();
}

result<device_units> units_of(const std::string& meta, const std::string& path) {
  const auto j = nlohmann::json::parse(meta, nullptr, false);
  const auto bad = [&](const char* what) {
    return input_error({path}, fmt::format("record 1: META {}", what));
  };
  if (j.is_discarded() || !j.is_object()) return bad("is not a JSON object");
  device_units u;
  const auto num = [&](const char* key, double& out) {
    const auto it = j.find(key);
    if (it == j.end() || !it->is_number()) return false;
    out = it->get<double>();
    return std::isfinite(out);
  };
  if (!num("scale_factor_v_per_dps", u.scale_factor_v_per_dps))
    return bad("has no usable scale_factor_v_per_dps");
  if (!num("temp_v_per_c", u.temp_v_per_c)) return bad("has no usable temp_v_per_c");
  if (!num("temp_at_0v_c", u.temp_at_0v_c)) return bad("has no usable temp_at_0v_c");
  if (const auto it = j.find("sensor"); it != j.end() && it->is_string()) u.sensor = *it;
  if (auto s = check_units(u, path + ": record 1: META"); !s) return s.err();
  return u;
}

rig_run_builder::rig_run_builder(std::string path, bool with_conversions)
    : with_conversions_(with_conversions) {
  run_.path = std::move(path);
}

// Sequence numbers within one device session, unwrapped in file order: a frame sent again
// arrives within 32 768 numbers of the newest one.
std::uint64_t rig_run_builder::unwrap(std::uint16_t seq) {
  if (!have_seq_) {
    have_seq_ = true;
    highest_seq_ = (std::uint64_t{1} << 32) + seq;
    return highest_seq_;
  }
  const auto d = static_cast<std::int16_t>(static_cast<std::uint16_t>(seq - highest_seq_));
  const auto s = static_cast<std::uint64_t>(static_cast<std::int64_t>(highest_seq_) + d);
  highest_seq_ = std::max(highest_seq_, s);
  return s;
}

double rig_run_builder::angle_of(const protocol::configure_msg& c, std::uint8_t pos) const {
  if (pos >= c.n_positions || pos >= protocol::max_positions) return method::no_value;
  return c.pos_cdeg[pos] / 100.0;
}

rig_dwell rig_run_builder::physical(const protocol::dwell_msg& d, const protocol::configure_msg& c,
                                    double t0_s, double t1_s) const {
  rig_dwell r;
  r.d = d;
  r.time_s = 0.5 * (t0_s + t1_s);
  r.angle_deg = angle_of(c, d.position);
  r.rate_dps =
      d.n == 0 ? method::no_value
               : static_cast<double>(d.code_sum) / d.n * lsb_v_ / run_.units.scale_factor_v_per_dps;
  if (d.n_temp != 0)
    r.temp_c = static_cast<double>(d.temp_sum) / d.n_temp * lsb_v_ / run_.units.temp_v_per_c +
               run_.units.temp_at_0v_c;
  r.accel_x_g = accel_g(d.ax_high_ticks, d.ax_period_ticks);
  r.accel_y_g = accel_g(d.ay_high_ticks, d.ay_period_ticks);
  return r;
}

status rig_run_builder::add(const gfr::record& r, std::size_t n) {
  const auto bad = [&](const std::string& what) {
    return input_error({run_.path}, fmt::format("record {}: {}", n, what));
  };
  if (!have_meta_) {
    if (r.type != gfr::kind::meta) return bad("the first record is not META");
    have_meta_ = true;
    run_.meta_json.assign(r.body.begin(), r.body.end());
    auto u = units_of(run_.meta_json, run_.path);
    if (!u) return u.err();
    run_.units = *u;
    return ok();
  }
  switch (r.type) {
    case gfr::kind::meta:
      return bad("a second META record");
    case gfr::kind::info:
      if (!decode_info(r.body, run_.info)) return bad("INFO body does not decode");
      if (run_.info.tick_hz == 0) return bad("INFO gives a tick rate of 0");
      have_info_ = true;
      lsb_v_ = adc_lsb_v(run_.info.range);
      run_.config = run_.info.config;
      return ok();
    case gfr::kind::configure:
      if (!decode(r.body, run_.config)) return bad("CONFIGURE body does not decode");
      if (run_.config.n_positions < 2 || run_.config.n_positions > protocol::max_positions)
        return bad(fmt::format("CONFIGURE with {} positions", run_.config.n_positions));
      return ok();
    case gfr::kind::start: {
      if (r.body.size() != 0 && r.body.size() != 2 && r.body.size() != 4)
        return bad("START record of the wrong size");
      start_mark m{session_, std::nullopt, n, r.host_time_us, run_.config};
      if (r.body.size() >= 2)
        m.after_seq = unwrap(static_cast<std::uint16_t>(r.body[0] | (r.body[1] << 8)));
      // Format 3: the CRC of the configuration the device started with. A damaged CONFIGURE
      // record leaves an older one (or INFO's) in force here: its angle table would label the
      // run's dwells wrongly, so the run's angles are unknown instead.
      if (r.body.size() == 4)
        m.config_known = protocol::configure_crc(run_.config) ==
                         static_cast<std::uint16_t>(r.body[2] | (r.body[3] << 8));
      starts_.push_back(m);
      return ok();
    }
    case gfr::kind::frame: {
      if (r.body.size() < 3) return bad("frame record shorter than its header");
      if (!have_info_) return bad("a device frame before the device's INFO");
      ++run_.frames;
      // u8 type, u16 seq (little-endian), payload: the frame as the decoder gave it.
      const auto seq = static_cast<std::uint16_t>(r.body[1] | (r.body[2] << 8));
      const protocol::frame fr{r.body[0], seq, r.body.data() + 3, r.body.size() - 3};
      const std::uint64_t s = unwrap(seq);
      if (fr.type == static_cast<std::uint8_t>(protocol::msg::dwell)) {
        protocol::dwell_msg d;
        if (!fr.as(d)) return bad("DWELL body does not decode");
        arrivals_.push_back({d, session_, s, seq, n, r.host_time_us, run_.config});
        // The live view: arrival order, ticks continued from the last dwell.
        if (!live_started_) live_last_ = d.t_start_ticks;
        live_started_ = true;
        live_s_ += static_cast<std::int32_t>(d.t_end_ticks - live_last_) /
                   static_cast<double>(run_.info.tick_hz);
        live_last_ = d.t_end_ticks;
        run_.dwells.push_back(physical(d, run_.config, live_s_, live_s_));
        run_.dwells.back().seq = seq;
      } else if (fr.type == static_cast<std::uint8_t>(protocol::msg::raw)) {
        protocol::raw_msg m;
        if (!fr.as(m) || m.count > protocol::raw_msg::max_codes)
          return bad("RAW body does not decode");
        if (with_conversions_) raws_.push_back({m, session_, s, n});
      }
      return ok();
    }
    case gfr::kind::gap: {
      if (r.body.size() != 5) return bad("gap record of the wrong size");
      protocol::reader body{r.body.data(), r.body.size()};
      const std::uint8_t reason = body.u8();
      const std::uint32_t count = body.u32();
      switch (static_cast<gfr::gap_reason>(reason)) {
        case gfr::gap_reason::corrupt:
          run_.corrupt_frames += count;
          return ok();
        case gfr::gap_reason::missing:
          run_.missing_frames += count;
          return ok();
        case gfr::gap_reason::device_reset:
          ++run_.device_resets;
          ++session_;  // the rebooted device numbers its frames from 0 again
          have_seq_ = false;
          return ok();
        case gfr::gap_reason::link_lost:
          ++run_.link_losses;
          return ok();
      }
      return bad("gap record of an unknown reason");
    }
    case gfr::kind::stop:
      if (r.body.size() != 1 || r.body[0] < 1 ||
          r.body[0] > static_cast<std::uint8_t>(gfr::stop_reason::device_failed))
        return bad("STOP record of an unknown reason");
      run_.stop = static_cast<gfr::stop_reason>(r.body[0]);
      return ok();
  }
  return bad("unknown record kind");
}

// The RAW codes of dwell k = n_positions cycle + position are the run's gyro conversions
// k n_avg .. (k+1) n_avg - 1 (a RDY timeout uses an index too: docs/PROTOCOL.md, RAW); each is
// placed at the end of its conversion period within the dwell.
void rig_run_builder::place(
    const rig_dwell& r, double t0_s, double t1_s,
    std::map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::int32_t>>>& pend,
    const protocol::configure_msg& cfg) {
  const std::uint16_t n_avg = cfg.n_avg;
  const std::uint64_t k = std::uint64_t{cfg.n_positions} * r.d.cycle + r.d.position;
  const auto it = pend.find(k);
  if (it == pend.end()) return;
  for (const auto& [j, code] : it->second) {
    rig_conversion c;
    c.time_s = t0_s + (t1_s - t0_s) * (j + 1) / n_avg;
    c.angle_deg = r.angle_deg;
    c.code = code;
    c.rate_dps = code * lsb_v_ / run_.units.scale_factor_v_per_dps;
    run_.conversions.push_back(c);
  }
  pend.erase(it);
}

result<rig_run> rig_run_builder::finish() && {
  // Each dwell's run: the last START of its device session whose acknowledgement it follows.
  std::vector<std::vector<const arrival*>> runs(starts_.size());
  const auto run_of = [&](std::uint32_t session, std::uint64_t seq,
                          std::size_t record) -> std::optional<std::size_t> {
    for (std::size_t i = starts_.size(); i-- > 0;) {
      const start_mark& m = starts_[i];
      if (m.session != session) continue;
      if (m.after_seq ? seq > *m.after_seq : record > m.record) return i;
    }
    return std::nullopt;
  };
  for (const arrival& a : arrivals_) {
    if (auto i = run_of(a.session, a.seq, a.record)) {
      runs[*i].push_back(&a);
    } else {
      ++run_.outside_runs;
    }
  }
  run_.dwells.clear();
  double last_end_s = 0.0;
  std::uint64_t last_host_us = 0;
  bool any = false;
  std::size_t unknown_positions = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    auto& v = runs[i];
    if (v.empty()) continue;
    std::sort(v.begin(), v.end(),
              [](const arrival* a, const arrival* b) { return a->seq < b->seq; });
    // Repeats of a frame (stored twice) are read once.
    v.erase(std::unique(v.begin(), v.end(),
                        [](const arrival* a, const arrival* b) { return a->seq == b->seq; }),
            v.end());
    if (!starts_[i].config_known) {
      run_.unknown_config += v.size();
      continue;
    }
    const protocol::configure_msg& cfg = starts_[i].config;
    std::map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::int32_t>>> pend;
    if (with_conversions_ && cfg.n_avg != 0) {
      const std::uint64_t after = starts_[i].after_seq.value_or(0);
      for (const raw_block& b : raws_) {
        if (b.session != starts_[i].session || b.seq <= after) continue;
        if (run_of(b.session, b.seq, b.record) != i) continue;
        for (std::uint8_t k = 0; k < b.m.count; ++k) {
          const std::uint64_t index = std::uint64_t{b.m.first_index} + k;
          pend[index / cfg.n_avg].emplace_back(static_cast<std::uint32_t>(index % cfg.n_avg),
                                               b.m.code(k));
        }
      }
    }
    // Device ticks (u32, wrapping) continued into one count in sequence order; a later run
    // continues after the last one by the host's gap between them.
    const std::uint32_t origin = v.front()->d.t_start_ticks;
    const double offset_s =
        any ? last_end_s + static_cast<double>(v.front()->host_us - last_host_us) * 1e-6 : 0.0;
    std::int32_t prev_start = -1;
    std::uint64_t expected_k = 0, seen = 0;
    for (const arrival* a : v) {
      const double hz = run_.info.tick_hz;
      const std::int32_t t0 = static_cast<std::int32_t>(a->d.t_start_ticks - origin);
      const std::int32_t t1 = static_cast<std::int32_t>(a->d.t_end_ticks - origin);
      if (t0 < prev_start || t1 < t0)
        return input_error({run_.path},
                           fmt::format("record {}: DWELL of cycle {} position {} starts at "
                                       "device tick {}, before the dwell before it: its times go "
                                       "backwards (the file is damaged)",
                                       a->record, a->d.cycle, a->d.position, a->d.t_start_ticks));
      prev_start = t0;
      rig_dwell r = physical(a->d, cfg, offset_s + t0 / hz, offset_s + t1 / hz);
      r.seq = a->seq16;
      r.segment = static_cast<std::uint32_t>(i);
      if (std::isfinite(r.temp_c) &&
          !within(r.temp_c, io::recording_reader::min_temp_c, io::recording_reader::max_temp_c))
        return input_error({run_.path},
                           fmt::format("record {}: a dwell's temperature is {:.6g} degC, outside "
                                       "what a recording may hold ({} to {} degC): the "
                                       "temperature conversion (META) or the file is wrong",
                                       a->record, r.temp_c, io::recording_reader::min_temp_c,
                                       io::recording_reader::max_temp_c));
      if (!std::isfinite(r.angle_deg)) {
        ++unknown_positions;  // not in the angle table: never guessed
        continue;
      }
      if (with_conversions_) place(r, offset_s + t0 / hz, offset_s + t1 / hz, pend, cfg);
      const std::uint64_t k = std::uint64_t{cfg.n_positions} * a->d.cycle + a->d.position;
      expected_k = std::max(expected_k, k + 1);
      ++seen;
      last_end_s = offset_s + t1 / hz;
      last_host_us = a->host_us;
      run_.dwells.push_back(r);
    }
    run_.lost_dwells += expected_k - std::min(expected_k, seen);
    for (const auto& [k, codes] : pend) run_.unplaced_conversions += codes.size();
    any = true;
  }
  if (unknown_positions != 0)
    run_.warnings.push_back(fmt::format(
        "{}: {} dwells name a position outside their configuration's angle table: not used",
        run_.path, unknown_positions));
  if (run_.unknown_config != 0)
    run_.warnings.push_back(fmt::format(
        "{}: {} dwells belong to a run whose configuration (its angle table) is not in the file "
        "(the CONFIGURE record before its START is damaged or missing): not used",
        run_.path, run_.unknown_config));
  const auto off_pair = std::count_if(run_.dwells.begin(), run_.dwells.end(), [](const auto& d) {
    return d.angle_deg != 0.0 && d.angle_deg != 180.0;
  });
  if (off_pair != 0)
    run_.warnings.push_back(fmt::format(
        "{}: {} dwells at table positions other than 0 and 180 deg: the method's analyses "
        "(calibrate, compensate, adev, noise, report) pair A = 0 with B = 180 and leave them "
        "out; export writes every dwell",
        run_.path, off_pair));
  if (run_.outside_runs != 0)
    run_.warnings.push_back(fmt::format(
        "{}: {} dwells arrived outside an acknowledged run (a run the device had before the "
        "recorder's START): not used",
        run_.path, run_.outside_runs));
  if (!run_.stop)
    run_.warnings.push_back(fmt::format(
        "{}: the recording has no STOP record: the recorder ended without closing it (a kill or "
        "a power loss); everything up to its last record is read",
        run_.path));
  return std::move(run_);
}

result<rig_run> interpret(const gfr::file& f, const std::string& path, bool with_conversions) {
  rig_run_builder b(path, with_conversions);
  for (std::size_t i = 0; i < f.records.size(); ++i)
    if (auto s = b.add(f.records[i], i + 1); !s) return s.err();
  auto run = std::move(b).finish();
  if (!run) return run.err();
  run->warnings.insert(run->warnings.begin(), f.warnings.begin(), f.warnings.end());
  return run;
}

result<rig_run> read_rig_run(const std::string& path, bool with_conversions, bool strict) {
  auto f = gfr::read(path, strict);
  if (!f) return f.err();
  return interpret(*f, path, with_conversions);
}

std::optional<method::row> dwell_row(const rig_dwell& d) {
  if (d.d.n == 0 || (d.d.flags & protocol::dwell_step_fault) != 0) return std::nullopt;
  if (d.angle_deg != 0.0 && d.angle_deg != 180.0) return std::nullopt;
  return method::row{d.time_s, d.angle_deg, d.rate_dps, d.temp_c, d.d.n};
}

std::vector<method::row> dwell_rows(const rig_run& run) {
  std::vector<method::row> rows;
  rows.reserve(run.dwells.size());
  for (const auto& d : run.dwells)
    if (auto r = dwell_row(d)) rows.push_back(*r);
  return rows;
}

std::vector<io::csv_metadata> csv_metadata(const rig_run& run) {
  const auto& c = run.config;
  std::vector<io::csv_metadata> m;
  if (!run.units.sensor.empty()) m.push_back({"sensor_name", run.units.sensor});
  m.push_back({"serial", fmt::format("{}", run.info.serial)});
  m.push_back({"firmware",
               fmt::format("{}.{}.{}", run.info.fw_major, run.info.fw_minor, run.info.fw_patch)});
  if (run.info.board == static_cast<std::uint8_t>(protocol::board_kind::host_emulator))
    m.push_back({"emulated", "gyroflip emulate"});
  else if (run.info.board == static_cast<std::uint8_t>(protocol::board_kind::qemu))
    m.push_back({"emulated", "the firmware's QEMU image"});
  m.push_back({"n_avg", fmt::format("{}", c.n_avg)});
  m.push_back({"settle_s", fmt::format("{}", c.settle_ms / 1000.0)});
  m.push_back({"filter_word", fmt::format("{}", c.filter_word)});
  m.push_back({"chop", (c.flags & protocol::cfg_chop) != 0 ? "on" : "off"});
  m.push_back({"steps_per_rev", fmt::format("{}", c.steps_per_rev)});
  m.push_back({"step_rate_sps", fmt::format("{}", c.step_rate_sps)});
  return m;
}

result<recording_rows> read_recording_rows(const std::string& path, double angle_tolerance_deg) {
  recording_rows out;
  if (path.ends_with(".gfr")) {
    auto run = read_rig_run(path);
    if (!run) return run.err();
    out.rows = dwell_rows(*run);
    out.metadata = csv_metadata(*run);
    out.warnings = run->warnings;
    return out;
  }
  auto reader = io::recording_reader::open(path, angle_tolerance_deg);
  if (!reader) return reader.err();
  method::row r;
  for (;;) {
    const auto step = reader->next(r);
    if (step == io::csv_reader::step::failed) return reader->last_error();
    if (step == io::csv_reader::step::end) break;
    out.rows.push_back(r);
  }
  out.metadata = reader->metadata();
  out.warnings = reader->warnings();
  return out;
}

}  // namespace gyroflip::rigdata
