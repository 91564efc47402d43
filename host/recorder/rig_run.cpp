/// \file
/// \brief A `.gfr` recording as a rig run (rig_run.hpp).
#include "host/recorder/rig_run.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/protocol/frame.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/recording.hpp"

namespace gyroflip::host {

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

}  // namespace

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
  if (!num("scale_factor_v_per_dps", u.scale_factor_v_per_dps) || u.scale_factor_v_per_dps == 0.0)
    return bad("has no usable scale_factor_v_per_dps");
  if (!num("temp_v_per_c", u.temp_v_per_c) || u.temp_v_per_c == 0.0)
    return bad("has no usable temp_v_per_c");
  if (!num("temp_at_0v_c", u.temp_at_0v_c)) return bad("has no usable temp_at_0v_c");
  if (const auto it = j.find("sensor"); it != j.end() && it->is_string()) u.sensor = *it;
  return u;
}

rig_run_builder::rig_run_builder(std::string path, bool with_conversions)
    : with_conversions_(with_conversions) {
  run_.path = std::move(path);
}

std::int64_t rig_run_builder::ticks(std::uint32_t t) {
  if (!clock_started_) {
    clock_started_ = true;
    clock_total_ = t;
  } else {
    clock_total_ += static_cast<std::int32_t>(t - clock_last_);
  }
  clock_last_ = t;
  return clock_total_;
}

void rig_run_builder::new_segment() {
  flush_pending();
  ++segment_;
  clock_started_ = false;
  have_origin_ = false;
}

void rig_run_builder::flush_pending() {
  for (const auto& [k, codes] : pending_) run_.unplaced_conversions += codes.size();
  pending_.clear();
}

double rig_run_builder::seconds(std::int64_t t) const {
  return offset_s_ + static_cast<double>(t - origin_ticks_) / run_.info.tick_hz;
}

void rig_run_builder::add_dwell(const protocol::dwell_msg& d, std::uint16_t seq,
                                std::uint64_t host_us) {
  const std::int64_t t0 = ticks(d.t_start_ticks);
  const std::int64_t t1 = ticks(d.t_end_ticks);
  if (!have_origin_) {
    have_origin_ = true;
    origin_ticks_ = t0;
    // A later segment continues after the last one by the host's gap between them.
    offset_s_ = run_.dwells.empty()
                    ? 0.0
                    : last_time_s_ + static_cast<double>(host_us - last_host_us_) * 1e-6;
  }
  rig_dwell r;
  r.d = d;
  r.seq = seq;
  r.segment = segment_;
  r.time_s = 0.5 * (seconds(t0) + seconds(t1));
  r.angle_deg = d.position == 0 ? 0.0 : 180.0;
  r.rate_dps =
      d.n == 0 ? method::no_value
               : static_cast<double>(d.code_sum) / d.n * lsb_v_ / run_.units.scale_factor_v_per_dps;
  if (d.n_temp != 0)
    r.temp_c = static_cast<double>(d.temp_sum) / d.n_temp * lsb_v_ / run_.units.temp_v_per_c +
               run_.units.temp_at_0v_c;
  r.accel_x_g = accel_g(d.ax_high_ticks, d.ax_period_ticks);
  r.accel_y_g = accel_g(d.ay_high_ticks, d.ay_period_ticks);
  last_time_s_ = seconds(t1);
  last_host_us_ = host_us;
  if (with_conversions_) place(r, seconds(t0), seconds(t1));
  run_.dwells.push_back(r);
}

