// The rig's wire protocol (firmware/protocol, docs/PROTOCOL.md): CRC and COBS against published
// vectors, a round trip of every message, every single-bit flip and every truncation of sample
// frames rejected, and a stream with junk, duplicated and dropped frames decoded with exact counts.
#include <gtest/gtest.h>

#include <bit>

#include <cstdint>
#include <random>
#include <vector>

#include "firmware/protocol/cobs.hpp"
#include "firmware/protocol/crc16.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "firmware/protocol/messages.hpp"

namespace p = gyroflip::protocol;
using bytes = std::vector<std::uint8_t>;

namespace {

// An independent bitwise CRC-16/CCITT-FALSE (no table) to check the table-driven one.
std::uint16_t crc16_bitwise(const bytes& b) {
  std::uint16_t c = 0xFFFF;
  for (std::uint8_t x : b) {
    c = static_cast<std::uint16_t>(c ^ (x << 8));
    for (int k = 0; k < 8; ++k)
      c = static_cast<std::uint16_t>((c & 0x8000) != 0 ? (c << 1) ^ 0x1021 : c << 1);
  }
  return c;
}

bytes cobs(const bytes& in) {
  bytes out(p::cobs_max_encoded(in.size()));
  const std::size_t n = p::cobs_encode(in.data(), in.size(), out.data(), out.size());
  out.resize(n);
  return out;
}

template <class M>
bytes frame_of(const M& m, std::uint16_t seq) {
  bytes out(p::max_wire);
  const std::size_t n = p::encode_message(m, seq, out.data(), out.size());
  EXPECT_GT(n, 0u);
  out.resize(n);
  return out;
}

struct decoded {
  std::vector<p::frame> frames;
  std::vector<bytes> payloads;
};

decoded decode_all(p::frame_decoder& d, const bytes& stream) {
  decoded r;
  for (std::uint8_t b : stream) {
    if (d.push(b)) {
      r.frames.push_back(d.current());
      r.payloads.emplace_back(d.current().payload, d.current().payload + d.current().length);
    }
  }
  return r;
}

// Messages with every field away from its default, drawn from a fixed seed.
struct samples {
  p::info_msg info;
  p::dwell_msg dwell;
  p::raw_msg raw;
  p::status_msg status;
  p::error_msg error;
  p::ack_msg ack;
  p::nak_msg nak;
  p::compensated_msg compensated;
  p::cal_result_msg cal_result;
  p::ping_msg ping;
  p::configure_msg configure;
  p::start_msg start;
  p::stop_msg stop;
  p::home_msg home;
  p::set_delta_n_msg set_delta_n;
  p::calibrate_msg calibrate;
  p::gone_msg gone;
  p::resend_msg resend;

