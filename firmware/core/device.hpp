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
inline constexpr uint8_t fw_version_minor = 4;
inline constexpr uint8_t fw_version_patch = 0;

/// Transmit ring, in bytes of the COBS stream (each goes out as two wire bytes): a RAW frame
/// (112 B with its delimiters) plus the reserve below, plus room for what is still going out.
inline constexpr size_t tx_ring_bytes = 320;
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
/// Frames a RESEND asked for that a main-loop pass sends again at most on a port with short
/// passes (board_facts::short_passes): each costs ~5 000 MCLK cycles on the MSP430F149 (the
/// history's copy, COBS, the ring), and a RESEND of 16 answered in one pass was its longest
/// (20-27 ms, beyond the receive queue's 8.3 ms: docs/PERFORMANCE.md, "Timing on the chip").
inline constexpr int resend_per_poll = 1;
static_assert(protocol::header_bytes + protocol::dwell_payload + protocol::crc_bytes <=
              frame_history<history_bytes>::max_frame);
/// Received wire bytes a main-loop pass decodes at most (5.6 ms of line), and how many of them
/// make the pass's heavy thing on a port with short passes (~5 000 MCLK cycles on the
/// MSP430F149): a pass that decoded more leaves its INFO, RESEND frame or STATUS to the next
/// (docs/PERFORMANCE.md, "Fifth pass"). The step queue is topped up every rx_feed_bytes.
inline constexpr uint16_t rx_per_poll = 64;
inline constexpr uint16_t rx_light_bytes = 16;
inline constexpr uint16_t rx_feed_bytes = 16;
inline constexpr uint16_t rx_commanded = 0x100;  // device::receive's flag
/// A turn's first step is due this many ticks after the step timer is armed (ports with one).
inline constexpr uint32_t first_step_lead_ticks = 4;
/// Wire bytes a main-loop pass hands to the UART at most (1.4 ms of line at 115 200 b/s; passes
/// come every ~0.3 ms on the MSP430F149, so the line rarely waits for the loop).
inline constexpr size_t tx_per_poll = 16;
/// The longest payload the device sends: a RAW block of 32 codes (INFO is 92 bytes).
inline constexpr size_t max_sent_payload = protocol::raw_payload(protocol::raw_msg::max_codes);
/// The longest command frame (CONFIGURE, 54 B of payload) as COBS bytes: the receive buffer.
inline constexpr size_t max_command_cobs = 64;
/// A wait the sequencer should have ended this long ago means it is stuck: the watchdog is no
/// longer fed (ticks). A turn is stuck when no step was made for this long.
inline constexpr uint32_t stall_ticks = 8192;
/// Conversion results the /RDY interrupt may hold for the main loop: it starts the next
/// conversion only while two places are free, so the ADC is never further ahead than this.
inline constexpr uint8_t adc_queue_len = 4;
/// The AD7739 after its reset: registers are not accessed before this (docs/HARDWARE.md, "The
/// AD7739 as the firmware uses it").
inline constexpr uint32_t adc_reset_wait_ms = 1;
/// Polls without the tick counter moving before the tick clock (the 32 768 Hz crystal on the
/// MSP430F149) is declared failed: a pass takes at least ~100 MCLK cycles, so >= 0.36 s at
/// 5.5296 MHz, thousands of tick periods.
inline constexpr uint32_t frozen_tick_polls = 20000;
/// The home switch must read closed this long before homing ends (contact bounce and noise).
inline constexpr uint32_t home_debounce_ticks = 66;  // 2 ms at 32 768 Hz

/// What a port tells the core about its board.
struct board_facts {
  /// The serial when the board has no record of its own (hal_ops::nv_read, nv_board).
  uint32_t serial = 0;
  uint32_t mclk_hz = ad7739::mclk_hz_nominal;                   ///< the AD7739's master clock
  protocol::board_kind board = protocol::board_kind::hardware;  ///< INFO's `board`
  /// The highest top step rate the board's CPU and timer keep (CONFIGURE above: NAK bad_arg).
  uint16_t max_step_rate_sps = protocol::max_step_rate_sps;
  /// A main-loop pass does one heavy thing at most (a command's answer, a dwell's report, a
  /// STATUS): on a microcontroller whose UART receive queue holds a few milliseconds.
  bool short_passes = false;
};

class device {
 public:
  /// Constant-initialised (constexpr): a port's device object needs no constructor at start-up,
  /// so an image works whatever a flasher does with .init_array (docs/FIRMWARE.md).
  constexpr device(const hal& hw, const board_facts& facts) : hw_(hw), facts_(facts), adc_(hw) {}
  /// Replaces board_facts::max_step_rate_sps before boot: only the MSP430F149's simulator image
  /// (main.cpp, GYROFLIP_F149_SIM), to measure its main loop at rates its board refuses.
  void set_max_step_rate_sps(uint16_t sps) { facts_.max_step_rate_sps = sps; }

