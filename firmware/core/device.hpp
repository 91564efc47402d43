/// \file
/// \brief The rig's firmware core (docs/FIRMWARE.md): the sequencer (turn -> settle -> acquire
/// N -> report -> turn), the sampler (AD7739 conversions with a bounded RDY wait, PWM tilt
/// capture), the link (commands in, frames out through a transmit ring that never blocks) and
/// the on-board processing. One object, no allocation, no global state; a port creates it with
/// its HAL and calls poll() from its main loop.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "firmware/core/budget.hpp"
#include "firmware/core/processing.hpp"
#include "firmware/drivers/ad7739/ad7739.hpp"
#include "firmware/drivers/stepper/stepper.hpp"
#include "firmware/hal/hal.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/util/ring.hpp"

namespace gyroflip::fw {

inline constexpr uint8_t fw_version_major = 0;
inline constexpr uint8_t fw_version_minor = 1;
inline constexpr uint8_t fw_version_patch = 0;
inline constexpr uint16_t max_n_avg = 65535;
inline constexpr uint8_t max_n_temp = 64;
inline constexpr uint16_t max_step_rate_sps = 5000;
inline constexpr uint16_t max_status_period_ms = 60000;
/// Transmit ring: a RAW frame (206 B) plus room for the frames that must not be dropped.
inline constexpr size_t tx_ring_bytes = 512;
/// Room a RAW frame must leave in the ring for two DWELLs, a COMPENSATED and a STATUS (RAW is
/// dropped first when the link falls behind).
inline constexpr size_t tx_reserve_bytes = 2 * protocol::wire_bytes(dwell_payload) +
                                           protocol::wire_bytes(compensated_payload) +
                                           protocol::wire_bytes(status_payload);

/// What a port tells the core about its board.
struct board_facts {
  uint32_t serial = 0;
  uint32_t mclk_hz = ad7739::mclk_hz_nominal;  ///< the AD7739's master clock
};

/// Why CONFIGURE was refused (status::bad_arg), for NAK and tests.
[[nodiscard]] protocol::status check_config(const protocol::configure_msg& c, uint32_t mclk_hz);

class device {
 public:
  /// Constant-initialised (constexpr): a port's device object needs no constructor at start-up,
  /// so an image works whatever a flasher does with .init_array (docs/FIRMWARE.md).
  constexpr device(const hal& hw, const board_facts& facts) : hw_(hw), facts_(facts), adc_(hw) {}

  /// Resets and calibrates the ADC, then sends INFO. An ADC that does not answer is reported
  /// (ERROR) and the device still runs: its dwells then carry RDY-timeout flags.
  void boot();
  /// One pass of the main loop: received bytes, the sequencer, the status timer, the UART.
  void poll();

  [[nodiscard]] protocol::device_state state() const { return state_; }
  [[nodiscard]] const protocol::configure_msg& config() const { return cfg_; }
  [[nodiscard]] const protocol::status_msg& counters() const { return stat_; }
  [[nodiscard]] const stepper::motor& motor(uint8_t i) const { return motors_[i & 1u]; }
  [[nodiscard]] int32_t delta_n_q8() const { return delta_n_q8_; }

 private:
  enum class phase : uint8_t { idle, homing, turning, settling, gyro, temp };

  // link
  void receive();
  void handle(const protocol::frame& f);
  void transmit();
  /// Queues message `m` whole, or drops it (counted); RAW (`droppable`) only while the ring
  /// keeps tx_reserve_bytes free for the frames that must not be lost.
  template <class M>
  bool send(const M& m, bool droppable = false) {
    return queue(protocol::encode_message(m, tx_seq_, scratch_, sizeof scratch_), droppable);
  }
  bool queue(size_t n, bool droppable);
  void ack(const protocol::frame& f);
  void nak(const protocol::frame& f, protocol::status why);
  void error(protocol::status code, protocol::error_source what, uint32_t value);
  void send_info();
  void send_status();

  // sequencer
  void apply_adc_config();
  void start_run(bool by_calibrate);
  void stop_run();
  void begin_turn(int32_t steps, uint32_t now);
  void begin_dwell(uint32_t now);
  void step_sequencer(uint32_t now);
  void step_conversion(uint32_t now, bool gyro);
  void capture_pwm();
  void finish_dwell(uint32_t now);
  void flush_raw();
  [[nodiscard]] int32_t turn_steps(uint8_t to_position) const;
  [[nodiscard]] stepper::ramp ramp() const;
  void write_port();

  const hal& hw_;
  board_facts facts_;
  ad7739::driver adc_;
  protocol::configure_msg cfg_{};
  protocol::device_state state_ = protocol::device_state::idle;
  phase phase_ = phase::idle;
  uint8_t adc_revision_ = 0;

  // link state
  protocol::frame_decoder rx_{true};  // commands: a restarted host's numbering is obeyed
  byte_ring<tx_ring_bytes> tx_;
  uint8_t scratch_[protocol::max_wire] = {};
  uint16_t tx_seq_ = 0;
  protocol::status_msg stat_{};
  uint32_t last_status_ = 0;

  // motion
  stepper::motor motors_[2];
  stepper::mover mover_;
  uint32_t home_steps_ = 0;
  uint32_t next_home_step_ = 0;
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
  uint8_t position_ = 0;  // 0: A, 1: B
  uint32_t gyro_index_ = 0;
  bool timeout_reported_ = false;
  protocol::dwell_msg dwell_{};
  protocol::raw_msg raw_{};

  // processing
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