  explicit samples(std::uint32_t seed) {
    std::mt19937 g(seed);
    auto u = [&](auto& v) { v = static_cast<std::remove_reference_t<decltype(v)>>(g()); };
    auto code = [&] { return static_cast<std::int32_t>(g() % (1u << 24)) - (1 << 23); };
    u(configure.n_avg), u(configure.n_temp), u(configure.settle_ms), u(configure.n_positions);
    for (auto& v : configure.pos_steps) u(v);
    for (auto& v : configure.pos_cdeg) u(v);
    u(configure.steps_per_rev), u(configure.step_rate_sps);
    u(configure.start_rate_sps), u(configure.ramp_sps2), u(configure.filter_word);
    u(configure.flags), u(configure.flip_motor), u(configure.other_motor);
    u(configure.gyro_channel), u(configure.temp_channel), u(configure.status_period_ms);
    u(info.fw_major), u(info.fw_minor), u(info.fw_patch), u(info.protocol), u(info.serial);
    u(info.mclk_hz), u(info.tick_hz), u(info.adc_revision), u(info.max_n_avg);
    u(info.max_raw_codes), u(info.range), u(info.reset_cause), u(info.boot_count);
    u(info.history_bytes);
    info.config = configure;
    u(dwell.cycle), u(dwell.position), u(dwell.flags), u(dwell.t_start_ticks);
    u(dwell.t_end_ticks), u(dwell.n), u(dwell.n_temp), u(dwell.temp_sum);
    dwell.code_sum = -static_cast<std::int64_t>(g() % (1u << 23)) * 65535;  // beyond 32 bits
    dwell.code_min = code(), dwell.code_max = code();
    u(dwell.ax_high_ticks), u(dwell.ax_period_ticks), u(dwell.ay_high_ticks);
    u(dwell.ay_period_ticks);
    u(raw.first_index);
    raw.count = p::raw_msg::max_codes;
    for (std::uint8_t i = 0; i < raw.count; ++i) raw.set(i, code());
    raw.set(0, -(1 << 23)), raw.set(1, (1 << 23) - 1);  // both ends of the 24-bit range
    u(status.state), u(status.uptime_ticks), u(status.cycle), u(status.frames_sent);
    u(status.frames_dropped), u(status.rx_frames_ok), u(status.rx_errors);
    u(status.rdy_timeouts), u(status.last_error), u(status.retransmits);
    u(status.history_oldest), u(status.line_corrected), u(status.line_uncorrectable);
    u(status.start_failures), u(status.stale_results), u(status.stack_free);
    u(status.clock_faults);
    u(error.code), u(error.what), u(error.value);
    u(ack.seq), u(ack.of_type);
    u(nak.seq), u(nak.of_type), u(nak.reason);
    u(compensated.cycle), u(compensated.rate_q8), u(compensated.bias_q8), u(compensated.flags);
    u(cal_result.cycles), u(cal_result.delta_n_q8), u(cal_result.std_q8), u(cal_result.flags);
    u(set_delta_n.delta_n_q8);
    u(calibrate.cycles);
    u(start.config_crc);
    gone.count = p::gone_msg::max_seqs;
    for (auto& v : gone.seqs) u(v);
    resend.count = 5;
    for (std::uint8_t i = 0; i < resend.count; ++i) u(resend.seqs[i]);
  }

  // Calls f(message) for every message type.
  template <class F>
  void each(F&& f) const {
    f(info), f(dwell), f(raw), f(status), f(error), f(ack), f(nak), f(compensated);
    f(cal_result), f(ping), f(configure), f(start), f(stop), f(home), f(set_delta_n);
    f(calibrate), f(gone), f(resend);
  }
};

template <class M>
void expect_round_trip(const M& m, std::uint16_t seq) {
  p::frame_decoder d;
  const bytes wire = frame_of(m, seq);
  ASSERT_LE(wire.size(), p::max_wire);
  const decoded got = decode_all(d, wire);
  ASSERT_EQ(got.frames.size(), 1u) << "type " << int(M::type);
  EXPECT_EQ(got.frames[0].seq, seq);
  M back{};
  p::frame f = got.frames[0];
  f.payload = got.payloads[0].data();
  ASSERT_TRUE(f.as(back)) << "type " << int(M::type);
  EXPECT_TRUE(back == m) << "type " << int(M::type);
  EXPECT_EQ(d.counts().good, 1u);
  EXPECT_EQ(d.counts().bad(), 0u);
}

}  // namespace

TEST(Crc16, CheckValueAndBitwiseAgreement) {
  // CRC-16/CCITT-FALSE of "123456789" is 0x29B1 (Greg Cook's catalogue of parametrised CRCs).
  const bytes check = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(p::crc16(check.data(), check.size()), 0x29B1);
  std::mt19937 g(7);
  for (int len = 0; len < 300; ++len) {
    bytes b(static_cast<std::size_t>(len));
    for (auto& x : b) x = static_cast<std::uint8_t>(g());
    EXPECT_EQ(p::crc16(b.data(), b.size()), crc16_bitwise(b)) << len;
  }
}

