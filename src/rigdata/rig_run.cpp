/// \file
/// \brief A `.gfr` recording as a rig run (rig_run.hpp).
#include "gyroflip/rigdata/rig_run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
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

rig_mount_record mount_of_meta(const std::string& meta) {
  rig_mount_record m;
  const auto j = nlohmann::json::parse(meta, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return m;
  if (const auto it = j.find("table_axis"); it != j.end() && it->is_string())
    m.table_axis = it->get<std::string>();
  if (const auto it = j.find("azimuth_deg"); it != j.end() && it->is_number()) {
    const double a = it->get<double>();
    if (std::isfinite(a) && std::fabs(a) <= 360.0) m.azimuth_deg = a;
  }
  return m;
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
  // The sensor model (record since issue 31): finite numbers only; anything else is not a model
  // and is left out whole (the run then names its sensor only, as older files do).
  if (const auto it = j.find("sensor_params"); it != j.end() && it->is_object()) {
    for (const auto& [key, value] : it->items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>())) {
        u.sensor_params.clear();
        break;
      }
      u.sensor_params.emplace_back(key, value.get<double>());
    }
  }
  if (auto s = check_units(u, path + ": record 1: META"); !s) return s.err();
  return u;
}

rig_run_builder::rig_run_builder(std::string path, bool with_conversions)
    : with_conversions_(with_conversions) {
  run_.path = std::move(path);
}

rig_dwell rig_run_builder::physical(const protocol::dwell_msg& d, const protocol::configure_msg& c,
                                    double lsb_v, double t0_s, double t1_s) const {
  rig_dwell r;
  r.d = d;
  r.time_s = 0.5 * (t0_s + t1_s);
  r.angle_deg = d.position < c.n_positions && d.position < protocol::max_positions
                    ? c.pos_cdeg[d.position] / 100.0
                    : method::no_value;  // not in the angle table: never guessed
  r.rate_dps =
      d.n == 0 ? method::no_value
               : static_cast<double>(d.code_sum) / d.n * lsb_v / run_.units.scale_factor_v_per_dps;
  if (d.n_temp != 0)
    r.temp_c = static_cast<double>(d.temp_sum) / d.n_temp * lsb_v / run_.units.temp_v_per_c +
               run_.units.temp_at_0v_c;
  r.accel_x_g = accel_g(d.ax_high_ticks, d.ax_period_ticks);
  r.accel_y_g = accel_g(d.ay_high_ticks, d.ay_period_ticks);
  return r;
}

void rig_run_builder::add_damage(const gfr::damaged_region& d) {
  event e;
  e.type = ev::damage;
  e.record = d.before;
  events_.push_back(e);
  if (!d.again) ++run_.damaged_regions;
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
    run_.mount = mount_of_meta(run_.meta_json);
    return ok();
  }
  const auto push = [&](ev t, std::size_t index, std::optional<std::uint16_t> seq = {}) {
    event e;
    e.type = t;
    e.record = n;
    e.host_us = r.host_time_us;
    e.seq16 = seq.value_or(0);
    e.has_seq = seq.has_value();
    e.index = static_cast<std::uint32_t>(index);
    events_.push_back(e);
  };
  switch (r.type) {
    case gfr::kind::meta:
      return bad("a second META record");
    case gfr::kind::copy:
      return ok();  // gfr::parse has put back what it copies
    case gfr::kind::info: {
      protocol::info_msg m;
      if (!decode_info(r.body, m)) return bad("INFO body does not decode");
      if (m.tick_hz == 0) return bad("INFO gives a tick rate of 0");
      if (infos_.empty() || m.serial == infos_.front().serial) {
        have_info_ = true;
        run_.info = m;
        lsb_v_ = adc_lsb_v(m.range);
        run_.config = m.config;
      }
      infos_.push_back(m);
      push(ev::info, infos_.size() - 1);
      config_event_ = events_.size() - 1;
      return ok();
    }
    case gfr::kind::configure: {
      protocol::configure_msg c;
      if (!decode(r.body, c)) return bad("CONFIGURE body does not decode");
      if (c.n_positions < 2 || c.n_positions > protocol::max_positions)
        return bad(fmt::format("CONFIGURE with {} positions", c.n_positions));
      run_.config = c;
      configs_.push_back(c);
      push(ev::configure, configs_.size() - 1);
      config_event_ = events_.size() - 1;
      return ok();
    }
    case gfr::kind::start: {
      if (r.body.size() != 0 && r.body.size() != 2 && r.body.size() != 4)
        return bad("START record of the wrong size");
      start_seen m;
      m.config_event = config_event_;
      // Format 3: the CRC of the configuration the device started with.
      if (r.body.size() == 4) m.crc = static_cast<std::uint16_t>(r.body[2] | (r.body[3] << 8));
      starts_.push_back(m);
      std::optional<std::uint16_t> ack;
      if (r.body.size() >= 2) ack = static_cast<std::uint16_t>(r.body[0] | (r.body[1] << 8));
      push(ev::start, starts_.size() - 1, ack);
      return ok();
    }
    case gfr::kind::frame: {
      if (r.body.size() < 3) return bad("frame record shorter than its header");
      ++run_.frames;
      // u8 type, u16 seq (little-endian), payload: the frame as the decoder gave it.
      const auto seq = static_cast<std::uint16_t>(r.body[1] | (r.body[2] << 8));
      const protocol::frame fr{r.body[0], seq, r.body.data() + 3, r.body.size() - 3};
      const auto type = static_cast<protocol::msg>(fr.type);
      if (type == protocol::msg::dwell) {
        protocol::dwell_msg d;
        if (!fr.as(d)) return bad("DWELL body does not decode");
        dwell_msgs_.push_back(d);
        push(ev::dwell, dwell_msgs_.size() - 1, seq);
        if (!have_info_) return ok();  // no clock yet: not in the live view
        // The live view: arrival order, ticks continued from the last dwell.
        if (!live_started_) live_last_ = d.t_start_ticks;
        live_started_ = true;
        live_s_ += static_cast<std::int32_t>(d.t_end_ticks - live_last_) /
                   static_cast<double>(run_.info.tick_hz);
        live_last_ = d.t_end_ticks;
        run_.dwells.push_back(physical(d, run_.config, lsb_v_, live_s_, live_s_));
        run_.dwells.back().seq = seq;
        run_.dwells.back().record = n;
      } else if (type == protocol::msg::raw) {
        protocol::raw_msg m;
        if (!fr.as(m) || m.count > protocol::raw_msg::max_codes)
          return bad("RAW body does not decode");
        if (with_conversions_) raws_.push_back(m);
        push(with_conversions_ ? ev::raw : ev::other, raws_.size() - 1, seq);
      } else if (protocol::status_msg m; type == protocol::msg::status && fr.as(m)) {
        statuses_.push_back({m.boot_count, m.uptime_ticks});
        push(ev::status, statuses_.size() - 1, seq);
      } else if (protocol::ack_msg a;
                 type == protocol::msg::ack && fr.as(a) &&
                 a.of_type == static_cast<std::uint8_t>(protocol::msg::start)) {
        ack_at_.push_back(a.at_seq);
        push(ev::ack_start, ack_at_.size() - 1, seq);
      } else if (protocol::ack_msg c;
                 type == protocol::msg::ack && fr.as(c) &&
                 c.of_type == static_cast<std::uint8_t>(protocol::msg::configure)) {
        push(ev::ack_configure, 0, seq);
      } else {
        push(ev::other, 0, seq);
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
          ++run_.device_resets;  // the rebooted device numbers its frames from 0 again
          push(ev::gap_reset, 0);
          return ok();
        case gfr::gap_reason::link_lost:
          ++run_.link_losses;
          push(ev::gap_link, count);
          return ok();
      }
      return bad("gap record of an unknown reason");
    }
    case gfr::kind::stop:
      if (r.body.size() != 1 || r.body[0] < 1 ||
          r.body[0] > static_cast<std::uint8_t>(gfr::stop_reason::disk_full))
        return bad("STOP record of an unknown reason");
      run_.stop = static_cast<gfr::stop_reason>(r.body[0]);
      return ok();
  }
  return bad("unknown record kind");
}

