/// \file
/// \brief The rig's firmware core (docs/FIRMWARE.md): the sequencer (turn -> settle -> acquire
/// N -> report -> turn, through the positions of CONFIGURE's angle table), the sampler (AD7739
/// conversions with a bounded RDY wait and a check that each result is new, PWM tilt capture),
/// the link (commands in, executed once each; frames out through a transmit ring that never
/// blocks; a retransmit history that RESEND draws on) and the on-board processing. One object,
/// no allocation, no global state; a port creates it with its HAL and calls poll() from its
/// main loop.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "firmware/core/processing.hpp"
#include "firmware/drivers/ad7739/ad7739.hpp"
#include "firmware/drivers/stepper/stepper.hpp"
#include "firmware/hal/hal.hpp"
#include "firmware/protocol/budget.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "firmware/util/history.hpp"
#include "firmware/util/ring.hpp"

namespace gyroflip::fw {

inline constexpr uint8_t fw_version_major = 0;
inline constexpr uint8_t fw_version_minor = 3;
inline constexpr uint8_t fw_version_patch = 0;

/// Transmit ring, in bytes of the COBS stream (each goes out as two wire bytes): a RAW frame
/// (112 B with its delimiters) plus the reserve below, plus room for what is still going out.
inline constexpr size_t tx_ring_bytes = 352;
/// Room a RAW frame must leave in the ring for a DWELL, a COMPENSATED and a STATUS (RAW is
/// dropped first when the link falls behind; a RAW block every 64 ms leaves time to send them).
inline constexpr size_t tx_reserve_bytes = (protocol::line_bytes(protocol::dwell_payload) +
                                            protocol::line_bytes(protocol::compensated_payload) +
                                            protocol::line_bytes(protocol::status_payload)) /
                                           protocol::line_expansion;
static_assert(tx_ring_bytes >=
              protocol::line_bytes(protocol::raw_payload(32)) / 2 + tx_reserve_bytes + 64);
/// The retransmit history (RESEND): frames before COBS. On the MSP430F149 it takes what its
/// 2 KB of RAM leave (docs/PERFORMANCE.md): 7 DWELLs (57 B each with its length byte), i.e.
/// 6 s of the paper's rig (a dwell every ~0.9 s), or 4.5 s with COMPENSATED on.
inline constexpr size_t history_bytes = 400;
/// The longest command frame (CONFIGURE, 54 B of payload) as COBS bytes: the receive buffer.
inline constexpr size_t max_command_cobs = 64;
/// A wait the sequencer should have ended this long ago means it is stuck: the watchdog is no
/// longer fed (ticks).
inline constexpr uint32_t stall_ticks = 8192;
/// Polls without the tick counter moving before the tick clock (the 32 768 Hz crystal on the
/// MSP430F149) is declared failed: a pass takes at least ~100 MCLK cycles, so >= 0.36 s at
/// 5.5296 MHz, thousands of tick periods.
inline constexpr uint32_t frozen_tick_polls = 20000;
/// The home switch must read closed this long before homing ends (contact bounce and noise).
inline constexpr uint32_t home_debounce_ticks = 66;  // 2 ms at 32 768 Hz

/// What a port tells the core about its board.
struct board_facts {
  uint32_t serial = 0;
  uint32_t mclk_hz = ad7739::mclk_hz_nominal;                   ///< the AD7739's master clock
  protocol::board_kind board = protocol::board_kind::hardware;  ///< INFO's `board`
};

class device {
 public:
  /// Constant-initialised (constexpr): a port's device object needs no constructor at start-up,
  /// so an image works whatever a flasher does with .init_array (docs/FIRMWARE.md).
  constexpr device(const hal& hw, const board_facts& facts) : hw_(hw), facts_(facts), adc_(hw) {}

  /// Resets and calibrates the ADC, then sends INFO with why and how often the device started.
  /// An ADC that does not answer is reported (ERROR) and the device still runs: its dwells then
  /// carry RDY-timeout flags.
  void boot(const boot_info& b = {});
  /// One pass of the main loop: received bytes, the sequencer, the status timer, the UART, and
  /// the watchdog (fed only while the sequencer keeps its deadlines).
  void poll();

  [[nodiscard]] protocol::device_state state() const { return state_; }
  [[nodiscard]] const protocol::configure_msg& config() const { return cfg_; }
  [[nodiscard]] const protocol::status_msg& counters() const { return stat_; }
  [[nodiscard]] const stepper::motor& motor(uint8_t i) const { return motors_[i & 1u]; }
  [[nodiscard]] int32_t delta_n_q8() const { return delta_n_q8_; }
  /// The sequencer kept its deadlines at the last poll (what feeds the watchdog).
  [[nodiscard]] bool healthy() const { return healthy_; }

 private:
  enum class phase : uint8_t { idle, homing, turning, settling, gyro, temp };