TEST(Cobs, PublishedExamples) {
  // The examples of Cheshire & Baker's encoding as listed in the COBS literature (Wikipedia,
  // "Consistent Overhead Byte Stuffing", examples 1-7; the 254/255-byte ones built here).
  EXPECT_EQ(cobs({0x00}), (bytes{0x01, 0x01}));
  EXPECT_EQ(cobs({0x00, 0x00}), (bytes{0x01, 0x01, 0x01}));
  EXPECT_EQ(cobs({0x00, 0x11, 0x00}), (bytes{0x01, 0x02, 0x11, 0x01}));
  EXPECT_EQ(cobs({0x11, 0x22, 0x00, 0x33}), (bytes{0x03, 0x11, 0x22, 0x02, 0x33}));
  EXPECT_EQ(cobs({0x11, 0x22, 0x33, 0x44}), (bytes{0x05, 0x11, 0x22, 0x33, 0x44}));
  EXPECT_EQ(cobs({0x11, 0x00, 0x00, 0x00}), (bytes{0x02, 0x11, 0x01, 0x01, 0x01}));
  bytes run254;  // 01 .. FE: one full block, then an empty final block
  for (int i = 1; i <= 254; ++i) run254.push_back(static_cast<std::uint8_t>(i));
  bytes want = {0xFF};
  want.insert(want.end(), run254.begin(), run254.end());
  want.push_back(0x01);
  EXPECT_EQ(cobs(run254), want);
  bytes run255 = {0x00};  // 00 01 .. FE
  run255.insert(run255.end(), run254.begin(), run254.end());
  want = {0x01, 0xFF};
  want.insert(want.end(), run254.begin(), run254.end());
  want.push_back(0x01);
  EXPECT_EQ(cobs(run255), want);
}

TEST(Cobs, RoundTripInPlaceAndRejectsBadInput) {
  std::mt19937 g(11);
  for (int len = 0; len < 700; len += (len < 20 ? 1 : 7)) {
    bytes in(static_cast<std::size_t>(len));
    for (auto& x : in) x = (g() % 4 == 0) ? 0 : static_cast<std::uint8_t>(g());
    const bytes enc = cobs(in);
    ASSERT_LE(enc.size(), p::cobs_max_encoded(in.size()));
    for (std::uint8_t x : enc) ASSERT_NE(x, 0);
    // In place: the input staged at the documented offset inside the output buffer.
    const std::size_t off = p::cobs_max_encoded(in.size()) - in.size();
    bytes buf(off + in.size() + 1);
    std::copy(in.begin(), in.end(), buf.begin() + static_cast<std::ptrdiff_t>(off));
    const std::size_t n = p::cobs_encode(buf.data() + off, in.size(), buf.data(), buf.size());
    ASSERT_EQ(bytes(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n)), enc) << len;
    bytes dec(in.size() + 8);
    const long m = p::cobs_decode(enc.data(), enc.size(), dec.data(), dec.size());
    ASSERT_EQ(m, len);
    dec.resize(static_cast<std::size_t>(m));
    ASSERT_EQ(dec, in);
  }
  bytes dst(16);
  const bytes zero_inside = {0x03, 0x11, 0x00};
  EXPECT_EQ(p::cobs_decode(zero_inside.data(), zero_inside.size(), dst.data(), dst.size()), -1);
  const bytes past_end = {0x05, 0x11, 0x22};
  EXPECT_EQ(p::cobs_decode(past_end.data(), past_end.size(), dst.data(), dst.size()), -1);
  const bytes fits = {0x05, 0x11, 0x22, 0x33, 0x44};
  EXPECT_EQ(p::cobs_decode(fits.data(), fits.size(), dst.data(), 3), -1);  // capacity too small
}

TEST(Protocol, EveryMessageRoundTrips) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const samples s(seed);
    std::uint16_t seq = static_cast<std::uint16_t>(seed * 1000);
    s.each([&](const auto& m) { expect_round_trip(m, seq++); });
  }
  // Defaults and the sequence number's ends.
  expect_round_trip(p::configure_msg{}, 0);
  expect_round_trip(p::dwell_msg{}, 0xFFFF);
  p::raw_msg empty;
  expect_round_trip(empty, 5);
}