namespace {

constexpr std::size_t npos = static_cast<std::size_t>(-1);

// A STATUS uptime that went back (a restarted clock), not a 32-bit wrap: the recorder's test.
bool went_back(std::uint32_t now, std::uint32_t before) {
  return now < before && before - now < 0x80000000U;
}

// Why a frame of the file is not used.
enum class mark : std::uint8_t { none, reconnect, other_board, unknown_boot };

// A device boot as the reader establishes it.
struct boot_session {
  std::size_t info = npos;        // its INFO (index into the INFOs), when the file has it
  std::size_t info_event = npos;  // where that INFO is
  std::optional<std::uint16_t> boot;
  bool unannounced = false;  // began with no reset recorded and no damage to have lost one
  bool saw_setup = false;    // a CONFIGURE or START of it was seen
  std::size_t epoch = 0;     // damaged regions before it began (its reset's, when inferred)
};

// The median of `v` (empty: 0).
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// A device clock placed on the host's: host time = host_at_0_s + device time * host_per_device.
struct clock_line {
  double host_at_0_s = 0.0;
  double host_per_device = std::numeric_limits<double>::quiet_NaN();  // NaN: not measured
};

// The lower envelope of a boot's frames, each a (device time, host arrival) pair in seconds: a
// frame arrives after it is made, never before, so the line below every point that lies
// closest to them all is the device's clock on the host's; a frame held in a transmitter, or
// sent again on RESEND, lies above it and moves nothing. The slope is the linear programme of
// Moon, Skelly and Towsley, "Estimation and removal of clock skew from network delay
// measurements" (IEEE INFOCOM 1999): the edge of the points' lower convex hull over their mean
// device time. Measured only over at least `min_device_s` of the device's clock and
// `min_host_s` of the host's; otherwise `fallback_slope` (NaN: 1) places the line.
clock_line lower_envelope(std::vector<std::pair<double, double>> pts, double fallback_slope,
                          double min_device_s, double min_host_s) {
  clock_line c;
  if (pts.empty()) return c;
  std::sort(pts.begin(), pts.end());
  std::vector<std::pair<double, double>> hull;  // lower hull, device time ascending
  for (const auto& p : pts) {
    if (!hull.empty() && hull.back().first == p.first) continue;  // the earliest arrival only
    while (hull.size() >= 2) {
      const auto& a = hull[hull.size() - 2];
      const auto& b = hull.back();
      // b lies on or above the segment a-p: not on the lower hull.
      if ((b.second - a.second) * (p.first - a.first) >=
          (p.second - a.second) * (b.first - a.first))
        hull.pop_back();
      else
        break;
    }
    hull.push_back(p);
  }
  double mean_d = 0.0;
  for (const auto& p : pts) mean_d += p.first;
  mean_d /= static_cast<double>(pts.size());
  double slope = std::isfinite(fallback_slope) ? fallback_slope : 1.0;
  const double span_d = hull.back().first - hull.front().first;
  double lo_h = pts.front().second, hi_h = lo_h;
  for (const auto& p : pts) {
    lo_h = std::min(lo_h, p.second);
    hi_h = std::max(hi_h, p.second);
  }
  if (hull.size() >= 2 && span_d >= min_device_s && hi_h - lo_h >= min_host_s) {
    std::size_t k = 1;
    while (k + 1 < hull.size() && hull[k].first < mean_d) ++k;
    const double s = (hull[k].second - hull[k - 1].second) / (hull[k].first - hull[k - 1].first);
    if (s > 0.0) {
      slope = s;
      c.host_per_device = s;
    }
  }
  c.host_at_0_s = std::numeric_limits<double>::infinity();
  for (const auto& p : pts) c.host_at_0_s = std::min(c.host_at_0_s, p.second - slope * p.first);
  return c;
}

}  // namespace