  /// Resets and calibrates the ADC, then sends INFO with why and how often the device started.
  /// An ADC that does not answer is reported (ERROR) and the device still runs: its dwells then
  /// carry RDY-timeout flags.
  void boot(const boot_info& b = {});
  /// One pass of the main loop: received bytes, the sequencer, the status timer, the UART, and
  /// the watchdog (fed only while the sequencer keeps its deadlines).
  void poll();

  /// Interrupt entry, the step timer (hal_ops::step_timer) at tick `now`: takes the step that is
  /// due and returns true with `*next_due` when the port should arm the timer again.
  bool on_step_timer(uint32_t now, uint32_t* next_due);
  /// Interrupt entry, the ADC's /RDY (hal::rdy_irq) at tick `now` (only its low 16 bits are
  /// used: a conversion's times are 16-bit tick differences, so a port may pass its timer's
  /// count alone): starts the dwell's next conversion at once and reads the result of the one
  /// that ended, so that conversions follow each other at the ADC's pace, not the main loop's.
  void on_rdy(uint32_t now);

  [[nodiscard]] protocol::device_state state() const { return state_; }
  [[nodiscard]] const protocol::configure_msg& config() const { return cfg_; }
  [[nodiscard]] const protocol::status_msg& counters() const { return stat_; }
  [[nodiscard]] const stepper::motor& motor(uint8_t i) const { return motors_[i & 1u]; }
  [[nodiscard]] int32_t delta_n_q8() const { return delta_n_q8_; }
  /// The sequencer kept its deadlines at the last poll (what feeds the watchdog).
  [[nodiscard]] bool healthy() const { return healthy_; }
  /// Times a turn paused because the main loop fell behind its steps and resumed with a new
  /// ramp from standstill (stepper::mover::rebase).
  [[nodiscard]] uint16_t step_rebases() const { return mover_.rebases(); }

 private:
  enum class phase : uint8_t { idle, calibrating, homing, turning, settling, acquiring };
  /// What follows the ADC's calibration: nothing (boot, CONFIGURE), or a run.
  enum class then : uint8_t { idle, run };

