// docs/PROTOCOL.md is a specification a user writes a reader from: its example frames and its
// table of layout seeds must be what the encoder produces.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"

namespace {

using namespace gyroflip::protocol;

std::string doc() {
  std::ifstream in(std::string(GYROFLIP_DOCS_DIR) + "/PROTOCOL.md");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

template <class M>
std::string wire_hex(const M& m, uint16_t seq) {
  uint8_t buf[max_wire];
  const size_t n = encode_message(m, seq, buf, sizeof buf);
  std::string out;
  char b[4];
  for (size_t i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%s%02X", i == 0 ? "" : " ", buf[i]);
    out += b;
  }
  return out;
}

template <class M>
std::string line_hex(const M& m, uint16_t seq, bool lead) {
  uint8_t buf[max_wire_bytes];
  const size_t n = encode_wire(m, seq, buf, sizeof buf, lead);
  std::string out;
  char b[4];
  for (size_t i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%s%02X", i == 0 ? "" : " ", buf[i]);
    out += b;
  }
  return out;
}

// The doc's line that starts with `label: `, without the label.
std::string example(const std::string& text, const std::string& label) {
  const std::string key = "\n" + label + ": ";
  const size_t at = text.find(key);
  if (at == std::string::npos) return "(no example '" + label + "')";
  const size_t from = at + key.size();
  return text.substr(from, text.find('\n', from) - from);
}

TEST(ProtocolDoc, ExampleFramesAreTheEncodersBytes) {
  const std::string t = doc();
  ASSERT_FALSE(t.empty());
  ack_msg a;
  a.of_type = 0x20;
  set_delta_n_msg d;
  d.delta_n_q8 = 791;
  calibrate_msg k;
  k.cycles = 100;
  info_msg i;
  i.fw_minor = 4;
  i.protocol = 2;
  i.serial = 0x0F149001;
  i.mclk_hz = 6144000;
  i.tick_hz = 32768;
  i.adc_revision = 0x29;
  i.max_n_avg = 65535;
  i.max_raw_codes = 32;
  i.range = 4;
  i.reset_cause = 1;
  i.boot_count = 1;
  i.history_bytes = 400;
  i.stored = info_serial_stored | info_delta_n_stored;
  i.delta_n_q8 = 791;
  dwell_msg w;
  w.cycle = 7;
  w.position = 1;
  w.t_start_ticks = 1234567;
  w.t_end_ticks = 1251833;
  w.n = 256;
  w.code_sum = -1234567;
  w.code_min = -9000;
  w.code_max = 4000;
  w.n_temp = 4;
  w.temp_sum = -16000;
  w.ax_high_ticks = 8200;
  w.ax_period_ticks = 16400;
  w.ay_high_ticks = 8100;
  w.ay_period_ticks = 16400;
  raw_msg r;
  r.first_index = 3584;
  r.count = 2;
  r.set(0, -4821);
  r.set(1, 17);
  status_msg s;
  s.state = 2;
  s.uptime_ticks = 327680;
  s.cycle = 7;
  s.frames_sent = 120;
  s.rx_frames_ok = 4;
  s.history_oldest = 113;
  s.stack_free = 530;
  error_msg e;
  e.code = 5;
  e.what = 1;
  e.value = 1234;
  nak_msg nk;
  nk.seq = 9;
  nk.of_type = 0x21;
  nk.reason = 8;
  compensated_msg cm;
  cm.cycle = 7;
  cm.rate_q8 = -1523;
  cm.bias_q8 = 12800000;
  cal_result_msg cr;
  cr.cycles = 100;
  cr.delta_n_q8 = 791;
  cr.std_q8 = 2048;
  start_msg st;
  st.config_crc = configure_crc(configure_msg{});
  resend_msg rs;
  rs.count = 2;
  rs.seqs[0] = 40;
  rs.seqs[1] = 41;
  gone_msg gn;
  gn.count = 1;
  gn.seqs[0] = 40;

  EXPECT_EQ(example(t, "ping seq=0"), wire_hex(ping_msg{}, 0));
  EXPECT_EQ(example(t, "ack seq=0 of ping seq=0"), wire_hex(a, 0));
  EXPECT_EQ(example(t, "configure seq=1 (defaults)"), wire_hex(configure_msg{}, 1));
  EXPECT_EQ(example(t, "start seq=2 (naming the default configuration)"), wire_hex(st, 2));
  EXPECT_EQ(example(t, "stop seq=3"), wire_hex(stop_msg{}, 3));
  EXPECT_EQ(example(t, "home seq=4"), wire_hex(home_msg{}, 4));
  EXPECT_EQ(example(t, "set_delta_n seq=5 (791 q8)"), wire_hex(d, 5));
  EXPECT_EQ(example(t, "calibrate seq=6 (100 cycles)"), wire_hex(k, 6));
  EXPECT_EQ(example(t, "info seq=0 (MSP430F149, defaults)"), wire_hex(i, 0));
  EXPECT_EQ(example(t, "dwell seq=42"), wire_hex(w, 42));
  EXPECT_EQ(example(t, "raw seq=43 (2 codes)"), wire_hex(r, 43));
  EXPECT_EQ(example(t, "status seq=44"), wire_hex(s, 44));
  EXPECT_EQ(example(t, "error seq=45"), wire_hex(e, 45));
  EXPECT_EQ(example(t, "nak seq=46"), wire_hex(nk, 46));
  EXPECT_EQ(example(t, "compensated seq=47"), wire_hex(cm, 47));
  EXPECT_EQ(example(t, "cal_result seq=48"), wire_hex(cr, 48));
  EXPECT_EQ(example(t, "resend seq=7 (40 and 41)"), wire_hex(rs, 7));
  EXPECT_EQ(example(t, "gone seq=49 (40)"), wire_hex(gn, 49));
  // On the wire (the line code): a host's command with its leading run, a device's answer.
  EXPECT_EQ(example(t, "wire: ping seq=0 from a host"), line_hex(ping_msg{}, 0, true));
  EXPECT_EQ(example(t, "wire: ack seq=0 of ping seq=0"), line_hex(a, 0, false));
}

TEST(ProtocolDoc, TheMessageTableHasEverySeedAndPayloadSize) {
  const std::string t = doc();
  struct row {
    uint8_t type;
    const char* name;
    uint8_t seed;
  };
  const std::vector<row> rows = {
      {0x01, "INFO", info_msg::crc_extra},
      {0x10, "DWELL", dwell_msg::crc_extra},
      {0x11, "RAW", raw_msg::crc_extra},
      {0x12, "STATUS", status_msg::crc_extra},
      {0x13, "ERROR", error_msg::crc_extra},
      {0x14, "ACK", ack_msg::crc_extra},
      {0x15, "NAK", nak_msg::crc_extra},
      {0x16, "COMPENSATED", compensated_msg::crc_extra},
      {0x17, "CAL_RESULT", cal_result_msg::crc_extra},
      {0x18, "GONE", gone_msg::crc_extra},
      {0x20, "PING", ping_msg::crc_extra},
      {0x21, "CONFIGURE", configure_msg::crc_extra},
      {0x22, "START", start_msg::crc_extra},
      {0x23, "STOP", stop_msg::crc_extra},
      {0x24, "HOME", home_msg::crc_extra},
      {0x25, "SET_DELTA_N", set_delta_n_msg::crc_extra},
      {0x26, "CALIBRATE", calibrate_msg::crc_extra},
      {0x27, "RESEND", resend_msg::crc_extra},
  };
  for (const row& r : rows) {
    char head[32];
    std::snprintf(head, sizeof head, "| 0x%02X | %s |", r.type, r.name);
    const size_t at = t.find(head);
    ASSERT_NE(at, std::string::npos) << head;
    const std::string line = t.substr(at, t.find('\n', at) - at);
    char seed[16];
    std::snprintf(seed, sizeof seed, "| 0x%02X |", r.seed);
    EXPECT_NE(line.find(seed), std::string::npos) << line;
  }
}

}  // namespace