TEST(Protocol, MessagesHaveDistinctLayoutSeedsAndFitAFrame) {
  const samples s(4);
  std::vector<int> types;
  s.each([&](const auto& m) {
    using M = std::remove_cvref_t<decltype(m)>;
    std::uint8_t extra = 0;
    ASSERT_TRUE(p::crc_extra_of(static_cast<std::uint8_t>(M::type), extra));
    EXPECT_EQ(extra, M::crc_extra);
    types.push_back(static_cast<int>(M::type));
  });
  std::sort(types.begin(), types.end());
  EXPECT_EQ(std::adjacent_find(types.begin(), types.end()), types.end());
  std::uint8_t extra = 0;
  for (int t = 0; t < 256; ++t) {
    const bool known = std::binary_search(types.begin(), types.end(), t);
    EXPECT_EQ(p::crc_extra_of(static_cast<std::uint8_t>(t), extra), known) << t;
  }
  p::raw_msg too_many;
  too_many.count = p::raw_msg::max_codes + 1;
  bytes out(p::max_wire);
  EXPECT_EQ(p::encode_message(too_many, 0, out.data(), out.size()), 0u);
  EXPECT_EQ(p::encode_message(p::ping_msg{}, 0, out.data(), p::max_wire - 1), 0u);
}

TEST(Protocol, AnotherLayoutOfAMessageIsACrcErrorNotAMisread) {
  // A peer whose DWELL has another layout (another seed) but the same length: MAVLink v2's
  // CRC_EXTRA point. The frame is rejected as a CRC error.
  const samples s(5);
  bytes payload(p::max_payload);
  p::writer w{payload.data(), payload.size()};
  s.dwell.put(w);
  bytes raw = {p::protocol_version, static_cast<std::uint8_t>(p::msg::dwell), 7, 0,
               static_cast<std::uint8_t>(w.n)};
  raw.insert(raw.end(), payload.begin(), payload.begin() + static_cast<std::ptrdiff_t>(w.n));
  const auto other_seed = static_cast<std::uint8_t>(p::dwell_msg::crc_extra ^ 0x5A);
  const std::uint16_t crc = p::crc16_byte(p::crc16(raw.data(), raw.size()), other_seed);
  raw.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  raw.push_back(static_cast<std::uint8_t>(crc >> 8));
  bytes wire = cobs(raw);
  wire.push_back(0);
  p::frame_decoder d;
  EXPECT_TRUE(decode_all(d, wire).frames.empty());
  EXPECT_EQ(d.counts().crc_errors, 1u);
  // The same bytes with the right seed decode.
  EXPECT_EQ(wire.size(), frame_of(s.dwell, 7).size());
}

TEST(Protocol, EverySingleBitFlipAndEveryTruncationIsRejected) {
  const samples s(6);
  std::size_t checked = 0;
  s.each([&](const auto& m) {
    const bytes wire = frame_of(m, 0x1234);
    for (std::size_t i = 0; i + 1 < wire.size(); ++i) {  // the delimiter itself: below
      for (int bit = 0; bit < 8; ++bit) {
        bytes bad = wire;
        bad[i] = static_cast<std::uint8_t>(bad[i] ^ (1u << bit));
        p::frame_decoder d;
        const decoded got = decode_all(d, bad);
        ASSERT_TRUE(got.frames.empty()) << "type " << int(std::remove_cvref_t<decltype(m)>::type)
                                        << " byte " << i << " bit " << bit;
        ASSERT_GE(d.counts().bad(), 1u);
        ++checked;
      }
    }
    for (std::size_t k = 1; k + 1 < wire.size(); ++k) {
      bytes cut(wire.begin(), wire.begin() + static_cast<std::ptrdiff_t>(k));
      cut.push_back(0);
      p::frame_decoder d;
      ASSERT_TRUE(decode_all(d, cut).frames.empty()) << "truncated to " << k;
      ASSERT_EQ(d.counts().bad(), 1u);
      ++checked;
    }
    // A flipped delimiter joins the frame to the next one: both are lost, nothing misread.
    bytes joined = wire;
    joined.back() = 0x01;
    const bytes next = frame_of(m, 0x1235);
    joined.insert(joined.end(), next.begin(), next.end());
    p::frame_decoder d;
    ASSERT_TRUE(decode_all(d, joined).frames.empty());
  });
  EXPECT_GT(checked, 4000u);  // about 4 600 corrupted frames
}