  // link
  void receive();
  void handle(const protocol::frame& f);
  bool repeated_command(const protocol::frame& f);
  void remember_reply(const protocol::frame& f, bool acked, protocol::status why);
  void resend(const protocol::frame& f);
  void transmit();
  /// Queues message `m` whole, or drops it (counted); RAW (`droppable`) only while the ring
  /// keeps tx_reserve_bytes free for the frames that must not be lost. Data frames (DWELL,
  /// COMPENSATED, CAL_RESULT, ERROR) are also kept in the history for RESEND.
  template <class M>
  bool send(const M& m, bool droppable = false) {
    protocol::writer w{scratch_ + protocol::detail::stage + protocol::header_bytes,
                       protocol::max_payload};
    m.put(w);
    return w.ok && queue(static_cast<uint8_t>(M::type), w.n, droppable);
  }
  bool queue(uint8_t type, size_t payload_len, bool droppable);
  bool queue_staged(size_t raw_len, bool droppable);
  void ack(const protocol::frame& f);
  void nak(const protocol::frame& f, protocol::status why);
  void nak_raw(uint8_t type, uint16_t seq, protocol::status why);
  void error(protocol::status code, protocol::error_source what, uint32_t value);
  void send_info();
  void send_status();

  // health
  void check_clocks(uint32_t now);
  [[nodiscard]] bool on_schedule(uint32_t now) const;

  // sequencer
  void apply_adc_config();
  void start_run(bool by_calibrate);
  void stop_run();
  void begin_turn(uint8_t to_position, uint32_t now);
  void begin_dwell(uint32_t now);
  void step_sequencer(uint32_t now);
  void step_homing(uint32_t now);
  void step_conversion(uint32_t now, bool gyro);
  void take_result(uint32_t now, bool gyro, uint8_t ch);
  void capture_pwm();
  void finish_dwell(uint32_t now);
  void process_pair(const protocol::dwell_msg& d);
  void flush_raw();
  [[nodiscard]] stepper::ramp ramp() const;
  void set_coils(bool on);
  void write_port();
  [[nodiscard]] bool method_pair() const;

  const hal& hw_;
  board_facts facts_;
  ad7739::driver adc_;
  protocol::configure_msg cfg_{};
  // A host sent CONFIGURE since this boot: only then is START taken (a START retried from
  // before a reset names a configuration the rebooted device was never sent; docs/PROTOCOL.md).
  bool configured_ = false;
  protocol::device_state state_ = protocol::device_state::idle;
  phase phase_ = phase::idle;
  uint8_t adc_revision_ = 0;
  boot_info boot_{};

  // link state
  protocol::basic_stream_decoder<max_command_cobs> rx_{true};  // repeats: a retried command
  byte_ring<tx_ring_bytes> tx_;
  bool tx_low_nibble_ = false;  // the ring's first byte is half sent
  frame_history<history_bytes> history_;
  uint8_t scratch_[protocol::max_wire] = {};
  uint16_t tx_seq_ = 0;
  protocol::status_msg stat_{};
  uint32_t last_status_ = 0;
  // The last command executed and its reply: a retry (same sequence number, type and payload)
  // is answered again, not executed again.
  bool have_last_cmd_ = false;
  uint16_t last_cmd_seq_ = 0;
  uint8_t last_cmd_type_ = 0;
  uint16_t last_cmd_crc_ = 0;
  bool last_cmd_acked_ = false;
  uint16_t last_cmd_at_seq_ = 0;
  protocol::status last_cmd_why_ = protocol::status::ok;

  // health
  bool healthy_ = true;
  uint32_t last_ticks_ = 0;
  uint32_t polls_same_tick_ = 0;
  uint8_t clock_faults_reported_ = 0;

  // motion
  stepper::motor motors_[2];
  stepper::mover mover_;
  uint32_t home_steps_ = 0;
  uint32_t next_home_step_ = 0;
  uint32_t home_closed_since_ = 0;
  bool home_closed_ = false;
  bool home_then_run_ = false;

  // acquisition
  uint32_t conv_ticks_ = 1;     // one conversion, in ticks (rounded up)
  uint32_t timeout_ticks_ = 3;  // a RDY later than this is missing: 3 conversion times
  uint32_t settle_ticks_ = 0;   // the configuration's settle_ms and status_period_ms, in ticks
  uint32_t status_ticks_ = 0;
  uint32_t phase_start_ = 0;
  uint32_t conv_start_ = 0;
  bool converting_ = false;
  uint16_t attempts_ = 0;
  uint8_t position_ = 0;  // index into the angle table
  uint32_t gyro_index_ = 0;
  bool fault_reported_ = false;  // one ERROR per dwell for its RDY timeouts or start failures
  protocol::dwell_msg dwell_{};
  protocol::raw_msg raw_{};

  // processing (the method's pair: positions 0 and 1, 180 deg apart)
  int32_t mean_a_q8_ = 0;
  uint8_t flags_a_ = 0;
  bool have_a_ = false;  // the cycle's A dwell had at least one conversion
  int32_t delta_n_q8_ = 0;
  calibrator cal_;
  bool stop_after_cal_ = false;
  bool cal_wait_a_ = false;  // a calibration counts whole cycles that start after CALIBRATE
  bool step_fault_ = false;  // homing failed: flag the next dwell
};

}  // namespace gyroflip::fw
