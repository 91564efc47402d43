/// \file
/// \brief The rig without hardware: the firmware core (firmware/core, host port) driving
/// simulated hardware, one tick of its clock at a time (docs/EMULATOR.md).
///
/// Behind the HAL: the register-level AD7739 model (firmware/ports/host/ad7739_model.hpp, the
/// one the firmware tests use) whose codes come from the simulator's physics, the same objects
/// `simulate` uses: the gyro (sensor/gyro.hpp), the ADC's noise and quantisation
/// (rig/ad7739.hpp), the site and axes (rig/geometry.hpp), the rate and temperature profiles.
/// The table is motor 0 of the stepper port: its angle is the decoded step position times
/// 360 deg / steps per revolution from the home switch (at step 0). The gyro runs on a grid of
/// conversion times also while no conversion runs, so it sees the table's rate during a turn
/// and its low-pass filter settles as the real part's would; each conversion samples it over
/// its own window:
///   w(t) = g_in(a) w_in(t) + g_tab(a) dangle/dt + earth(a) + (g0 + g1 (T - T_ref)) . f(a)
/// with a the table step (rig/geometry.hpp terms at that angle). Channel 1 carries the
/// ADXRS150-style temperature output, 8.4 mV/K about 2.50 V at 298 K (docs/FACTS.md §9; [U]), and
/// the two PWM inputs an ADXL202 on the table, x and y along the sensor's x and y axes, duty
/// 0.5 + 0.125 f/g (data sheet p. 1).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "firmware/core/device.hpp"
#include "firmware/ports/host/board.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/rig/profiles.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/gyro.hpp"

namespace gyroflip::host {

/// The emulated rig. From `sim`: the sensor, site and axes, rate and temperature profiles, the
/// ADC's clock, filter word, chop and noise, the power-on time, the seed, the mount (an azimuth,
/// a tilt: rig/geometry.hpp) and the table's steps per revolution; the schedule and the duration
/// are the firmware's and the host's.
struct emulator_config {
  rig::simulation_config sim;
  std::uint32_t serial = 1;      ///< the device's serial number (INFO)
  double accel_period_s = 1e-3;  ///< ADXL202 T2 (R_SET = 125 kOhm; data sheet p. 1)
  /// The capture timer's clock: 1 MHz, a whole number of counts per 1-ms period (the F149
  /// board's Timer_B runs at SMCLK/8 = 691.2 kHz, where a 1-ms period is 691 counts and a 50 %
  /// duty would read 0.5007 with the model's exact edges).
  double accel_capture_hz = 1.0e6;
};

/// The terms an indexed run should find (issue 33 item 2), as the gyro senses them (deg/s): the
/// Earth term and the g-term at each table angle theta are a constant plus a first harmonic,
/// earth(theta) + g(theta) = mean + c1 cos(theta) + s1 sin(theta), no second harmonic. The
/// harmonic fit's c1, s1 (method/harmonic.hpp) are earth_c1 + g_c1 and earth_s1 + g_s1; its b is
/// the gyro's bias plus `mean`.
struct harmonic_truth {
  double earth_c1_dps = 0.0, earth_s1_dps = 0.0;
  double g_c1_dps = 0.0, g_s1_dps = 0.0;
  double mean_dps = 0.0;  ///< the Earth term and g-term's mean over the table angle
  [[nodiscard]] double c1_dps() const noexcept { return earth_c1_dps + g_c1_dps; }
  [[nodiscard]] double s1_dps() const noexcept { return earth_s1_dps + g_s1_dps; }
};

class emulator {
 public:
  static constexpr std::uint32_t tick_hz = fw::model::host_board::tick_hz;

  /// Errors: those of the simulator's parts (sensor, ADC, geometry, profiles), and an ADC clock
  /// outside 1..10 MHz.
  [[nodiscard]] static result<std::unique_ptr<emulator>> make(const emulator_config& c);
  emulator(const emulator&) = delete;
  emulator& operator=(const emulator&) = delete;
  ~emulator();

  /// Boots the firmware: it resets and calibrates the ADC and sends INFO.
  void boot();
  /// Resets the microcontroller (firmware state lost, its boot counter kept) and boots it
  /// again; the table, the sensor and the line keep their state.
  void reset();
  /// Runs `n` ticks of the device clock, one main-loop pass per tick.
  void run(std::uint32_t n);

  /// Bytes from the host, as many as the device's receive queue takes (1 KB, emptied at the
  /// line's rate): how many (the rest waits, as in a UART's FIFO and the host's buffer).
  std::size_t send(const std::uint8_t* p, std::size_t n);
  /// Takes up to `cap` bytes the device has sent.
  std::size_t receive(std::uint8_t* out, std::size_t cap);