TEST(Protocol, StreamWithJunkDuplicatesAndDropsIsCountedExactly) {
  // 200 frames numbered 0..199; frames 50..52 and 120 are dropped (4 missing), frames 10 and 90
  // are sent twice (2 duplicates), and junk is inserted: 3 runs ended by a delimiter (3 bad),
  // one flipped byte inside frame 150 (1 bad, and so 1 more missing), 2 empty delimiters (not
  // frames). Expected: 195 new frames handed out.
  const samples s(8);
  bytes stream = {0x00};  // a device starts with a delimiter
  std::mt19937 g(3);
  auto junk = [&] {
    for (int k = 0; k < 17; ++k) stream.push_back(static_cast<std::uint8_t>(1 + g() % 255));
    stream.push_back(0x00);
  };
  for (std::uint16_t seq = 0; seq < 200; ++seq) {
    if ((seq >= 50 && seq <= 52) || seq == 120) continue;
    p::dwell_msg m = s.dwell;
    m.cycle = seq;
    bytes f = frame_of(m, seq);
    if (seq == 150) f[5] = static_cast<std::uint8_t>(f[5] ^ 0x10);
    stream.insert(stream.end(), f.begin(), f.end());
    if (seq == 10 || seq == 90) stream.insert(stream.end(), f.begin(), f.end());
    if (seq == 30 || seq == 31 || seq == 170) junk();
    if (seq == 60) stream.insert(stream.end(), {0x00, 0x00});
  }
  for (std::size_t chunk : {std::size_t{1}, std::size_t{7}, std::size_t{4096}}) {
    p::frame_decoder d;
    std::vector<std::uint32_t> cycles;
    for (std::size_t at = 0; at < stream.size(); at += chunk) {
      for (std::size_t i = at; i < std::min(stream.size(), at + chunk); ++i) {
        if (d.push(stream[i])) {
          p::dwell_msg m;
          ASSERT_TRUE(d.current().as(m));
          ASSERT_EQ(m.cycle, d.current().seq);
          cycles.push_back(m.cycle);
        }
      }
    }
    EXPECT_EQ(cycles.size(), 195u);
    EXPECT_EQ(d.counts().good, 197u);  // the two duplicates are valid frames, not handed out
    EXPECT_EQ(d.counts().duplicates, 2u);
    EXPECT_EQ(d.counts().missing, 5u);
    EXPECT_EQ(d.counts().bad(), 4u);
    EXPECT_TRUE(std::is_sorted(cycles.begin(), cycles.end()));
  }
}

TEST(Protocol, OverlongInputIsDiscardedUntilTheNextDelimiter) {
  bytes stream(3 * p::max_wire, 0x42);
  stream.push_back(0);
  const bytes ok = frame_of(p::ping_msg{}, 1);
  stream.insert(stream.end(), ok.begin(), ok.end());
  p::frame_decoder d;
  const decoded got = decode_all(d, stream);
  EXPECT_EQ(got.frames.size(), 1u);
  EXPECT_EQ(d.counts().too_long, 1u);
  EXPECT_EQ(d.counts().bad(), 1u);
}

TEST(Protocol, OtherVersionUnknownTypeAndLengthMismatchAreNamed) {
  auto seal = [](bytes raw) {
    bytes wire = cobs(raw);
    wire.push_back(0);
    return wire;
  };
  bytes v1 = {1, static_cast<std::uint8_t>(p::msg::ping), 0, 0, 0, 0, 0};  // a version-1 device
  bytes unknown = {p::protocol_version, 0x7F, 0, 0, 0, 0, 0};
  bytes short_len = {p::protocol_version, static_cast<std::uint8_t>(p::msg::ping), 0, 0, 3, 0, 0};
  p::frame_decoder d;
  decode_all(d, seal(v1));
  decode_all(d, seal(unknown));
  decode_all(d, seal(short_len));
  decode_all(d, seal({1, 2, 3}));
  EXPECT_EQ(d.counts().bad_version, 1u);
  EXPECT_EQ(d.counts().foreign_version, 1u);
  EXPECT_EQ(d.counts().unknown_type, 1u);
  EXPECT_EQ(d.counts().bad_length, 2u);
  EXPECT_EQ(d.counts().good, 0u);
}