result<rig_run> rig_run_builder::finish() && {
  const std::size_t n_ev = events_.size();
  std::vector<mark> marks(n_ev, mark::none);
  std::vector<std::size_t> session_of(n_ev, 0);
  std::vector<std::size_t> epoch_of(n_ev, 0);
  const auto is_frame = [](ev t) {
    return t == ev::dwell || t == ev::raw || t == ev::status || t == ev::ack_start ||
           t == ev::ack_configure || t == ev::other;
  };

  // 1. A reconnected line: frames stored after the port was lost (the link GAP's time less its
  // milliseconds) and before that GAP, written once the recorder knew the device again, arrived
  // before it was identified: which board sent them is not known.
  for (std::size_t g = 0; g < n_ev; ++g) {
    if (events_[g].type != ev::gap_link) continue;
    const std::uint64_t ms = events_[g].index;
    const std::uint64_t lost_at = events_[g].host_us - std::min(events_[g].host_us, ms * 1000);
    for (std::size_t i = g; i-- > 0;) {
      if (events_[i].type == ev::damage) continue;
      if (events_[i].host_us < lost_at || events_[i].type == ev::gap_link) break;
      if (is_frame(events_[i].type)) marks[i] = mark::reconnect;
    }
  }
  // 2. Another board: everything after an INFO of another serial than the file's first INFO,
  // until an INFO of that board again.
  if (!infos_.empty()) {
    const std::uint32_t serial = infos_.front().serial;
    bool other = false;
    for (std::size_t i = 0; i < n_ev; ++i) {
      if (events_[i].type == ev::info) other = infos_[events_[i].index].serial != serial;
      if (other && events_[i].type != ev::damage) marks[i] = mark::other_board;
    }
  }

  // 3. Device boots: a reset GAP starts a new one; so does an INFO or STATUS of another boot
  // (or a STATUS whose clock went back) where none was recorded. With damage between the last
  // sign of the old boot and the first of the new one, the reset's GAP was lost there; without,
  // nothing says which device sent what came between, nor that the new boot was set up.
  std::vector<boot_session> sessions(1);
  std::size_t cur = 0, epoch = 0, last_ev = 0;
  // The last STATUS's uptime in this boot (have_uptime: there is one).
  std::uint32_t last_uptime = 0;
  bool have_uptime = false;
  std::vector<std::size_t> inferred_at;  // records where a lost reset was found
  const auto split = [&](std::size_t e, std::optional<std::uint16_t> boot) {
    boot_session s;
    s.boot = boot;
    s.unannounced = epoch_of[last_ev] == epoch;
    s.epoch = epoch_of[last_ev];  // what lies after the region its reset was lost in is damaged
    if (!s.unannounced) inferred_at.push_back(events_[e].record);
    for (std::size_t i = last_ev + 1; i < e; ++i) {
      if (session_of[i] != cur || events_[i].type == ev::damage) continue;
      if (epoch_of[i] == epoch && !s.unannounced) {
        session_of[i] = sessions.size();  // after the last damaged region: the new boot's
      } else if (epoch_of[i] != epoch_of[last_ev] || s.unannounced) {
        if (marks[i] == mark::none) marks[i] = mark::unknown_boot;
      }
    }
    sessions.push_back(s);
    cur = sessions.size() - 1;
    last_ev = e;
  };
  for (std::size_t i = 0; i < n_ev; ++i) {
    const event& e = events_[i];
    if (e.type == ev::damage) ++epoch;
    epoch_of[i] = epoch;
    session_of[i] = cur;
    if (marks[i] == mark::reconnect || marks[i] == mark::other_board) continue;
    switch (e.type) {
      case ev::gap_reset:
        sessions.emplace_back().epoch = epoch;
        cur = sessions.size() - 1;
        session_of[i] = cur;
        last_ev = i;
        have_uptime = false;
        break;
      case ev::info: {
        const auto& m = infos_[e.index];
        boot_session& s = sessions[cur];
        if (s.info == npos && (!s.boot || !s.saw_setup || *s.boot == m.boot_count)) {
          s.info = e.index;
          s.info_event = i;
          s.boot = m.boot_count;
          last_ev = i;
          have_uptime = false;  // what came before its INFO may be of a boot before it
        } else if (s.boot && *s.boot == m.boot_count) {
          last_ev = i;  // the same boot again (an INFO after a reconnect)
        } else {
          split(i, m.boot_count);
          session_of[i] = cur;
          sessions[cur].info = e.index;
          sessions[cur].info_event = i;
          have_uptime = false;
        }
        break;
      }
      case ev::configure:
      case ev::start:
        sessions[cur].saw_setup = true;
        break;
      case ev::status: {
        const status_seen& st = statuses_[e.index];
        boot_session& s = sessions[cur];
        if (!s.boot && !s.saw_setup) {  // before the boot is identified: its INFO decides
          last_uptime = st.uptime_ticks;
          have_uptime = true;
          break;
        }
        if (!s.boot) s.boot = st.boot;  // its INFO is lost: its own STATUS says which boot
        if (st.boot != *s.boot || (have_uptime && went_back(st.uptime_ticks, last_uptime))) {
          split(i, st.boot);
          session_of[i] = cur;
        } else {
          last_ev = i;
        }
        last_uptime = st.uptime_ticks;
        have_uptime = true;
        break;
      }
      default:
        break;
    }
  }
  run_.inferred_resets = inferred_at.size();

  // 4. Sequence numbers, unwrapped per boot in file order (a frame sent again arrives within
  // 32 768 numbers of the newest one); a START's ACK number with them.
  std::vector<std::uint64_t> seq_of(n_ev, 0);
  {
    std::vector<std::optional<std::uint64_t>> highest(sessions.size());
    for (std::size_t i = 0; i < n_ev; ++i) {
      const event& e = events_[i];
      if (!e.has_seq || marks[i] == mark::reconnect || marks[i] == mark::other_board) continue;
      auto& h = highest[session_of[i]];
      if (!h) {
        h = (std::uint64_t{1} << 32) + e.seq16;
        seq_of[i] = *h;
        continue;
      }
      const auto d = static_cast<std::int16_t>(static_cast<std::uint16_t>(e.seq16 - *h));
      seq_of[i] = static_cast<std::uint64_t>(static_cast<std::int64_t>(*h) + d);
      h = std::max(*h, seq_of[i]);
    }
  }

  // 5. The runs: each START record, and a START lost in damage rebuilt from the ACK the device
  // sent for it (stored as a frame).
  struct run_mark {
    std::size_t session = 0;
    std::size_t event = 0;  // where it stands (for files of format 1: its frames follow it)
    std::optional<std::uint64_t> after_seq;
    std::optional<protocol::configure_msg> config;  // empty: not known
    bool usable = true;
    // The positions per cycle its dwells are numbered by (the configuration in force, when its
    // own is not known): for its time only, which a run not labelled still gives the file.
    std::uint8_t positions = 2;
    bool timing_only = false;  // dwells of a boot whose START and its ACK are lost
  };
  const auto config_at = [&](std::size_t event_index) -> const protocol::configure_msg& {
    const event& c = events_[event_index];
    return c.type == ev::info ? infos_[c.index].config : configs_[c.index];
  };
  const auto damage_between = [&](std::size_t a, std::size_t b) {
    return a != npos && epoch_of[a] != epoch_of[b];
  };
  const auto same_table = [](const protocol::configure_msg& x, const protocol::configure_msg& y) {
    if (x.n_positions != y.n_positions) return false;
    for (std::size_t k = 0; k < x.n_positions && k < protocol::max_positions; ++k)
      if (x.pos_cdeg[k] != y.pos_cdeg[k]) return false;
    return true;
  };
  std::vector<run_mark> runs;
  // ACK numbers the START records name, with their boots.
  std::vector<std::pair<std::size_t, std::uint16_t>> start_acks;
  for (std::size_t i = 0; i < n_ev; ++i)
    if (events_[i].type == ev::start && events_[i].has_seq)
      start_acks.emplace_back(session_of[i], events_[i].seq16);
  std::size_t unknown_config_runs = 0;
  for (std::size_t i = 0; i < n_ev; ++i) {
    const event& e = events_[i];
    if (e.type == ev::start && marks[i] == mark::other_board) {
      continue;  // another board's run: its dwells are counted apart
    } else if (e.type == ev::start) {
      run_mark m;
      m.session = session_of[i];
      m.event = i;
      if (e.has_seq) m.after_seq = seq_of[i];
      const start_seen& st = starts_[e.index];
      if (st.config_event != npos) {
        const auto& in_force = config_at(st.config_event);
        if (st.crc ? protocol::configure_crc(in_force) == *st.crc
                   : !damage_between(st.config_event, i))
          m.config = in_force;
      }
      // A damaged CONFIGURE record leaves an older one (or INFO's) in force: its angle table
      // would label the run's dwells wrongly (a swapped 180,0 table turns the sign of dN). The
      // configuration the START names may still be in the file (the same CONFIGURE is sent after
      // every reset): taken when every configuration of the file with its CRC has one angle
      // table - the device's own START check is this CRC.
      if (!m.config && st.crc) {
        std::optional<protocol::configure_msg> found;
        bool agree = true;
        for (std::size_t j = 0; j < n_ev && agree; ++j) {
          if (events_[j].type != ev::configure && events_[j].type != ev::info) continue;
          const auto& c = config_at(j);
          if (protocol::configure_crc(c) != *st.crc) continue;
          if (found && !same_table(*found, c)) agree = false;
          if (!found) found = c;
        }
        if (agree) m.config = found;
      }
      if (!m.config) ++unknown_config_runs;
      if (marks[i] != mark::none) m.usable = false;
      if (m.config) {
        m.positions = m.config->n_positions;
      } else if (st.config_event != npos) {
        m.positions = config_at(st.config_event).n_positions;
      }
      runs.push_back(m);
    } else if (e.type == ev::ack_start && marks[i] == mark::none) {
      // The START record follows its ACK within a few records: lost when damage follows the
      // ACK before the next record of the recorder's own and no START names this ACK.
      const std::uint16_t at = ack_at_[e.index];
      const std::pair<std::size_t, std::uint16_t> named{session_of[i], at};
      if (std::find(start_acks.begin(), start_acks.end(), named) != start_acks.end()) continue;
      std::size_t j = i + 1;
      while (j < n_ev && is_frame(events_[j].type)) ++j;
      if (j >= n_ev || events_[j].type != ev::damage) continue;
      start_acks.push_back(named);
      run_mark m;
      m.session = session_of[i];
      m.event = j;
      m.after_seq =
          seq_of[i] - static_cast<std::uint16_t>(static_cast<std::uint16_t>(e.seq16 - at));
      // Its configuration: the CONFIGURE before the ACK, when no damage lies between them.
      std::size_t c = npos;
      for (std::size_t k = i; k-- > 0 && c == npos;)
        if (events_[k].type == ev::configure || events_[k].type == ev::info) c = k;
      if (c != npos && events_[c].type == ev::configure && !damage_between(c, i) &&
          session_of[c] == m.session)
        m.config = config_at(c);
      if (c != npos) m.positions = config_at(c).n_positions;
      if (!m.config) ++unknown_config_runs;
      runs.push_back(m);
      ++run_.rebuilt_starts;
    }
  }
  std::stable_sort(runs.begin(), runs.end(),
                   [](const run_mark& a, const run_mark& b) { return a.event < b.event; });
  // A boot that began with no reset recorded is set up again only after its INFO: a run it
  // started before (with no identification) is not labelled.
  for (auto& m : runs) {
    const boot_session& s = sessions[m.session];
    if (s.unannounced && (s.info_event == npos || s.info_event > m.event)) m.usable = false;
  }

  // 6. Each dwell's run: the last START of its boot whose acknowledgement it follows.
  const auto run_of = [&](std::size_t i) -> std::optional<std::size_t> {
    for (std::size_t k = runs.size(); k-- > 0;) {
      const run_mark& m = runs[k];
      if (m.session != session_of[i]) continue;
      if (m.after_seq ? seq_of[i] > *m.after_seq : i > m.event) return k;
    }
    return std::nullopt;
  };
  // The INFO that converts a boot's dwells: its own, else (lost in damage) the nearest INFO
  // of the same board - tick rate and ADC range are the firmware's.
  const auto info_for = [&](std::size_t session) -> std::optional<std::size_t> {
    if (sessions[session].info != npos) return sessions[session].info;
    std::optional<std::size_t> best;
    for (std::size_t d = 1; d < sessions.size() && !best; ++d) {
      if (session >= d && sessions[session - d].info != npos) best = sessions[session - d].info;
      if (!best && session + d < sessions.size() && sessions[session + d].info != npos)
        best = sessions[session + d].info;
    }
    if (!best) {
      for (std::size_t k = 0; k < infos_.size() && !best; ++k)
        if (infos_[k].serial == infos_.front().serial) best = k;
    }
    return best;
  };
  // A dwell of no START in the file (one cut off before its record was written): the device
  // starts only with the configuration in force, which only a CONFIGURE it acknowledges changes,
  // and refuses CONFIGURE while it runs (docs/PROTOCOL.md). So a dwell sent after the ACK of a
  // CONFIGURE of its boot, with no other CONFIGURE acknowledged since, is of a run of that
  // configuration. Established only when the CONFIGURE record, the ACK frame before it and the
  // dwell lie in one boot with no damage between them (damage could hide another CONFIGURE or
  // a reset) and the boot was set up by the recorder.
  // The CONFIGURE record nearest before each event with no damage or other boot between, and
  // the ACK frame the recorder wrote it on; the ACKs of CONFIGURE of each boot by number.
  std::vector<std::size_t> cfg_before(n_ev, npos);
  std::map<std::size_t, std::vector<std::uint64_t>> cfg_acks;
  for (std::size_t i = 0, cur_cfg = npos; i < n_ev; ++i) {
    if (i > 0 && (epoch_of[i] != epoch_of[i - 1] || session_of[i] != session_of[i - 1]))
      cur_cfg = npos;
    cfg_before[i] = cur_cfg;
    if (events_[i].type == ev::configure) cur_cfg = marks[i] == mark::none ? i : npos;
    if (events_[i].type == ev::ack_configure && marks[i] == mark::none)
      cfg_acks[session_of[i]].push_back(seq_of[i]);
  }
  for (auto& [s, v] : cfg_acks) std::sort(v.begin(), v.end());
  const auto configured_before = [&](std::size_t i) -> std::optional<std::size_t> {
    const std::size_t c = cfg_before[i];
    if (c == npos) return std::nullopt;
    const std::size_t s = session_of[i];
    const boot_session& b = sessions[s];
    if (b.unannounced && (b.info_event == npos || b.info_event > c)) return std::nullopt;
    // Its ACK: the frame before the record (the recorder writes the record on it).
    std::size_t a = c;
    while (a-- > 0 && events_[a].type != ev::ack_configure)
      if (!is_frame(events_[a].type)) return std::nullopt;
    if (a == npos || session_of[a] != s || epoch_of[a] != epoch_of[i] || marks[a] != mark::none ||
        !(seq_of[a] < seq_of[i]))
      return std::nullopt;
    // No other CONFIGURE acknowledged between that ACK and the dwell, in the device's numbering.
    const auto& acks = cfg_acks[s];
    const auto next = std::upper_bound(acks.begin(), acks.end(), seq_of[a]);
    if (next != acks.end() && *next < seq_of[i]) return std::nullopt;
    return c;
  };
  std::map<std::size_t, std::vector<std::size_t>> by_configure;  // per CONFIGURE event
  std::vector<std::vector<std::size_t>> members(runs.size());
  std::map<std::size_t, std::vector<std::size_t>> orphans;  // per boot
  for (std::size_t i = 0; i < n_ev; ++i) {
    if (events_[i].type != ev::dwell) continue;
    switch (marks[i]) {
      case mark::reconnect:
        ++run_.unidentified;
        continue;
      case mark::other_board:
        ++run_.other_board;
        continue;
      case mark::unknown_boot:
        ++run_.unknown_boot;
        continue;
      case mark::none:
        break;
    }
    const auto k = run_of(i);
    if (!k && sessions[session_of[i]].unannounced) {
      ++run_.unidentified;  // a boot no reset announced, never set up by the recorder
    } else if (!k && epoch_of[i] > sessions[session_of[i]].epoch) {
      ++run_.unknown_config;  // its START (and the ACK of it) lies in a damaged region
      orphans[session_of[i]].push_back(i);
    } else if (!k) {
      if (const auto c = configured_before(i)) {
        by_configure[*c].push_back(i);  // its START record is not in the file
      } else {
        ++run_.outside_runs;
      }
    } else if (!runs[*k].usable) {
      ++run_.unidentified;
    } else {
      members[*k].push_back(i);
    }
  }

  for (auto& [c, v] : by_configure) {
    run_mark m;
    m.session = session_of[c];
    m.event = c;
    m.config = configs_[events_[c].index];
    m.positions = m.config->n_positions;
    run_.by_configure += v.size();
    runs.push_back(m);
    members.push_back(std::move(v));
  }
  if (!by_configure.empty()) {  // runs numbered (segment) in file order
    std::vector<std::size_t> by_event(runs.size());
    for (std::size_t r = 0; r < runs.size(); ++r) by_event[r] = r;
    std::stable_sort(by_event.begin(), by_event.end(),
                     [&](std::size_t a, std::size_t b) { return runs[a].event < runs[b].event; });
    std::vector<run_mark> sorted_runs;
    std::vector<std::vector<std::size_t>> sorted_members;
    for (const std::size_t r : by_event) {
      sorted_runs.push_back(runs[r]);
      sorted_members.push_back(std::move(members[r]));
    }
    runs = std::move(sorted_runs);
    members = std::move(sorted_members);
  }
  // A boot's dwells whose START and its ACK are lost are not labelled, but their clock still
  // times the file: a run of their own, for time only.
  for (auto& [session, v] : orphans) {
    run_mark m;
    m.session = session;
    m.event = v.front();
    m.timing_only = true;
    runs.push_back(m);
    members.push_back(std::move(v));
  }
  std::vector<std::size_t> order(runs.size());
  for (std::size_t r = 0; r < runs.size(); ++r) order[r] = r;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return runs[a].event < runs[b].event; });

  // 7. Each run's dwells in sequence order, timed on the device's clock unwrapped into 64 bits.
  // A run whose dwells are not labelled (its angle table not known) still places the runs after
  // it in time, so that damage does not move them.
  run_.dwells.clear();
  double last_end_s = 0.0;
  // The last timed dwell: its end on its device's clock, its arrival, its boot (session) and the
  // last event of the run that set last_end_s.
  std::uint32_t last_end_ticks = 0;
  std::uint64_t last_host_us = 0;
  std::size_t last_session = npos, last_event = 0;
  bool any = false;
  // A boot's clock on the host's around device tick `ref` (review of issue 32, fifth pass,
  // finding 1): the lower envelope of its frames' arrivals against the device times they were
  // made at (a STATUS's uptime, a DWELL's end), in seconds from `ref` and from `ref_host_us`.
  // One dwell's arrival is not its end: a dwell held in the transmitter or first sent on
  // RESEND arrived seconds after it (a run at --speed 1 placed 3.5 s late). Frames more than
  // 2^30 ticks from `ref` are left out (their 32-bit difference could have wrapped).
  std::map<std::size_t, std::vector<std::size_t>> timed_frames;  // per session: STATUS, DWELL
  for (std::size_t i = 0; i < n_ev; ++i)
    if ((events_[i].type == ev::status || events_[i].type == ev::dwell) && marks[i] == mark::none)
      timed_frames[session_of[i]].push_back(i);
  const auto boot_clock = [&](std::size_t session, std::uint32_t ref, std::uint64_t ref_host_us,
                              double fallback_slope) {
    std::vector<std::pair<double, double>> pts;
    const auto info_index = info_for(session);
    if (!info_index) return clock_line{};
    const double hz = infos_[*info_index].tick_hz;
    for (const std::size_t i : timed_frames[session]) {
      std::uint32_t ticks = 0;
      if (events_[i].type == ev::status)
        ticks = statuses_[events_[i].index].uptime_ticks;
      else if (events_[i].type == ev::dwell)
        ticks = dwell_msgs_[events_[i].index].t_end_ticks;
      else
        continue;
      const auto d = static_cast<std::int32_t>(ticks - ref);
      if (d > (1 << 30) || d < -(1 << 30)) continue;
      pts.emplace_back(
          static_cast<double>(d) / hz,
          (static_cast<double>(events_[i].host_us) - static_cast<double>(ref_host_us)) * 1e-6);
    }
    // The pace is measured over at least 2 s of the device's clock and 50 ms of the host's.
    return lower_envelope(std::move(pts), fallback_slope, 2.0, 0.05);
  };
  std::size_t unknown_positions = 0, went_backwards = 0, borrowed_info = 0;
  for (const std::size_t r : order) {
    auto& v = members[r];
    if (v.empty()) continue;
    std::stable_sort(v.begin(), v.end(),
                     [&](std::size_t a, std::size_t b) { return seq_of[a] < seq_of[b]; });
    // Repeats of a frame (stored twice) are read once.
    v.erase(std::unique(v.begin(), v.end(),
                        [&](std::size_t a, std::size_t b) { return seq_of[a] == seq_of[b]; }),
            v.end());
    const bool label = runs[r].config.has_value();
    if (!label && !runs[r].timing_only) run_.unknown_config += v.size();
    const auto info_index = info_for(runs[r].session);
    if (!info_index) {
      if (label) run_.unconverted += v.size();
      continue;
    }
    if (label && sessions[runs[r].session].info == npos) borrowed_info += v.size();
    const protocol::info_msg& info = infos_[*info_index];
    const double hz = info.tick_hz;
    const double lsb_v = adc_lsb_v(info.range);
    const protocol::configure_msg cfg = runs[r].config.value_or(protocol::configure_msg{});
    const std::uint64_t positions = label ? cfg.n_positions : runs[r].positions;
    const auto msg = [&](std::size_t i) -> const protocol::dwell_msg& {
      return dwell_msgs_[events_[i].index];
    };
    const auto k_of = [&](const protocol::dwell_msg& d) {
      return positions * d.cycle + d.position;
    };
    // Ticks per dwell: the median step between neighbours (a 32-bit step is exact while it is
    // shorter than 2^31 ticks: 18 h at 32 768 Hz, 36 min at 1 MHz).
    std::vector<double> per_dwell;
    for (std::size_t j = 1; j < v.size(); ++j) {
      const auto& a = msg(v[j - 1]);
      const auto& b = msg(v[j]);
      const auto dt = static_cast<std::int32_t>(b.t_start_ticks - a.t_start_ticks);
      if (k_of(b) > k_of(a) && dt > 0)
        per_dwell.push_back(static_cast<double>(dt) / static_cast<double>(k_of(b) - k_of(a)));
    }
    const double ticks_per_dwell = median(std::move(per_dwell));
    std::map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::int32_t>>> pend;
    if (label && with_conversions_ && cfg.n_avg != 0) {
      for (std::size_t i = 0; i < n_ev; ++i) {
        if (events_[i].type != ev::raw || marks[i] != mark::none) continue;
        if (session_of[i] != runs[r].session || run_of(i) != r) continue;
        const protocol::raw_msg& b = raws_[events_[i].index];
        for (std::uint8_t k = 0; k < b.count; ++k) {
          const std::uint64_t index = std::uint64_t{b.first_index} + k;
          pend[index / cfg.n_avg].emplace_back(static_cast<std::uint32_t>(index % cfg.n_avg),
                                               b.code(k));
        }
      }
    }
    // A later run continues after the last one by the host's gap between them.
    // Time 0 is the start of the first run's first dwell (cycle 0, position 0): where that dwell
    // is lost (on the line, or in damage), as many of the run's steps before its first one read,
    // so that a dwell lost does not move every time of the file.
    // (Host times are differences of a steady clock: a later run's first dwell arrives after the
    // last one's, or with it; never a negative gap.)
    const bool placed_by_host = any;
    const double last_end_before_s = last_end_s;
    // The host's gap from the last run's last dwell's end to this run's first dwell's start,
    // each on its boot's clock placed on the host's (boot_clock): never before the run before
    // it ends (a device faster than the host's clock; the warning below says by how much).
    double host_gap_s = 0.0;
    double pace = std::numeric_limits<double>::quiet_NaN();  // device s per host s, last boot's
    if (any) {
      constexpr double nan_slope = std::numeric_limits<double>::quiet_NaN();
      const std::uint64_t host_now = events_[v.front()].host_us;
      const std::uint32_t first_ticks = msg(v.front()).t_start_ticks;
      const clock_line before0 = boot_clock(last_session, last_end_ticks, last_host_us, nan_slope);
      const clock_line now0 = boot_clock(runs[r].session, first_ticks, host_now, nan_slope);
      // A boot whose pace could not be measured keeps the other's (or the host's).
      const clock_line before =
          std::isfinite(before0.host_per_device) || !std::isfinite(now0.host_per_device)
              ? before0
              : boot_clock(last_session, last_end_ticks, last_host_us, now0.host_per_device);
      const clock_line now =
          std::isfinite(now0.host_per_device) || !std::isfinite(before0.host_per_device)
              ? now0
              : boot_clock(runs[r].session, first_ticks, host_now, before0.host_per_device);
      host_gap_s = (static_cast<double>(host_now) - static_cast<double>(last_host_us)) * 1e-6 +
                   now.host_at_0_s - before.host_at_0_s;
      if (!std::isfinite(host_gap_s)) host_gap_s = 0.0;
      const double slope =
          std::isfinite(before.host_per_device) ? before.host_per_device : now.host_per_device;
      if (std::isfinite(slope)) pace = 1.0 / slope;
    }
    // A run of another boot than the run before it: its own clock says how long it ran before
    // its first dwell, from its first STATUS stored after that run (a STATUS goes out once, as
    // it is made, and this boot began after the last one ended) to the dwell's start. The run
    // is never placed closer than that: the host's gap says less where the device ran faster
    // than the host's clock, as an emulator at --speed max does while it waits for the host
    // to start it again (issue 32: a run placed 11.9 s early, the warning said up to 1.9 s).
    double boot_lead_s = 0.0;
    if (any && runs[r].session != last_session) {
      const std::size_t first_event = *std::min_element(v.begin(), v.end());
      for (std::size_t i = last_event + 1; i < first_event; ++i) {
        if (events_[i].type != ev::status || session_of[i] != runs[r].session ||
            marks[i] != mark::none)
          continue;
        const auto lead = static_cast<std::int32_t>(msg(v.front()).t_start_ticks -
                                                    statuses_[events_[i].index].uptime_ticks);
        boot_lead_s = std::max(0.0, static_cast<double>(lead) / hz);
        break;
      }
    }
    const double offset_s = any ? last_end_s + std::max(boot_lead_s, std::max(0.0, host_gap_s))
                                : ticks_per_dwell * static_cast<double>(k_of(msg(v.front()))) / hz;
    std::int64_t start_ticks = 0;  // from the run's first dwell
    std::uint32_t prev_raw = msg(v.front()).t_start_ticks;
    std::uint64_t prev_k = k_of(msg(v.front()));
    std::uint64_t expected_k = 0, seen = 0;
    bool timed = false;  // a dwell of this run set the time the next run continues from
    constexpr double wrap = 4294967296.0;
    for (std::size_t j = 0; j < v.size(); ++j) {
      const std::size_t i = v[j];
      const protocol::dwell_msg& d = msg(i);
      // The step from the dwell before: its 32-bit difference plus the whole wraps of the
      // counter that make it closest to the dwells between them at the run's pace.
      const std::uint32_t step32 = d.t_start_ticks - prev_raw;
      const double expect =
          ticks_per_dwell * (static_cast<double>(k_of(d)) - static_cast<double>(prev_k));
      const double wraps = std::round((expect - static_cast<double>(step32)) / wrap);
      const std::int64_t step = static_cast<std::int64_t>(step32) +
                                static_cast<std::int64_t>(wraps) * (std::int64_t{1} << 32);
      const auto length = static_cast<std::int32_t>(d.t_end_ticks - d.t_start_ticks);
      if (j != 0 && (step < 0 || length < 0)) {
        if (!label) break;  // counted already; its clock times nothing after this
        // Times that go back: not this run's clock (a reset no record says, or damage). What
        // follows is not placed on it.
        went_backwards += v.size() - j;
        run_.unknown_boot += v.size() - j;
        run_.warnings.push_back(fmt::format(
            "{}: record {}: DWELL of cycle {} position {} starts at device tick {}, before the "
            "dwell before it: its times go backwards; it and the {} dwells after it in its run "
            "are not used",
            run_.path, events_[i].record, d.cycle, d.position, d.t_start_ticks, v.size() - j - 1));
        break;
      }
      if (j == 0 && length < 0) {
        if (label) {
          ++went_backwards;
          ++run_.unknown_boot;
        }
        continue;
      }
      start_ticks += j == 0 ? 0 : step;
      prev_raw = d.t_start_ticks;
      prev_k = k_of(d);
      const double t0 = offset_s + static_cast<double>(start_ticks) / hz;
      const double t1 = offset_s + static_cast<double>(start_ticks + length) / hz;
      if (!label) {
        last_end_s = t1;
        last_end_ticks = d.t_end_ticks;
        last_host_us = events_[i].host_us;
        last_session = runs[r].session;
        last_event = std::max(last_event, i);
        timed = true;
        continue;
      }
      rig_dwell rd = physical(d, cfg, lsb_v, t0, t1);
      rd.seq = events_[i].seq16;
      rd.segment = static_cast<std::uint32_t>(r);
      rd.record = events_[i].record;
      rd.index = k_of(d);
      if (std::isfinite(rd.temp_c) &&
          !within(rd.temp_c, io::recording_reader::min_temp_c, io::recording_reader::max_temp_c))
        return input_error(
            {run_.path}, fmt::format("record {}: a dwell's temperature is {:.6g} degC, outside "
                                     "what a recording may hold ({} to {} degC): the "
                                     "temperature conversion (META) or the file is wrong",
                                     events_[i].record, rd.temp_c, io::recording_reader::min_temp_c,
                                     io::recording_reader::max_temp_c));
      if (!std::isfinite(rd.angle_deg)) {
        ++unknown_positions;  // not in the angle table: never guessed
        continue;
      }
      // The RAW codes of dwell k = n_positions cycle + position are the run's gyro
      // conversions k n_avg .. (k+1) n_avg - 1 (a RDY timeout uses an index too:
      // docs/PROTOCOL.md, RAW); each is placed at the end of its conversion period.
      if (const auto it = pend.find(k_of(d)); it != pend.end()) {
        for (const auto& [index, code] : it->second) {
          rig_conversion c;
          c.time_s = t0 + (t1 - t0) * (index + 1) / cfg.n_avg;
          c.angle_deg = rd.angle_deg;
          c.code = code;
          c.rate_dps = code * lsb_v / run_.units.scale_factor_v_per_dps;
          run_.conversions.push_back(c);
        }
        pend.erase(it);
      }
      expected_k = std::max(expected_k, k_of(d) + 1);
      ++seen;
      last_end_s = t1;
      last_end_ticks = d.t_end_ticks;
      last_host_us = events_[i].host_us;
      last_session = runs[r].session;
      last_event = std::max(last_event, i);
      timed = true;
      run_.dwells.push_back(rd);
    }
    run_.lost_dwells += expected_k - std::min(expected_k, seen);
    for (const auto& [k, codes] : pend) run_.unplaced_conversions += codes.size();
    if (placed_by_host && timed) {
      // The device time between the runs is the host's gap times the pace, where the device ran
      // on at its pace: a device faster than the host's clock (an emulator run fast; damage or
      // lost dwells at the end of a run do not change it) leaves this run and every later one
      // early by the difference. At a rig's pace (1, to its crystal) it is nothing.
      const double p = pace;
      // (Never less than the boot's own lead before its first dwell: the device ran that long.)
      const double paced_s = std::max(boot_lead_s, host_gap_s * p);
      const double shift_s = std::isfinite(p) ? paced_s - (offset_s - last_end_before_s) : 0.0;
      // Said whenever the device's clock kept another pace than the host's (beyond 1 %: an
      // emulator, not a crystal), however small the estimate: an emulator's pace between runs
      // is not the one measured within them (at --speed max it runs flat out while its device
      // waits for the host; issue 32: a run 1.03 s early after a reset, its boot's own lead
      // counted, with an estimate of 0), so the estimate is no bound. Also beyond 1 s at any pace.
      if (std::isfinite(p) && (std::fabs(p - 1.0) > 0.01 || std::fabs(shift_s) > 1.0)) {
        run_.later_runs_shift_s = std::max(run_.later_runs_shift_s, std::fabs(shift_s));
        run_.later_runs_off_pace = true;
        run_.warnings.push_back(fmt::format(
            "{}: record {}: run {} (export's segment {}) is placed after the run before it by "
            "the host's clock ({:.3g} s between their dwells), but the device's clock ran {:.3g} "
            "times as fast as the host's ({}): the "
            "device time between them is not known, and the time_s of this run and every later "
            "one may be {} by about {:.3g} s at the last run's pace (an emulator's pace varies: "
            "not a bound; times within a run are the device's own)",
            run_.path, events_[v.front()].record, r, r, host_gap_s, p,
            p > 1.0 ? "an emulator running faster than real time"
                    : "a device clock slower than the host's: an emulator the host could not run "
                      "at its speed, or a clock off its rate",
            shift_s >= 0 ? "early" : "late", std::fabs(shift_s)));
      }
    }
    any = any || timed;
  }
  // The last INFO of the file's board, and the configuration in force at the end.
  for (const auto& m : infos_)
    if (m.serial == infos_.front().serial) run_.info = m;

  // What could not be established, one warning per reason.
  const auto say = [&](std::size_t n, const std::string& what) {
    if (n != 0) run_.warnings.push_back(fmt::format("{}: {} {}", run_.path, n, what));
  };
  say(unknown_positions,
      "dwells name a position outside their configuration's angle table: not used");
  say(run_.unknown_config,
      "dwells belong to a run whose configuration (its angle table) is not in the file (the "
      "CONFIGURE record before its START, or the START, is damaged or missing): not used");
  say(run_.unidentified,
      "dwells came from a device that was not identified (stored after the port was lost and "
      "before the recorder knew the device again, or after a STATUS of another device boot with "
      "no reset recorded: another board, or a reset the recorder missed): not used");
  if (run_.other_board != 0 && !infos_.empty()) {
    std::uint32_t other = 0;
    for (const auto& m : infos_)
      if (m.serial != infos_.front().serial) other = m.serial;
    say(run_.other_board,
        fmt::format("dwells came from another board (serial {}; this file's board is {}): not "
                    "used",
                    other, infos_.front().serial));
  }
  say(run_.unknown_boot - went_backwards,
      "dwells lie between damaged regions of the file, one of which held a device reset: which "
      "boot sent them cannot be established: not used");
  say(run_.unconverted,
      "dwells have no intact INFO of their board in the file (its tick rate and ADC range "
      "convert them): not used");
  say(borrowed_info,
      "dwells of a device boot whose INFO record is damaged are converted with the tick rate and "
      "ADC range of another INFO of the same board");
  for (const std::size_t at : inferred_at)
    run_.warnings.push_back(fmt::format(
        "{}: record {}: the device had restarted (another boot count, or its clock back) and the "
        "record of the reset is lost in a damaged region before it: a new device boot begins "
        "there",
        run_.path, at));
  say(run_.by_configure,
      "dwells of a run whose START record is not in the file (the file ends, or is damaged, "
      "before it) are labelled by the CONFIGURE their device boot acknowledged before them (a "
      "device starts only with the configuration in force: docs/PROTOCOL.md)");
  say(run_.rebuilt_starts,
      "START records lost in damaged regions were rebuilt from the ACK the device sent for them");
  say(run_.outside_runs,
      "dwells arrived outside an acknowledged run (a run the device had before the recorder's "
      "START): not used");
  if (!run_.stop)
    run_.warnings.push_back(fmt::format(
        "{}: the recording has no STOP record: the recorder ended without closing it (a kill or "
        "a power loss); everything up to its last record is read",
        run_.path));
  else if (*run_.stop == gfr::stop_reason::disk_full)
    run_.warnings.push_back(fmt::format(
        "{}: the recording ended because the disk was full (or the file reached its size limit): "
        "the recorder stopped the device; what it sent after the last record is not in the file "
        "and is counted lost; everything before it is read",
        run_.path));
  static_cast<void>(unknown_config_runs);
  return std::move(run_);
}

