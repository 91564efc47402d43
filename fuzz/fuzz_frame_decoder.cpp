/// \file
/// \brief libFuzzer target: the rig protocol's decoders (firmware/protocol) on any byte stream:
/// the frame decoder (COBS frames) and the stream decoder (the line code over it, what a host and
/// a device read from the wire). Checks that every delimiter is accounted for, that every frame
/// handed out is well formed, and that a message decoded from it encodes back to the same payload
/// bytes, through the line code too.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"

namespace p = gyroflip::protocol;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

template <class M>
void reencode(const p::frame& f) {
  M m{};
  if (!f.as(m)) return;
  std::uint8_t wire[p::max_wire];
  const std::size_t n = p::encode_message(m, f.seq, wire, sizeof wire);
  check(n > 0 && n <= p::max_wire);
  p::frame_decoder d;
  bool got = false;
  for (std::size_t i = 0; i < n; ++i) got = d.push(wire[i]) || got;
  check(got && d.current().length == f.length && d.current().type == f.type);
  check(std::memcmp(d.current().payload, f.payload, f.length) == 0);
  std::uint8_t line[p::line_bytes(p::max_payload)];
  const std::size_t k = p::encode_wire(m, f.seq, line, sizeof line);
  check(k > 0 && k <= sizeof line);
  p::stream_decoder s;
  got = false;
  for (std::size_t i = 0; i < k; ++i) got = s.push(line[i]) || got;
  check(got && s.current().length == f.length && s.current().type == f.type);
  check(std::memcmp(s.current().payload, f.payload, f.length) == 0);
  check(s.line().corrected == 0 && s.line().uncorrectable == 0);
}

void reencode_any(const p::frame& f) {
  switch (static_cast<p::msg>(f.type)) {
    case p::msg::info:
      return reencode<p::info_msg>(f);
    case p::msg::dwell:
      return reencode<p::dwell_msg>(f);
    case p::msg::raw:
      return reencode<p::raw_msg>(f);
    case p::msg::status:
      return reencode<p::status_msg>(f);
    case p::msg::error:
      return reencode<p::error_msg>(f);
    case p::msg::ack:
      return reencode<p::ack_msg>(f);
    case p::msg::nak:
      return reencode<p::nak_msg>(f);
    case p::msg::compensated:
      return reencode<p::compensated_msg>(f);
    case p::msg::cal_result:
      return reencode<p::cal_result_msg>(f);
    case p::msg::ping:
      return reencode<p::ping_msg>(f);
    case p::msg::configure:
      return reencode<p::configure_msg>(f);
    case p::msg::start:
      return reencode<p::start_msg>(f);
    case p::msg::stop:
      return reencode<p::stop_msg>(f);
    case p::msg::home:
      return reencode<p::home_msg>(f);
    case p::msg::set_delta_n:
      return reencode<p::set_delta_n_msg>(f);
    case p::msg::calibrate:
      return reencode<p::calibrate_msg>(f);
    case p::msg::gone:
      return reencode<p::gone_msg>(f);
    case p::msg::resend:
      return reencode<p::resend_msg>(f);
  }
  std::abort();  // the decoder handed out a type it does not know
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  p::frame_decoder d;
  std::uint32_t ended = 0;  // delimiters that end at least one byte
  std::uint32_t handed_out = 0;
  bool pending = false;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0) {
      if (pending) ++ended;
      pending = false;
    } else {
      pending = true;
    }
    if (d.push(data[i])) {
      ++handed_out;
      check(d.current().length <= p::max_payload);
      reencode_any(d.current());
    }
  }
  const p::decoder_counts& c = d.counts();
  check(c.good + c.bad() == ended);
  check(handed_out + c.duplicates == c.good);
  // The same bytes as wire bytes: whatever the line code makes of them, every frame handed out
  // is well formed and re-encodes.
  p::stream_decoder line;
  for (std::size_t i = 0; i < size; ++i) {
    if (line.push(data[i])) {
      check(line.current().length <= p::max_payload);
      reencode_any(line.current());
    }
  }
  check(line.line().corrected + line.line().uncorrectable <= size);
  return 0;
}