// The RAW codes of dwell k = 2 cycle + position are the run's gyro conversions
// k n_avg .. (k+1) n_avg - 1 (a RDY timeout uses an index too: docs/PROTOCOL.md, RAW); each is
// placed at the end of its conversion period within the dwell.
void rig_run_builder::place(const rig_dwell& r, double t0_s, double t1_s) {
  const std::uint64_t k = 2ULL * r.d.cycle + r.d.position;
  while (!pending_.empty() && pending_.begin()->first < k) {
    run_.unplaced_conversions += pending_.begin()->second.size();
    pending_.erase(pending_.begin());
  }
  const auto it = pending_.find(k);
  if (it == pending_.end()) return;
  const double n_avg = run_.config.n_avg;
  for (const auto& [j, code] : it->second) {
    rig_conversion c;
    c.time_s = t0_s + (t1_s - t0_s) * (j + 1) / n_avg;
    c.angle_deg = r.angle_deg;
    c.code = code;
    c.rate_dps = code * lsb_v_ / run_.units.scale_factor_v_per_dps;
    run_.conversions.push_back(c);
  }
  pending_.erase(it);
}

void rig_run_builder::add_raw(const protocol::raw_msg& m) {
  if (!with_conversions_ || run_.config.n_avg == 0) return;
  for (std::uint8_t i = 0; i < m.count; ++i) {
    const std::uint64_t index = std::uint64_t{m.first_index} + i;
    pending_[index / run_.config.n_avg].emplace_back(
        static_cast<std::uint32_t>(index % run_.config.n_avg), m.code(i));
  }
}

status rig_run_builder::add(const gfr::record& r, std::size_t n) {
  const auto bad = [&](const char* what) {
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
      if (!decode(r.body, run_.info)) return bad("INFO body does not decode");
      if (run_.info.tick_hz == 0) return bad("INFO gives a tick rate of 0");
      have_info_ = true;
      lsb_v_ = adc_lsb_v(run_.info.range);
      run_.config = run_.info.config;
      return ok();
    case gfr::kind::configure:
      if (!decode(r.body, run_.config)) return bad("CONFIGURE body does not decode");
      return ok();
    case gfr::kind::start:
      if (in_segment_ || !run_.dwells.empty()) new_segment();
      in_segment_ = true;
      return ok();
    case gfr::kind::frame: {
      if (r.body.size() < 3) return bad("frame record shorter than its header");
      if (!have_info_) return bad("a device frame before the device's INFO");
      ++run_.frames;
      // u8 type, u16 seq (little-endian), payload: the frame as the decoder gave it.
      const auto seq = static_cast<std::uint16_t>(r.body[1] | (r.body[2] << 8));
      const protocol::frame fr{r.body[0], seq, r.body.data() + 3, r.body.size() - 3};
      if (fr.type == static_cast<std::uint8_t>(protocol::msg::dwell)) {
        protocol::dwell_msg d;
        if (!fr.as(d)) return bad("DWELL body does not decode");
        add_dwell(d, fr.seq, r.host_time_us);
      } else if (fr.type == static_cast<std::uint8_t>(protocol::msg::raw)) {
        protocol::raw_msg m;
        if (!fr.as(m) || m.count > protocol::raw_msg::max_codes)
          return bad("RAW body does not decode");
        add_raw(m);
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
          return ok();
        case gfr::gap_reason::link_lost:
          ++run_.link_losses;
          return ok();
      }
      return bad("gap record of an unknown reason");
    }
    case gfr::kind::stop:
      if (r.body.size() != 1 || r.body[0] < 1 || r.body[0] > 3)
        return bad("STOP record of an unknown reason");
      run_.stop = static_cast<gfr::stop_reason>(r.body[0]);
      return ok();
  }
  return bad("unknown record kind");
}

rig_run rig_run_builder::finish() && {
  flush_pending();
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
  run.warnings.insert(run.warnings.begin(), f.warnings.begin(), f.warnings.end());
  return run;
}

result<rig_run> read_rig_run(const std::string& path, bool with_conversions) {
  auto f = gfr::read(path);
  if (!f) return f.err();
  return interpret(*f, path, with_conversions);
}

std::optional<method::row> dwell_row(const rig_dwell& d) {
  if (d.d.n == 0 || (d.d.flags & protocol::dwell_step_fault) != 0) return std::nullopt;
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

}  // namespace gyroflip::host