result<rig_run> interpret(const gfr::file& f, const std::string& path, bool with_conversions) {
  rig_run_builder b(path, with_conversions);
  std::size_t d = 0;
  for (std::size_t i = 0; i < f.records.size(); ++i) {
    for (; d < f.damaged.size() && f.damaged[d].before <= i; ++d) b.add_damage(f.damaged[d]);
    if (auto s = b.add(f.records[i], f.records[i].number); !s) return s.err();
  }
  for (; d < f.damaged.size(); ++d) b.add_damage(f.damaged[d]);
  auto run = std::move(b).finish();
  if (!run) return run.err();
  run->repaired_records = f.repaired;
  run->restored_records = f.restored;
  run->warnings.insert(run->warnings.begin(), f.warnings.begin(), f.warnings.end());
  return run;
}

result<rig_run> read_rig_run(const std::string& path, bool with_conversions, bool strict) {
  auto f = gfr::read(path, strict);
  if (!f) return f.err();
  return interpret(*f, path, with_conversions);
}

position_table table_of_configure(const protocol::configure_msg& c) {
  std::vector<double> angles;
  std::vector<std::int32_t> steps;
  for (std::size_t i = 0; i < c.n_positions && i < protocol::max_positions; ++i) {
    angles.push_back(c.pos_cdeg[i] / 100.0);
    steps.push_back(c.pos_steps[i]);
  }
  auto t = position_table::of_visits(angles, steps);
  return t ? std::move(*t) : position_table{};
}