TEST(Protocol, WireFieldsAreLittleEndianAndSignExtended) {
  bytes buf(16);
  p::writer w{buf.data(), buf.size()};
  w.i24(-2);
  w.i48(-(std::int64_t{1} << 40) - 3);
  w.u32(0x01020304u);
  ASSERT_TRUE(w.ok);
  EXPECT_EQ(bytes(buf.begin(), buf.begin() + 13),
            (bytes{0xFE, 0xFF, 0xFF, 0xFD, 0xFF, 0xFF, 0xFF, 0xFF, 0xFE, 0x04, 0x03, 0x02, 0x01}));
  p::reader r{buf.data(), 13};
  EXPECT_EQ(r.i24(), -2);
  EXPECT_EQ(r.i48(), -(std::int64_t{1} << 40) - 3);
  EXPECT_EQ(r.u32(), 0x01020304u);
  EXPECT_TRUE(r.done());
  EXPECT_EQ(r.u8(), 0);
  EXPECT_FALSE(r.ok);
  p::writer full{buf.data(), 2};
  full.u32(1);
  EXPECT_FALSE(full.ok);
  EXPECT_EQ(full.n, 0u);
}

// ADXL202 data sheet Rev. B p. 1: A = (T1/T2 - 0.5) / 12.5 %, so 50 % duty is 0 g, 0 % and 100 %
// are -4 g and +4 g; values worked by hand, rounded to the nearest mg.
TEST(Protocol, Adxl202DutyCycleToAcceleration) {
  static_assert(p::adxl202_accel_mg(500, 1000) == 0);
  EXPECT_EQ(p::adxl202_accel_mg(56, 100), 480);
  EXPECT_EQ(p::adxl202_accel_mg(48, 100), -160);
  EXPECT_EQ(p::adxl202_accel_mg(2, 3), 1333);     // 1333.33
  EXPECT_EQ(p::adxl202_accel_mg(1, 3), -1333);    // -1333.33
  EXPECT_EQ(p::adxl202_accel_mg(4001, 8000), 1);  // one tick past 50 % of an 8000-tick period
  EXPECT_EQ(p::adxl202_accel_mg(0, 8000), -4000);
  EXPECT_EQ(p::adxl202_accel_mg(8000, 8000), 4000);
  EXPECT_EQ(p::adxl202_accel_mg(9000, 8000), 4000);  // T1 > T2 cannot be: full scale, no overflow
  EXPECT_EQ(p::adxl202_accel_mg(0xFFFFFFFFu, 0xFFFFFFFFu), 4000);
  EXPECT_EQ(p::adxl202_accel_mg(0x7FFFFFFFu, 0xFFFFFFFEu), 0);
  EXPECT_EQ(p::adxl202_accel_mg(7, 0), 0);  // no period captured
}

// ---- the line code (protocol v2: line.hpp) -------------------------------------------------

