// A rig on the host port for the firmware tests: the core, the models behind its HAL, and a
// host side that speaks the protocol through the virtual UART.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <vector>

#include "firmware/core/device.hpp"
#include "firmware/ports/host/board.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"

namespace gyroflip::fw::testing {

/// A deterministic code source: code = base + (table at B ? -rate : +rate) + noise, the noise a
/// 31-bit LCG of the conversion index mapped to [-amp, amp] (plain integers, so the expected
/// sums are exact).
struct code_source {
  int32_t base = 1000;
  int32_t rate = 250;
  int32_t noise_amp = 300;
  int32_t temp_code = -4000;
  const model::host_board* board = nullptr;
  int32_t pos_b_board = 100;  // motor 0's position at B, modulo a revolution, from home
  int32_t home_offset = 0;    // the board position of the home switch
  std::vector<int32_t>* positions = nullptr;  // motor 0's position at each gyro conversion

  [[nodiscard]] static int32_t noise(uint32_t index, int32_t amp) {
    if (amp == 0) return 0;
    uint32_t x = index * 1103515245u + 12345u;
    x ^= x >> 13;
    x *= 2654435761u;
    return static_cast<int32_t>(x % static_cast<uint32_t>(2 * amp + 1)) - amp;
  }
  [[nodiscard]] int32_t gyro(uint32_t index, bool at_b) const {
    return base + (at_b ? -rate : rate) + noise(index, noise_amp);
  }
  static int32_t call(void* ctx, uint8_t ch, uint32_t index) {
    const auto& s = *static_cast<const code_source*>(ctx);
    if (ch != 0) return s.temp_code + static_cast<int32_t>(index % 7);
    if (s.positions != nullptr) s.positions->push_back(s.board->motors.position[0]);
    const int32_t rev = s.board != nullptr ? s.board->steps_per_rev : 200;
    const bool at_b =
        s.board != nullptr &&
        ((s.board->motors.position[0] - s.home_offset) % rev + rev) % rev == s.pos_b_board;
    return s.gyro(index, at_b);
  }
};

struct rig {
  std::vector<int32_t> positions;
  code_source source{.positions = &positions};
  model::host_board board{&code_source::call, &source};
  device dev{board.hw(), board_facts{12345u, ad7739::mclk_hz_nominal}};
  protocol::stream_decoder decoder{true};  // retransmitted frames are handed out too
  uint16_t seq = 0;

  struct received {
    uint8_t type;
    uint16_t seq;
    std::vector<uint8_t> payload;
    uint32_t at_ticks;
    template <class M>
    [[nodiscard]] M as() const {
      protocol::frame f;
      f.type = type;
      f.seq = seq;
      f.payload = payload.data();
      f.length = payload.size();
      M m;
      if (!f.as(m)) throw std::runtime_error("frame is not the message asked for");
      return m;
    }
  };
  std::vector<received> frames;

  rig() {
    source.board = &board;
    dev.boot();
    run(1000);  // INFO (180 wire bytes) leaves at 115200 b/s: 16 ms
  }

  void drain() {
    uint8_t buf[4096];
    for (;;) {
      const size_t n = board.host_receive(buf, sizeof buf);
      if (n == 0) break;
      for (size_t i = 0; i < n; ++i)
        if (decoder.push(buf[i])) {
          const protocol::frame& f = decoder.current();
          frames.push_back(
              {f.type, f.seq, std::vector<uint8_t>(f.payload, f.payload + f.length), board.now});
        }
    }
  }

  /// Runs the device for `ticks` virtual ticks (one poll per tick).
  void run(uint32_t ticks) {
    for (uint32_t i = 0; i < ticks; ++i) {
      dev.poll();
      ++board.now;
      if ((i & 255u) == 0) drain();
    }
    drain();
  }
  /// Runs until `pred()` or `max_ticks`; true when pred held.
  bool run_until(const std::function<bool()>& pred, uint32_t max_ticks) {
    for (uint32_t i = 0; i < max_ticks; ++i) {
      dev.poll();
      ++board.now;
      if ((i & 63u) == 0) {
        drain();
        if (pred()) return true;
      }
    }
    drain();
    return pred();
  }

  /// Sends `m` as the host does (line code included) with the next sequence number, or `at`.
  template <class M>
  uint16_t send(const M& m) {
    return send_as(m, seq++);
  }
  template <class M>
  uint16_t send_as(const M& m, uint16_t s) {
    uint8_t buf[protocol::max_wire_bytes];
    const size_t n = protocol::encode_wire(m, s, buf, sizeof buf, true);
    board.host_send(buf, n);
    return s;
  }
  /// Wire bytes as they are (junk on the line).
  void send_bytes(const std::vector<uint8_t>& b) { board.host_send(b.data(), b.size()); }
  /// A COBS stream (a frame and its delimiter, as encode_frame gives it) through the line code.
  void send_cobs(const uint8_t* p, size_t n) {
    std::vector<uint8_t> w(protocol::run_before_command, 0);  // as a host sends
    for (size_t i = 0; i + 1 < n; ++i) {  // the last byte is COBS's 0x00: the run replaces it
      uint8_t two[2];
      protocol::line_encode(p[i], two);
      w.insert(w.end(), two, two + 2);
    }
    w.insert(w.end(), protocol::run_after(p[n - 2]), 0);
    send_bytes(w);
  }
  /// START naming the device's configuration (as a host sends it).
  uint16_t start() {
    protocol::start_msg m;
    m.config_crc = protocol::configure_crc(dev.config());
    return send(m);
  }

  template <class M>
  [[nodiscard]] std::vector<M> all() const {
    std::vector<M> out;
    for (const auto& f : frames)
      if (f.type == static_cast<uint8_t>(M::type)) out.push_back(f.template as<M>());
    return out;
  }
  /// The last message of type M (throws when there is none).
  template <class M>
  [[nodiscard]] M last() const {
    for (auto it = frames.rbegin(); it != frames.rend(); ++it)
      if (it->type == static_cast<uint8_t>(M::type)) return it->template as<M>();
    throw std::runtime_error("no such message received");
  }
  template <class M>
  [[nodiscard]] size_t count() const {
    size_t n = 0;
    for (const auto& f : frames) n += f.type == static_cast<uint8_t>(M::type) ? 1 : 0;
    return n;
  }
};

/// A short configuration for tests: n_avg conversions per dwell, no temperature conversions,
/// 5 ms of settling, no periodic STATUS.
inline protocol::configure_msg quick_config(uint16_t n_avg) {
  protocol::configure_msg c;
  c.n_avg = n_avg;
  c.n_temp = 0;
  c.settle_ms = 5;
  c.status_period_ms = 0;
  return c;
}

/// Sends CONFIGURE `c` and requires its ACK.
inline void configure(rig& r, const protocol::configure_msg& c) {
  const uint16_t s = r.send(c);
  r.run(400);
  const auto acks = r.all<protocol::ack_msg>();
  ASSERT_FALSE(acks.empty());
  ASSERT_EQ(acks.back().seq, s) << "CONFIGURE was not acknowledged";
}

}  // namespace gyroflip::fw::testing