position_table positions_of(const rig_run& run) {
  return table_of_configure(run.config);
}

std::optional<method::row> dwell_row(const rig_dwell& d, const position_table& table) {
  if (d.d.n == 0 || (d.d.flags & protocol::dwell_step_fault) != 0) return std::nullopt;
  const auto position = table.index_of(d.angle_deg);
  if (!position) return std::nullopt;
  return method::row{d.time_s, *position, d.rate_dps, d.temp_c, d.d.n};
}

std::vector<method::row> dwell_rows(const rig_run& run) {
  const position_table table = positions_of(run);
  std::vector<method::row> rows;
  rows.reserve(run.dwells.size());
  for (const auto& d : run.dwells)
    if (auto r = dwell_row(d, table)) rows.push_back(*r);
  return rows;
}

std::vector<io::csv_metadata> sensor_metadata(const device_units& units) {
  std::vector<io::csv_metadata> m;
  if (!units.sensor.empty()) m.push_back({"sensor_name", units.sensor});
  for (const auto& [key, value] : units.sensor_params)
    m.push_back({fmt::format("sensor.{}", key), fmt::format("{}", value)});
  return m;
}

std::vector<io::csv_metadata> csv_metadata(const rig_run& run) {
  const auto& c = run.config;
  std::vector<io::csv_metadata> m = sensor_metadata(run.units);
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
  // Where the rig stood (record --table-axis/--azimuth): only what META holds, never guessed.
  if (!run.mount.table_axis.empty()) m.push_back({"table_axis", run.mount.table_axis});
  if (run.mount.azimuth_deg)
    m.push_back({"azimuth_deg", fmt::format("{}", *run.mount.azimuth_deg)});
  return m;
}

}  // namespace gyroflip::rigdata