namespace {

// The extended Hamming [8,4,4] code: 16 codewords at distance >= 4 from each other, so every
// single bit error in a wire byte is corrected and every double one detected (never miscorrected).
TEST(LineCode, CorrectsEverySingleAndDetectsEveryDoubleBitError) {
  for (std::uint8_t a = 0; a < 16; ++a) {
    for (std::uint8_t b = 0; b < 16; ++b) {
      if (a == b) continue;
      const unsigned d = static_cast<unsigned>(p::hamming84_encode(a) ^ p::hamming84_encode(b));
      EXPECT_GE(std::popcount(d), 4);
    }
    const std::uint8_t c = p::hamming84_encode(a);
    EXPECT_EQ(p::hamming84_decode(c), a);
    for (int i = 0; i < 8; ++i) {
      EXPECT_EQ(p::hamming84_decode(static_cast<std::uint8_t>(c ^ (1u << i))),
                a | p::hamming84_corrected);
      for (int j = i + 1; j < 8; ++j)
        EXPECT_EQ(p::hamming84_decode(static_cast<std::uint8_t>(c ^ (1u << i) ^ (1u << j))),
                  p::hamming84_error);
    }
  }
}

bytes wire_of(const samples& s, std::uint16_t first_seq, bool lead) {
  bytes w;
  std::uint16_t seq = first_seq;
  s.each([&](const auto& m) {
    bytes b(p::max_wire_bytes);
    const std::size_t n = p::encode_wire(m, seq++, b.data(), b.size(), lead);
    b.resize(n);
    w.insert(w.end(), b.begin(), b.end());
  });
  return w;
}

std::size_t decode_line(p::stream_decoder& d, const bytes& w) {
  std::size_t n = 0;
  for (std::uint8_t b : w) n += d.push(b) ? 1u : 0u;
  return n;
}

// Every message through the line code, back to back as a device sends them and with the
// delimiter run before each as a host sends them: each decodes once, nothing corrected.
TEST(LineCode, EveryMessageRoundTripsBackToBackAndWithLeadingRuns) {
  const samples s(11);
  for (const bool lead : {false, true}) {
    p::stream_decoder d;
    EXPECT_EQ(decode_line(d, wire_of(s, 40, lead)), 18u) << lead;
    EXPECT_EQ(d.counts().bad(), 0u);
    EXPECT_EQ(d.line().corrected + d.line().uncorrectable + d.line().realigned, 0u);
  }
}

// One bit flipped in every wire byte of a stream: everything arrives, every flip is corrected.
TEST(LineCode, OneFlippedBitInEveryByteLosesNothing) {
  const samples s(12);
  bytes w = wire_of(s, 0, false);
  std::mt19937 g(5);
  for (std::uint8_t& b : w) b = static_cast<std::uint8_t>(b ^ (1u << (g() % 8)));
  p::stream_decoder d;
  EXPECT_EQ(decode_line(d, w), 18u);
  EXPECT_EQ(d.line().corrected, w.size());
  EXPECT_EQ(d.counts().bad(), 0u);
}

// A lost wire byte puts the high and low nibbles out of step: the frame it was in is lost, the
// delimiter run after it puts them back, and the next frames arrive.
TEST(LineCode, ALostByteCostsItsFrameOnly) {
  const samples s(13);
  const bytes w = wire_of(s, 0, false);
  for (std::size_t drop = 3; drop < w.size(); drop += 37) {
    bytes lossy = w;
    lossy.erase(lossy.begin() + static_cast<std::ptrdiff_t>(drop));
    p::stream_decoder d;
    EXPECT_GE(decode_line(d, lossy), 17u) << "drop at " << drop;
    EXPECT_LE(d.counts().bad(), 2u) << "drop at " << drop;  // its frame, split in two at most
  }
}

// Noise on an idle line (any bytes), then a long run of zeros, then frames: the noise never
// joins a frame. An even run keeps the nibbles in step with the noise's end; after an odd one
// (not a length the line code sends) the first frame may be read a nibble out and lost, and the
// delimiter runs put the rest back in step.
TEST(LineCode, NoiseAndIdleZerosBeforeAFrameDoNotJoinIt) {
  const samples s(14);
  for (const std::size_t zeros : {1000u, 1001u}) {
    bytes w;
    std::mt19937 g(6);
    for (int i = 0; i < 500; ++i) w.push_back(static_cast<std::uint8_t>(g()));
    w.insert(w.end(), zeros, 0);
    const bytes frames = wire_of(s, 0, true);
    w.insert(w.end(), frames.begin(), frames.end());
    p::stream_decoder d;
    EXPECT_GE(decode_line(d, w), zeros % 2 == 0 ? 18u : 17u) << zeros;
  }
}

// Between two frames, an idle run of any even length beyond the line code's own runs (those up to
// 16 carry the alignment: line.hpp) keeps the nibbles in step, also past the decoder's saturating
// count (253 once counted as 248, which put the frame after a run of more than 252 zeros one nibble
// out).
TEST(LineCode, LongEvenIdleRunsBetweenFramesKeepTheNibblesInStep) {
  const samples s(15);
  const bytes frames = wire_of(s, 0, true);
  for (const std::size_t idle : {20u, 100u, 248u, 250u, 252u, 254u, 256u, 258u, 1000u, 3000u}) {
    bytes w = frames;
    w.insert(w.end(), idle, 0);
    w.insert(w.end(), frames.begin(), frames.end());
    p::stream_decoder d{true};  // the second copy repeats the numbers
    EXPECT_EQ(decode_line(d, w), 36u) << idle;
    EXPECT_EQ(d.counts().bad(), 0u) << idle;
  }
}

}  // namespace