  [[nodiscard]] std::uint64_t ticks() const noexcept { return ticks_; }
  /// How often the firmware booted (1 at the first boot; INFO's boot_count).
  [[nodiscard]] std::uint16_t boots() const noexcept { return boots_; }
  /// The boot that ran at board tick `board_ticks` (the board's 32-bit clock, as a DWELL's
  /// t_end_ticks: within 2^32 ticks before now): the boot that made a DWELL, also when the frame
  /// first goes out after a reset (review of issue 32, fifth pass, finding 5: a DWELL held in
  /// the transmitter across a reset was logged with the new boot).
  [[nodiscard]] std::uint16_t boot_at(std::uint32_t board_ticks) const noexcept;
  [[nodiscard]] double time_s() const noexcept { return static_cast<double>(ticks_) / tick_hz; }
  [[nodiscard]] const fw::device& device() const noexcept;
  /// The table's angle (deg, in [0, 360)) now.
  [[nodiscard]] double table_angle_deg() const noexcept;
  /// The table's angle (deg) at the last gyro conversion.
  [[nodiscard]] double last_conversion_table_deg() const noexcept { return conv_table_deg_; }
  /// The table's angle (deg) at the last gyro conversion made at or before device tick
  /// `board_ticks` (the board's 32-bit clock, as a DWELL's t_end_ticks: within 2^32 ticks before
  /// now); NaN when no conversion that early is held (the angles of the last 4 096 turns are).
  /// A DWELL's true position: what its own conversions saw, also when the frame first goes out
  /// long after it ended (dropped from a full transmit ring and sent on RESEND after the table
  /// turned on: the angle of the last conversion then is the next dwell's).
  [[nodiscard]] double table_deg_at(std::uint32_t board_ticks) const noexcept;
  /// Holds the UART's transmitter (a stuck transmitter or a held CTS): the firmware's transmit
  /// ring fills and the frames it makes meanwhile that do not fit are dropped from the live
  /// stream (kept in its history: docs/PROTOCOL.md, RESEND).
  void hold_transmitter(bool on) noexcept;
  /// Earth term plus g-term at `temp_c`, half the difference of positions A (0 deg) and B
  /// (180 deg): the dN a calibration should find (paper eqn 11), as the gyro senses it (deg/s).
  [[nodiscard]] double delta_n_truth_dps(double temp_c) const noexcept;
  /// The first harmonic over the table angle of the Earth term and g-term at `temp_c`, from
  /// every table step (their Fourier coefficients): what an indexed run's c1 and s1 should find,
  /// for any angle table (for 0/180, c1 is delta_n_truth_dps).
  [[nodiscard]] harmonic_truth harmonic_truth_at(double temp_c) const noexcept;
  [[nodiscard]] const emulator_config& config() const noexcept { return cfg_; }

 private:
  struct parts;
  emulator(const emulator_config& c, std::unique_ptr<parts> p);
  static std::int32_t source(void* ctx, std::uint8_t ch, std::uint32_t index);
  std::int32_t gyro_code(double t_end_s);
  std::int32_t temp_code(double t_s);
  /// One gyro window centred at `t_s` at the table's step now; its output voltage.
  double sample_gyro(double t_s);
  double coil_heat_c(double t_s);
  void update_accel();
  [[nodiscard]] std::size_t step_index() const noexcept;

  emulator_config cfg_;
  std::unique_ptr<parts> p_;
  std::uint64_t ticks_ = 0;
  std::uint64_t next_idle_sample_ = 0;  // tick at which an idle gyro window is due
  double t_last_s_ = 0.0;               // centre of the last gyro window
  std::int32_t pos_last_ = 0;           // table step at that window
  std::int32_t pos_accel_ = -1;         // table step the accelerometer outputs were set for
  double conv_table_deg_ = 0.0;         // table angle at the last gyro conversion
  // (tick, angle) of each gyro conversion whose angle differs from the one before: the table's
  // stations in time, oldest first (table_deg_at).
  std::vector<std::pair<std::uint64_t, double>> stations_;
  double heat_c_ = 0.0;  // the coils' temperature rise at heat_t_s_
  double heat_t_s_ = 0.0;
  std::uint16_t boots_ = 0;               // the device's boot counter
  std::vector<std::uint64_t> resets_at_;  // ticks of each reset since boot(), ascending
};

}  // namespace gyroflip::host