  // link
  /// Decodes received bytes (at most `most`, one command): the bytes read, plus rx_commanded
  /// when a command is to be handled now (the caller handles rx_.current(): not from inside
  /// receive, whose frame would then lie under the deepest command's, on the F149's 2 KB).
  uint16_t receive(uint16_t most);
  void handle(const protocol::frame& f);
  [[gnu::noinline]] void configure(const protocol::frame& f);
  bool repeated_command(const protocol::frame& f);
  void remember_reply(const protocol::frame& f, bool acked, protocol::status why);
  [[gnu::noinline]] void resend(const protocol::frame& f);
  /// Sends again up to `n` of the frames RESEND marked in the history, while the ring keeps
  /// tx_reserve_bytes free for the live frames; true when it sent one.
  bool answer_resend(int n);
  void transmit();
  /// Queues message `m` whole, or drops it (counted); RAW (`droppable`) only while the ring
  /// keeps tx_reserve_bytes free for the frames that must not be lost. Data frames (DWELL,
  /// COMPENSATED, CAL_RESULT, ERROR) are also kept in the history for RESEND.
  template <class M>
  bool send(const M& m, bool droppable = false) {
    protocol::writer w{scratch_ + protocol::detail::stage + protocol::header_bytes,
                       max_sent_payload};
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
  void feed_steps();
  void send_status();

  // health
  void check_clocks(uint32_t now);
  [[nodiscard]] bool on_schedule(uint32_t now) const;

  // sequencer
  void apply_timing();
  void begin_calibration(then next, uint32_t now);
  void step_calibration(uint32_t now);
  void start_run(bool by_calibrate);
  void begin_run(uint32_t now);
  void stop_run();
  void begin_turn(uint8_t to_position, uint32_t now);
  void step_turn(uint32_t now);
  void begin_dwell(uint32_t now);
  /// True when the step did a heavy part of the sequence (a report, a turn's start, a dwell's
  /// start).
  bool step_sequencer(uint32_t now);
  void step_homing(uint32_t now);
  bool step_acquisition(uint32_t now);
  void start_conversion(uint32_t now);
  bool start_next(uint32_t now);
  void account(uint32_t result);
  void push_result(uint8_t kind, int32_t code, uint8_t st);
  void missing(uint8_t flag);
  void capture_pwm();
  void finish_dwell(uint32_t now);
  void process_pair(const protocol::dwell_msg& d);
  void flush_raw();
  void set_coils(bool on);
  void write_port();
  [[nodiscard]] bool method_pair() const;
  [[nodiscard]] uint8_t channel_of(uint16_t attempt) const;
  [[nodiscard]] uint16_t conv_age(uint32_t now) const;

  // non-volatile records
  void load_records();
  void save_delta_n();

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
  // Repeats delivered (a retried command); counts in 16 bits, as STATUS carries them.
  protocol::basic_stream_decoder<max_command_cobs, uint16_t> rx_{true};
  byte_ring<tx_ring_bytes> tx_;
  bool tx_low_nibble_ = false;  // the ring's first byte is half sent
  frame_history<history_bytes> history_;
  // Frames are staged and encoded here: sized for the longest frame the device sends (RAW of 32
  // codes), not the protocol's longest (the F149's RAM: docs/PERFORMANCE.md).
  uint8_t scratch_[protocol::detail::stage + protocol::wire_bytes(max_sent_payload)] = {};
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
  // The last pass handled a command and skipped the sequencer; the last pass read many bytes and
  // left its INFO, RESEND frame or STATUS to this one, which reads few (bit-fields: the F149's
  // RAM).
  bool sequencer_waited_ : 1 = false;
  bool tail_waited_ : 1 = false;
  bool command_waits_ : 1 = false;  // a command decoded behind a long read, for the next pass
  bool info_due_ = false;           // a PING's INFO, for the next pass (short_passes)
  bool resend_due_ = false;         // frames marked in the history by RESEND wait to go out
  bool turn_due_ = false;       // a dwell reported: its turn begins in the next pass (short_passes)
  uint32_t last_progress_ = 0;  // a turn's last step (the watchdog judges a turn by its steps)
  uint32_t last_ticks_ = 0;
  uint32_t polls_same_tick_ = 0;
  uint8_t clock_faults_reported_ = 0;

  // motion
  stepper::motor motors_[2];
  stepper::mover mover_;
  stepper::ramp_plan plan_{};    // the configuration's ramp (apply_timing)
  uint32_t home_interval_ = 1;   // ticks between homing steps (the start rate)
  uint16_t seen_steps_ = 0;      // the turn's steps at the last poll
  bool step_irq_armed_ = false;  // the step timer runs this turn (ports with one)
  uint32_t home_steps_ = 0;
  uint32_t next_home_step_ = 0;
  uint32_t home_closed_since_ = 0;
  bool home_closed_ = false;
  bool home_then_run_ = false;

  // the ADC's calibration (CONFIGURE, START, boot): one step per poll, never a blocking wait
  then after_cal_ = then::idle;
  bool timing_stale_ = false;  // CONFIGURE took a configuration: apply_timing in the next pass
  uint8_t cal_step_ = 0;       // channel (bit 1) and zero/full (bit 0); 4 when done
  bool cal_waiting_ = false;
  uint32_t cal_since_ = 0;

  // acquisition
  uint32_t conv_ticks_ = 1;     // one conversion, in ticks (rounded up)
  uint32_t timeout_ticks_ = 3;  // a RDY later than this is missing: 3 conversion times
  uint32_t settle_ticks_ = 0;   // the configuration's settle_ms and status_period_ms, in ticks
  uint32_t status_ticks_ = 0;
  uint32_t phase_start_ = 0;
  bool coils_released_ = false;  // settling: the coils are off for its second half
  // Shared with on_rdy (the /RDY interrupt): written by the main loop only in a critical section
  // or while no conversion runs (on_rdy acts only while one does).
  bool converting_ = false;
  uint16_t conv_start_ = 0;  // tick (low 16 bits) the running conversion started
  uint16_t planned_ = 0;     // conversions of this dwell: n_avg gyro, then n_temp temperature
  uint16_t started_ = 0;     // conversions started (or failed to start) so far
  // A result for the main loop: the 24-bit code, and in the top byte its kind (bits 7:6) and the
  // channel status's NOREF and OVR bits (sequencer.cpp).
  uint32_t results_[adc_queue_len] = {};
  uint8_t res_head_ = 0;   // main loop
  uint8_t res_tail_ = 0;   // on_rdy
  uint16_t attempts_ = 0;  // outcomes accounted by the main loop
  uint8_t position_ = 0;   // index into the angle table
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

  // non-volatile records and retained counters (INFO)
  uint8_t stored_ = 0;          // protocol::info_stored bits
  uint32_t serial_ = 0;         // the board's record, or facts_.serial
  bool delta_n_dirty_ = false;  // dN changed: saved when the device is next idle
};

}  // namespace gyroflip::fw
