/// \file
/// \brief Synthetic `.gfr` recordings and damage trials (synthetic_gfr.hpp).
#include "support/synthetic_gfr.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <utility>

#include <fmt/format.h>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/messages.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "support/run_cli.hpp"

namespace gyroflip::test {

namespace gfr = rigdata::gfr;
namespace p = protocol;
using bytes = std::vector<std::uint8_t>;

namespace {

void put_le(bytes& b, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// The recorder's side of a synthetic run: what it appends, in its order.
class generator {
 public:
  generator(const synthetic_options& o, const std::string& path) : o_(o), rng_(o.seed) {
    if (o.copies) {
      auto w = gfr::writer::create(path);
      if (w) w_.emplace(std::move(*w));
    } else {
      file_ = encode_file_header(4);
    }
    path_ = path;
  }

  synthetic_recording run() {
    const std::string meta =
        R"({"format":"gyroflip.gfr","sensor":"synthetic","scale_factor_v_per_dps":0.0125,)"
        R"("temp_v_per_c":0.0084,"temp_at_0v_c":24.85})";
    record(gfr::kind::meta, bytes(meta.begin(), meta.end()));
    seq_ = o_.first_seq;
    clock_ = o_.first_tick - static_cast<std::uint32_t>(2 * o_.tick_hz);  // 2 s before dwell 0
    boot_start(false);
    std::size_t k = 0;  // dwells of this boot
    for (std::size_t j = 0; j < o_.dwells; ++j) {
      dwell(k++, j);
      if (std::find(o_.resets_after.begin(), o_.resets_after.end(), j) != o_.resets_after.end()) {
        flush_late();
        record(gfr::kind::gap, gap_body(gfr::gap_reason::device_reset, 0));
        ++boot_;
        ++boot_count_;
        seq_ = 0;
        clock_ = static_cast<std::uint32_t>(o_.tick_hz / 2);  // uptime from its power-on
        tick(o_.restart_s);
        boot_start(true);
        k = 0;
      }
      if (std::find(o_.link_losses_after.begin(), o_.link_losses_after.end(), j) !=
          o_.link_losses_after.end()) {
        flush_late();
        advance(3.0);  // three seconds away; the device's history keeps what it sent
        record(gfr::kind::gap, gap_body(gfr::gap_reason::link_lost, 3000));
      }
    }
    flush_late();
    record(gfr::kind::stop, bytes{static_cast<std::uint8_t>(gfr::stop_reason::duration)});
    if (w_) {
      static_cast<void>(w_->close());
      const std::string t = read_text(path_);
      out_.bytes.assign(t.begin(), t.end());
    } else {
      out_.bytes = file_;
      write_text(path_, std::string(file_.begin(), file_.end()));
    }
    return std::move(out_);
  }

 private:
  static bytes gap_body(gfr::gap_reason r, std::uint32_t count) {
    bytes b{static_cast<std::uint8_t>(r)};
    put_le(b, count, 4);
    return b;
  }

  void record(gfr::kind k, const bytes& body) {
    if (w_) {
      static_cast<void>(w_->append(k, host_us_, body));
    } else {
      // As the recorder's clock does (a write between two records): never two in a microsecond.
      if (any_record_ && host_us_ <= last_us_) host_us_ = last_us_ + 1;
      any_record_ = true;
      last_us_ = host_us_;
      const bytes r = encode_record(k, host_us_, body);
      file_.insert(file_.end(), r.begin(), r.end());
    }
  }

  // A device frame as the recorder stores it: u8 type, u16 seq, payload.
  bytes frame_body(p::msg type, const bytes& pl) {
    bytes b{static_cast<std::uint8_t>(type)};
    put_le(b, seq_++, 2);
    b.insert(b.end(), pl.begin(), pl.end());
    return b;
  }
  void frame(p::msg type, const bytes& pl) { record(gfr::kind::frame, frame_body(type, pl)); }

  void ack(p::msg of) {
    p::ack_msg a;
    a.seq = command_++;
    a.of_type = static_cast<std::uint8_t>(of);
    a.at_seq = seq_;
    frame(p::msg::ack, payload_of(a));
  }

  void status(std::uint8_t state) {
    p::status_msg s;
    s.state = state;
    s.uptime_ticks = clock_;
    s.boot_count = boot_count_;
    frame(p::msg::status, payload_of(s));
    next_status_s_ = device_s_ + o_.status_period_s;
  }

  // Device (and host) time goes on by `s` seconds, with a STATUS each period.
  void advance(double s) {
    const double until = device_s_ + s;
    while (next_status_s_ <= until) {
      const double step = next_status_s_ - device_s_;
      tick(step);
      status(static_cast<std::uint8_t>(p::device_state::running));
    }
    tick(until - device_s_);
  }
  void tick(double s) {
    device_s_ += s;
    const double ticks = s * o_.tick_hz + tick_rest_;
    const double whole = std::floor(ticks);
    tick_rest_ = ticks - whole;
    clock_ += static_cast<std::uint32_t>(static_cast<std::uint64_t>(whole) & 0xFFFFFFFFU);
    host_us_ += static_cast<std::uint64_t>(std::llround(s * 1e6 / o_.device_speed));
  }

  // INFO, STOP, CONFIGURE, START as the recorder does them (after a reset: homing).
  void boot_start(bool after_reset) {
    if (after_reset) status(static_cast<std::uint8_t>(p::device_state::idle));
    p::info_msg info;
    info.protocol = p::protocol_version;
    info.serial = o_.serial;
    info.mclk_hz = 6144000;
    info.tick_hz = o_.tick_hz;
    info.range = 4;
    info.boot_count = boot_count_;
    record(gfr::kind::info, payload_of(info));
    advance(0.05);
    ack(p::msg::stop);
    advance(0.05);
    ack(p::msg::configure);
    p::configure_msg c;
    if (after_reset) c.flags = static_cast<std::uint8_t>(c.flags | p::cfg_home);
    record(gfr::kind::configure, payload_of(c));
    advance(0.05);
    const std::uint16_t at = seq_;
    ack(p::msg::start);
    bytes start;
    put_le(start, at, 2);
    put_le(start, p::configure_crc(c), 2);
    record(gfr::kind::start, start);
    advance(after_reset ? o_.homing_s : 1.85);
    segment_s_ = device_s_;
  }

  void dwell(std::size_t k, std::size_t j) {
    p::dwell_msg d;
    d.cycle = static_cast<std::uint32_t>(k / 2);
    d.position = static_cast<std::uint8_t>(k % 2);
    d.t_start_ticks = clock_;
    const double length_s = 0.6 * o_.dwell_s;
    d.t_end_ticks = clock_ + static_cast<std::uint32_t>(std::llround(length_s * o_.tick_hz));
    d.n = 256;
    std::uniform_int_distribution<std::int64_t> code(-40000, 40000);
    d.code_sum = 256 * code(rng_);
    d.n_temp = 4;
    d.temp_sum = 4 * 4300 + static_cast<std::int32_t>(code(rng_) / 100);
    const double start_s = device_s_ - segment_s_;
    const double through_s = device_s_;
    advance(length_s);  // the device sends a DWELL when it ends
    const std::uint16_t s = seq_;
    const bytes body = frame_body(p::msg::dwell, payload_of(d));
    out_.dwells.push_back(
        {boot_, s, d.cycle, d.position, d.position == 0 ? 0.0 : 180.0, start_s, through_s});
    if (std::find(o_.lost.begin(), o_.lost.end(), j) != o_.lost.end()) {
      out_.dwells.pop_back();
      lost_pending_ = true;
    } else if (held(k, j)) {
      late_.push_back(body);  // no GAP: the recorder sees nothing missing until they come
    } else if (o_.late_every != 0 && j % o_.late_every == o_.late_every - 1) {
      late_.push_back(body);  // it came again after the next one (RESEND)
      record(gfr::kind::gap, gap_body(gfr::gap_reason::corrupt, 1));
    } else {
      record(gfr::kind::frame, body);
      flush_late();
    }
    advance(o_.dwell_s - length_s);
    if (lost_pending_) {
      record(gfr::kind::gap, gap_body(gfr::gap_reason::missing, 1));
      lost_pending_ = false;
    }
  }
  // Dwell k of its boot, j of the recording, held back (held_before_reset, held_after_reset).
  bool held(std::size_t k, std::size_t j) const {
    if (boot_ != 0 && k < o_.held_after_reset) return true;
    for (const std::size_t r : o_.resets_after)
      if (j <= r && r - j < o_.held_before_reset) return true;
    return false;
  }
  void flush_late() {
    for (const auto& b : late_) record(gfr::kind::frame, b);
    late_.clear();
  }

  const synthetic_options& o_;
  std::mt19937_64 rng_;
  std::optional<gfr::writer> w_;
  bytes file_;
  std::string path_;
  synthetic_recording out_;
  std::uint64_t host_us_ = 0;
  std::uint64_t last_us_ = 0;
  bool any_record_ = false;
  std::uint16_t seq_ = 0;
  std::uint16_t command_ = 40000;
  std::uint16_t boot_count_ = 1;
  std::size_t boot_ = 0;
  std::uint32_t clock_ = 0;
  double tick_rest_ = 0.0;
  double device_s_ = 0.0;
  double next_status_s_ = 0.0;
  double segment_s_ = 0.0;
  std::vector<bytes> late_;
  bool lost_pending_ = false;
};

// A reading of a file: its dwells by the FRAME record each came from (the frame's bytes).
struct reading {
  std::optional<rigdata::rig_run> run;
  std::map<std::size_t, const gfr::record*> by_number;
  gfr::file file;
  std::string error;
};

reading read_bytes(const bytes& b) {
  reading r;
  auto f = gfr::parse(b, "trial.gfr");
  if (!f) {
    r.error = f.err().message;
    return r;
  }
  r.file = std::move(*f);
  for (const auto& rec : r.file.records) r.by_number[rec.number] = &rec;
  auto run = rigdata::interpret(r.file, "trial.gfr", false);
  if (!run) {
    r.error = run.err().message;
    return r;
  }
  r.run = std::move(*run);
  return r;
}

std::string key_of(const reading& r, const rigdata::rig_dwell& d) {
  const auto it = r.by_number.find(d.record);
  if (it == r.by_number.end()) return {};
  return std::string(it->second->body.begin(), it->second->body.end());
}

bool same_value(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

// The undamaged reading, and where each of its dwells' frames lies in the file.
struct truth {
  reading clean;
  std::map<std::string, const rigdata::rig_dwell*> dwell_of;
  std::map<std::string, std::vector<std::pair<std::uint64_t, std::uint64_t>>> spans;
};

truth truth_of(const bytes& file) {
  truth t;
  t.clean = read_bytes(file);
  if (!t.clean.run) return t;
  for (const auto& d : t.clean.run->dwells) t.dwell_of[key_of(t.clean, d)] = &d;
  for (const auto& rec : t.clean.file.records)
    if (rec.type == gfr::kind::frame)
      t.spans[std::string(rec.body.begin(), rec.body.end())].emplace_back(
          rec.offset, rec.offset + gfr::record_overhead + rec.body.size());
  return t;
}

// Whether a record spanning [first, second) of the undamaged file is intact in a damaged one.
using intact_test = std::function<bool(std::pair<std::uint64_t, std::uint64_t>)>;

// One trial: `damaged` is `file` changed; a dwell whose record passes `is_intact` is intact.
void trial(const truth& t, const bytes& damaged, const intact_test& is_intact,
           const std::string& what, damage_tally& tally) {
  ++tally.trials;
  const reading r = read_bytes(damaged);
  std::size_t intact = 0, recovered = 0, mislabelled = 0, repeated = 0, beyond = 0;
  std::map<std::string, const rigdata::rig_dwell*> got;
  double first_s = 0.0, last_s = 0.0;
  if (t.clean.run && !t.clean.run->dwells.empty()) {
    first_s = t.clean.run->dwells.front().time_s;
    last_s = t.clean.run->dwells.back().time_s;
  }
  if (r.run) {
    for (const auto& d : r.run->dwells) {
      const auto [it, fresh] = got.emplace(key_of(r, d), &d);
      if (!fresh) ++repeated;
      // (A tick's rounding of a run's first dwell lost: well within a millisecond.)
      if (!(d.time_s >= first_s - 1e-3 && d.time_s <= last_s + 1e-3)) ++beyond;
    }
  }
  for (const auto& [key, d] : t.dwell_of) {
    const auto sp = t.spans.find(key);
    const bool untouched =
        sp != t.spans.end() && std::any_of(sp->second.begin(), sp->second.end(), is_intact);
    if (!untouched) continue;
    ++intact;
    const auto g = got.find(key);
    if (g != got.end() && g->second->angle_deg == d->angle_deg &&
        same_value(g->second->rate_dps, d->rate_dps) && same_value(g->second->temp_c, d->temp_c)) {
      ++recovered;
      if (const double shift = std::fabs(g->second->time_s - d->time_s);
          shift > tally.max_time_shift_s) {
        tally.max_time_shift_s = shift;
        tally.max_time_shift_at = what;
      }
    }
  }
  for (const auto& [key, g] : got) {
    const auto d = t.dwell_of.find(key);
    if (d == t.dwell_of.end() || g->angle_deg != d->second->angle_deg ||
        !same_value(g->rate_dps, d->second->rate_dps) || !same_value(g->temp_c, d->second->temp_c))
      ++mislabelled;
  }
  std::size_t false_lost = 0;
  if (r.run && t.clean.run) {
    const std::size_t touched = t.dwell_of.size() - intact;
    const std::size_t may = t.clean.run->lost_dwells + touched;
    if (r.run->lost_dwells > may) false_lost = r.run->lost_dwells - may;
  }
  if (!r.run) ++tally.unreadable;
  tally.intact += intact;
  tally.recovered += recovered;
  tally.mislabelled += mislabelled;
  tally.repeated += repeated;
  tally.beyond_span += beyond;
  tally.false_lost += false_lost;
  if ((recovered != intact || mislabelled != 0 || repeated != 0 || beyond != 0 ||
       false_lost != 0) &&
      tally.notes.size() < 20)
    tally.notes.push_back(fmt::format(
        "{}: {} of {} intact dwells, {} mislabelled, {} twice, {} beyond the span, {} falsely "
        "lost{}{}",
        what, recovered, intact, mislabelled, repeated, beyond, false_lost,
        r.error.empty() ? "" : ": ", r.error));
}

// One trial: `damaged` is `file` with bytes [lo, hi) changed.
void trial(const truth& t, const bytes& damaged, std::uint64_t lo, std::uint64_t hi,
           const std::string& what, damage_tally& tally) {
  trial(
      t, damaged, [&](auto s) { return s.second <= lo || s.first >= hi; }, what, tally);
}

}  // namespace

bytes encode_record(gfr::kind k, std::uint64_t host_us, const bytes& body) {
  bytes b;
  const auto len = static_cast<std::uint32_t>(body.size() + 9);
  put_le(b, len, 4);
  put_le(b, len ^ 0xFFFFFFFFU, 4);
  b.push_back(static_cast<std::uint8_t>(k));
  put_le(b, host_us, 8);
  b.insert(b.end(), body.begin(), body.end());
  put_le(b, gfr::crc32(b), 4);
  return b;
}

bytes encode_file_header(std::uint16_t version) {
  bytes h(gfr::magic.begin(), gfr::magic.end());
  put_le(h, version, 2);
  put_le(h, 0, 2);
  put_le(h, gfr::crc32(h), 4);
  return h;
}

synthetic_recording make_synthetic_recording(const synthetic_options& o, const std::string& path) {
  return generator(o, path).run();
}

void flip_trials(const bytes& file, std::size_t flips, std::uint64_t seed, damage_tally& t) {
  const truth tr = truth_of(file);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::uint64_t> bit(0, file.size() * 8 - 1);
  for (std::size_t n = 0; n < flips; ++n) {
    const std::uint64_t b = bit(rng);
    bytes d = file;
    d[b / 8] = static_cast<std::uint8_t>(d[b / 8] ^ (1U << (b % 8)));
    trial(tr, d, b / 8, b / 8 + 1, fmt::format("bit {} (offset {})", b, b / 8), t);
  }
}

void zero_trials(const bytes& file, std::size_t regions, std::size_t max_bytes, std::uint64_t seed,
                 damage_tally& t) {
  const truth tr = truth_of(file);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> length(1, std::min(max_bytes, file.size()));
  for (std::size_t n = 0; n < regions; ++n) {
    const std::size_t len = length(rng);
    std::uniform_int_distribution<std::size_t> at(0, file.size() - len);
    const std::size_t lo = at(rng);
    bytes d = file;
    std::fill(d.begin() + static_cast<std::ptrdiff_t>(lo),
              d.begin() + static_cast<std::ptrdiff_t>(lo + len), std::uint8_t{0});
    trial(tr, d, lo, lo + len, fmt::format("zeros at {}..{}", lo, lo + len - 1), t);
  }
}

void repeat_trials(const bytes& file, std::size_t trials, std::size_t max_bytes, std::uint64_t seed,
                   damage_tally& t) {
  const truth tr = truth_of(file);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> length(1, max_bytes);
  std::uniform_int_distribution<std::size_t> at(gfr::file_header_bytes, file.size() - 2);
  for (std::size_t n = 0; n < trials; ++n) {
    const std::size_t lo = at(rng);
    const std::size_t len = std::min(length(rng), file.size() - lo);
    bytes d(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(lo + len));
    d.insert(d.end(), file.begin() + static_cast<std::ptrdiff_t>(lo),
             file.begin() + static_cast<std::ptrdiff_t>(lo + len));
    d.insert(d.end(), file.begin() + static_cast<std::ptrdiff_t>(lo + len), file.end());
    // A record that holds the whole block, and more on both sides, is cut by the repeat.
    trial(
        tr, d, [&](auto s) { return !(s.first < lo && s.second > lo + len); },
        fmt::format("{} bytes at {} twice", len, lo), t);
  }
}

void swap_trials(const bytes& file, std::size_t trials, std::size_t max_bytes, std::uint64_t seed,
                 damage_tally& t) {
  const truth tr = truth_of(file);
  std::mt19937_64 rng(seed);
  const std::size_t top = std::min(max_bytes, (file.size() - gfr::file_header_bytes) / 2);
  std::uniform_int_distribution<std::size_t> length(std::min<std::size_t>(512, top), top);
  for (std::size_t n = 0; n < trials; ++n) {
    const std::size_t len = length(rng);
    const std::size_t a = std::uniform_int_distribution<std::size_t>(gfr::file_header_bytes,
                                                                     file.size() - 2 * len)(rng);
    const std::size_t b =
        std::uniform_int_distribution<std::size_t>(a + len, file.size() - len)(rng);
    bytes d = file;
    std::copy_n(file.begin() + static_cast<std::ptrdiff_t>(b), len,
                d.begin() + static_cast<std::ptrdiff_t>(a));
    std::copy_n(file.begin() + static_cast<std::ptrdiff_t>(a), len,
                d.begin() + static_cast<std::ptrdiff_t>(b));
    const std::array<std::uint64_t, 4> cuts{a, a + len, b, b + len};
    trial(
        tr, d,
        [&](auto s) {
          return std::none_of(cuts.begin(), cuts.end(),
                              [&](std::uint64_t c) { return s.first < c && c < s.second; });
        },
        fmt::format("{} bytes at {} and {} swapped", len, a, b), t);
  }
}

namespace {

// Where each record of an undamaged recording starts (and the file's end).
std::vector<std::size_t> record_starts(const bytes& file) {
  std::vector<std::size_t> at;
  if (auto f = gfr::parse(file, "x.gfr"); f)
    for (const auto& r : f->records)
      if (!r.restored) at.push_back(r.offset);
  std::sort(at.begin(), at.end());
  at.push_back(file.size());
  return at;
}

}  // namespace

void splice_trials(const bytes& file, const bytes& other, std::size_t trials, std::size_t max_bytes,
                   std::uint64_t seed, bool overwrite, damage_tally& t) {
  const truth tr = truth_of(file);
  const auto file_starts = record_starts(file);
  const auto other_starts = record_starts(other);
  std::mt19937_64 rng(seed);
  const auto pick = [&](std::size_t lo, std::size_t hi) {
    return std::uniform_int_distribution<std::size_t>(lo, std::max(lo, hi))(rng);
  };
  // A record boundary at or after `at` (the end when none).
  const auto boundary = [](const std::vector<std::size_t>& starts, std::size_t at) {
    return *std::lower_bound(starts.begin(), starts.end() - 1, at);
  };
  const std::size_t head = gfr::file_header_bytes;
  for (std::size_t n = 0; n < trials; ++n) {
    const bool aligned = n % 2 == 0;
    std::size_t from = pick(head, other.size() - 2);
    std::size_t len = pick(1, std::min(max_bytes, other.size() - from));
    std::size_t at = pick(head, file.size() - 1);
    if (aligned) {
      from = boundary(other_starts, from);
      len = boundary(other_starts, std::min(other.size(), from + len)) - from;
      at = boundary(file_starts, at);
    }
    if (len == 0 || from >= other.size()) continue;
    const std::size_t over = overwrite ? std::min(len, file.size() - at) : 0;
    bytes d(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(at));
    d.insert(d.end(), other.begin() + static_cast<std::ptrdiff_t>(from),
             other.begin() + static_cast<std::ptrdiff_t>(from + len));
    d.insert(d.end(), file.begin() + static_cast<std::ptrdiff_t>(at + over), file.end());
    trial(
        tr, d,
        [&](auto s) {
          return overwrite ? s.second <= at || s.first >= at + over
                           : !(s.first < at && at < s.second);
        },
        fmt::format("{} bytes of the other recording from its offset {} {} offset {}", len, from,
                    overwrite ? "written over" : "inserted at", at),
        t);
  }
}

}  // namespace gyroflip::test
