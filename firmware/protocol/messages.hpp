/// \file
/// \brief Every message of the rig protocol, byte by byte (docs/PROTOCOL.md): a struct per
/// message with its type id, its layout seed (`crc_extra`, MAVLink v2's CRC_EXTRA idea: a peer
/// that knows another layout of a message gets a CRC mismatch, never a misread) and its
/// little-endian encoding. Freestanding: no heap, no standard library.
///
/// Units on the wire are the device's own: signed ADC codes (the AD7739's offset-binary code
/// minus 2^23, so 0 is 0 V), timer ticks (INFO's tick_hz), stepper steps, milliseconds; the host
/// converts with INFO's figures.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "crc16.hpp"
#include "wire.hpp"

namespace gyroflip::protocol {

/// The message ids (one byte; 0x01-0x1F device to host, 0x20-0x3F host to device).
enum class msg : uint8_t {
  info = 0x01,
  dwell = 0x10,
  raw = 0x11,
  status = 0x12,
  error = 0x13,
  ack = 0x14,
  nak = 0x15,
  compensated = 0x16,
  cal_result = 0x17,
  gone = 0x18,
  ping = 0x20,
  configure = 0x21,
  start = 0x22,
  stop = 0x23,
  home = 0x24,
  set_delta_n = 0x25,
  calibrate = 0x26,
  resend = 0x27,
};

/// The layout seed of a message: CRC-16/CCITT-FALSE of its layout text (name and fields in
/// order), folded to one byte. Changing a field changes the seed, and so every CRC of that
/// message.
[[nodiscard]] constexpr uint8_t layout_seed(const char* layout) {
  uint16_t c = crc16_init;
  for (size_t i = 0; layout[i] != 0; ++i) c = crc16_byte(c, static_cast<uint8_t>(layout[i]));
  return static_cast<uint8_t>((c >> 8) ^ (c & 0xFFu));
}

/// Bits of `configure_msg::flags`.
enum config_flag : uint8_t {
  cfg_chop = 0x01,        ///< AD7739 chopping on (CHOP bit of the conversion-time register)
  cfg_raw = 0x02,         ///< send RAW blocks (every gyro conversion)
  cfg_one_way = 0x04,     ///< turn A->B->A always the same way (rotary joint) instead of back
  cfg_home = 0x08,        ///< find the home switch before the first cycle
  cfg_compensate = 0x10,  ///< send COMPENSATED per cycle (r - dN, dN from SET_DELTA_N/CALIBRATE)
  /// Keep the flip motor's coils energised during dwells and while idle. Off by default: the
  /// coils are switched off once a turn has settled, because a two-phase-on hold heats the
  /// table under the gyro (docs/HARDWARE.md, "Stepper holding current").
  cfg_hold_coils = 0x20,
};
inline constexpr uint8_t cfg_all = 0x3F;

/// Positions a CONFIGURE can hold (the dwell sequence visits 0, 1, ..., n_positions - 1, 0, ...).
inline constexpr uint8_t max_positions = 8;
/// Angles in CONFIGURE are in hundredths of a degree, 0 .. 35 999.
inline constexpr uint16_t centidegrees_per_turn = 36000;

/// Frames RESEND can ask for: the run's data, and the errors that explain gaps in it. ACK, NAK,
/// INFO, STATUS and GONE are answers or snapshots (asked for again, not resent); RAW is too large
/// for the history (docs/PROTOCOL.md, RESEND).
[[nodiscard]] constexpr bool kept_for_resend(uint8_t type) {
  switch (static_cast<msg>(type)) {
    case msg::dwell:
    case msg::compensated:
    case msg::cal_result:
    case msg::error:
      return true;
    default:
      return false;
  }
}

/// What the motor that does not flip does (`configure_msg::other_motor`).
enum class other_motor : uint8_t {
  off = 0,       ///< coils de-energised
  hold = 1,      ///< energised at its phase (holds a second axis)
  same = 2,      ///< turns with the flipping motor, same direction
  opposite = 3,  ///< turns with the flipping motor, opposite direction
};

/// Bits of `dwell_msg::flags`.
enum dwell_flag : uint8_t {
  dwell_adc_clip = 0x01,     ///< a code at the ADC's full scale in this dwell
  dwell_rdy_timeout = 0x02,  ///< RDY did not come within 3 conversion times (a code missing)
  dwell_step_fault = 0x04,   ///< the turn before this dwell did not reach its position
  dwell_raw_dropped = 0x08,  ///< a RAW block of this dwell did not fit the transmit buffer
  /// A conversion result was not taken: the AD7739 said it was not this channel's new result
  /// (RDY was still low from an earlier one) or it came before its conversion time
  dwell_stale = 0x10,
  dwell_noref = 0x20,         ///< the AD7739 flagged its reference missing (NOREF) in a result
  dwell_start_failed = 0x40,  ///< a conversion could not be started (the SPI bus failed)
};

/// The device's states (`status_msg::state`).
enum class device_state : uint8_t { idle = 0, homing = 1, running = 2, fault = 3 };

/// The parts an ERROR names (`error_msg::what`).
enum class error_source : uint8_t { adc = 1, stepper = 2, link = 3, configuration = 4, clock = 5 };

/// Why the device last started (`info_msg::reset_cause`), as its microcontroller tells it.
enum class reset_cause : uint8_t {
  unknown = 0,
  power_on = 1,   ///< power applied (or a brown-out)
  watchdog = 2,   ///< the watchdog expired: the firmware stopped making progress
  reset_pin = 3,  ///< the reset pin (a debugger, a button)
  other = 4,      ///< another reset (a flash or watchdog key violation)
};

/// What sends INFO (`info_msg::board`): a rig's board, or a machine that only imitates one. Data
/// from anything but a board is not a measurement (a report says "simulated data").
enum class board_kind : uint8_t {
  hardware = 0,       ///< a real controller board (the MSP430F149 port)
  host_emulator = 1,  ///< gyroflip's emulator: the firmware on the host port's simulated rig
  qemu = 2,           ///< the Cortex-M3 image under QEMU
};

/// Bits of `info_msg::stored`.
enum info_stored : uint8_t {
  /// `serial` is the board's own, read from its information flash with a good CRC (else the
  /// port's default: 0 on the MSP430F149, "not programmed").
  info_serial_stored = 0x01,
  /// The dN in force at boot came from the information flash (a good record; else 0).
  info_delta_n_stored = 0x02,
  /// `prev_next_seq` and `prev_dwells` are the previous boot's (a reset that kept RAM); clear
  /// after a power-up, when they are 0 and unknown.
  info_prev_valid = 0x04,
};

/// Bits of `status_msg::clock_faults` (and ERROR clock values).
enum clock_fault : uint8_t {
  clock_xt2 = 0x01,    ///< the high-frequency crystal (MCLK, SMCLK: UART baud, SPI) failed
  clock_lfxt1 = 0x02,  ///< the 32 768 Hz crystal (ACLK: the tick counter) failed
};

/// CONFIGURE (host to device), also the second half of INFO. Defaults: the paper's rig.
struct configure_msg {
  static constexpr msg type = msg::configure;
  static constexpr const char* layout =
      "configure:u16 n_avg;u8 n_temp;u16 settle_ms;u8 n_positions;i16 pos_steps[8];"
      "u16 pos_cdeg[8];u16 steps_per_rev;u16 step_rate_sps;u16 start_rate_sps;u16 ramp_sps2;"
      "u8 filter_word;u8 flags;u8 flip_motor;u8 other_motor;u8 gyro_channel;u8 temp_channel;"
      "u16 status_period_ms";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint16_t n_avg = 256;     ///< gyro conversions per dwell (paper: 256)
  uint8_t n_temp = 4;       ///< temperature conversions per dwell, after the gyro's
  uint16_t settle_ms = 80;  ///< wait after a turn before the first conversion
  uint8_t n_positions = 2;  ///< positions in the angle table, 2..max_positions
  /// The angle table: each position in steps of the flip motor (from home) and the table angle
  /// it stands for in hundredths of a degree. A DWELL's `position` is an index into it. Default:
  /// A = 0 deg at step 0, B = 180 deg at step 100 (200 steps per revolution).
  int16_t pos_steps[max_positions] = {0, 100};
  uint16_t pos_cdeg[max_positions] = {0, 18000};
  uint16_t steps_per_rev = 200;      ///< full steps per turn of the table
  uint16_t step_rate_sps = 400;      ///< top step rate
  uint16_t start_rate_sps = 200;     ///< first step rate of the ramp (the simulator's pull-in rate)
  uint16_t ramp_sps2 = 2000;         ///< acceleration (steps/s^2)
  uint8_t filter_word = 94;          ///< AD7739 FW (~2 ms with chop: docs/HARDWARE.md)
  uint8_t flags = cfg_chop;          ///< config_flag bits
  uint8_t flip_motor = 0;            ///< 0: low nibble of the port, 1: high nibble
  uint8_t other_motor = 0;           ///< an other_motor value
  uint8_t gyro_channel = 0;          ///< AD7739 channel of the gyro (differential pair AIN0/AIN1)
  uint8_t temp_channel = 1;          ///< AD7739 channel of the temperature output (AIN2/AIN3)
  uint16_t status_period_ms = 1000;  ///< STATUS every this many ms (0: only on request)
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const configure_msg&) const = default;
};

/// Whether an angle table is the method's pair (docs/METHOD-NOTES.md): two positions 180 deg
/// apart, the only table whose cycles the device compensates on board. The one rule of the
/// device (COMPENSATE and its cycles) and of the host's rig settings (rig::rig_config, which
/// `simulate`, `emulate` and `record` check), in hundredths of a degree as the device keeps them.
constexpr bool is_method_pair(const configure_msg& c) {
  const int32_t d = int32_t{c.pos_cdeg[1]} - int32_t{c.pos_cdeg[0]};
  const int32_t half = centidegrees_per_turn / 2;
  return c.n_positions == 2 && (d == half || d == -half);
}

/// INFO's fields before the configuration (a device fills these and writes the configuration in
/// force after them, without a second copy of it on its stack).
struct info_head {
  uint8_t fw_major = 0, fw_minor = 0, fw_patch = 0, protocol = 0;
  uint32_t serial = 0;
  uint32_t mclk_hz = 0;        ///< AD7739 master clock
  uint32_t tick_hz = 0;        ///< device timestamps' tick rate
  uint8_t adc_revision = 0;    ///< AD7739 revision register as read at boot (0: no ADC)
  uint16_t max_n_avg = 0;      ///< largest n_avg this firmware accepts
  uint8_t max_raw_codes = 0;   ///< codes per RAW block
  uint8_t range = 0;           ///< AD7739 channel-setup range code (4: +-2.5 V)
  uint8_t reset_cause = 0;     ///< a reset_cause value: why the device last started
  uint16_t boot_count = 0;     ///< starts since power-on (wraps); a change means it rebooted
  uint16_t history_bytes = 0;  ///< size of the retransmit history (docs/PROTOCOL.md, RESEND)
  uint8_t board = 0;           ///< a board_kind value: a real board, or an emulator
  uint8_t stored = 0;      ///< info_stored bits: where serial, dN and the prev_ fields came from
  int32_t delta_n_q8 = 0;  ///< the dN in force (SET_DELTA_N, CALIBRATE, or the stored one)
  /// The previous boot's next sequence number and the DWELLs it sent (valid with
  /// info_prev_valid: a reset that kept RAM): a host counts what it never received of them.
  uint16_t prev_next_seq = 0;
  uint32_t prev_dwells = 0;
  void put_head(writer& w) const;
  void get_head(reader& r);
  bool operator==(const info_head&) const = default;
};

/// INFO / HELLO (device to host): at boot and in reply to PING.
struct info_msg : info_head {
  static constexpr msg type = msg::info;
  static constexpr const char* layout =
      "info:u8 fw_major;u8 fw_minor;u8 fw_patch;u8 protocol;u32 serial;u32 mclk_hz;"
      "u32 tick_hz;u8 adc_revision;u16 max_n_avg;u8 max_raw_codes;u8 range;u8 reset_cause;"
      "u16 boot_count;u16 history_bytes;u8 board;u8 stored;i32 delta_n_q8;u16 prev_next_seq;"
      "u32 prev_dwells;configure";
  static constexpr uint8_t crc_extra =
      static_cast<uint8_t>(layout_seed(layout) ^ configure_msg::crc_extra);
  configure_msg config;  ///< the configuration in force
  void put(writer& w) const {
    put_head(w);
    config.put(w);
  }
  void get(reader& r) {
    get_head(r);
    config.get(r);
  }
  bool operator==(const info_msg&) const = default;
};

/// DWELL (device to host): one position's acquisition, sent when its last conversion is read.
struct dwell_msg {
  static constexpr msg type = msg::dwell;
  static constexpr const char* layout =
      "dwell:u32 cycle;u8 position;u8 flags;u32 t_start_ticks;u32 t_end_ticks;u16 n;"
      "i48 code_sum;i24 code_min;i24 code_max;u8 n_temp;i32 temp_sum;u32 ax_high_ticks;"
      "u32 ax_period_ticks;u32 ay_high_ticks;u32 ay_period_ticks";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint32_t cycle = 0;    ///< cycle index (a cycle is one dwell at each position)
  uint8_t position = 0;  ///< index into CONFIGURE's angle table (default: 0 = A 0 deg, 1 = B 180)
  uint8_t flags = 0;     ///< dwell_flag bits
  uint32_t t_start_ticks = 0, t_end_ticks = 0;  ///< first conversion started, last one read
  uint16_t n = 0;        ///< gyro conversions in the sum (n_avg less RDY timeouts)
  int64_t code_sum = 0;  ///< sum of the gyro channel's signed codes (mean = code_sum / n)
  int32_t code_min = 0, code_max = 0;
  uint8_t n_temp = 0;    ///< temperature conversions in temp_sum
  int32_t temp_sum = 0;  ///< sum of the temperature channel's signed codes
  /// PWM accelerometer (ADXL202-class, docs/HARDWARE.md): high time T1 and period T2 of each
  /// axis, summed over the periods captured during the dwell, in timer ticks. The duty cycle is
  /// high / period; 0 when no period was captured.
  uint32_t ax_high_ticks = 0, ax_period_ticks = 0, ay_high_ticks = 0, ay_period_ticks = 0;
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const dwell_msg&) const = default;
};

/// Acceleration (milli-g, rounded to nearest) of an ADXL202/ADXL210-class duty-cycle output from
/// its summed high time T1 and period T2: A = (T1/T2 - 0.5) / 12.5 % (ADXL202/ADXL210 data sheet
/// Rev. B, p. 1; docs/FACTS.md section 9). Nominal offset and scale: each part's own are
/// calibrated (AD AN-604). 0 when no period was captured. For the host; the device never divides.
constexpr int32_t adxl202_accel_mg(uint32_t high_ticks, uint32_t period_ticks) {
  if (period_ticks == 0) return 0;
  if (high_ticks > period_ticks) high_ticks = period_ticks;  // no duty above 100 %: +4000 mg
  // 1000 mg * (T1/T2 - 1/2) * 8 = (8000 T1 - 4000 T2) / T2, exact in 64 bits for any u32 sums.
  const int64_t num =
      8000 * static_cast<int64_t>(high_ticks) - 4000 * static_cast<int64_t>(period_ticks);
  const int64_t den = period_ticks;
  return static_cast<int32_t>((num >= 0 ? num + den / 2 : num - den / 2) / den);
}

/// RAW (device to host): consecutive gyro codes, packed 3 bytes each.
struct raw_msg {
  static constexpr msg type = msg::raw;
  static constexpr const char* layout = "raw:u32 first_index;u8 count;i24 codes[count]";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  static constexpr uint8_t max_codes = 32;
  uint32_t first_index = 0;  ///< index of the first code in the run's count of gyro conversions
  uint8_t count = 0;
  uint8_t packed[3 * max_codes] = {};
  void set(uint8_t i, int32_t code) {
    writer w{packed + size_t{3} * i, 3};
    w.i24(code);
  }
  [[nodiscard]] int32_t code(uint8_t i) const {
    reader r{packed + size_t{3} * i, 3};
    return r.i24();
  }
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const raw_msg&) const = default;
};

/// STATUS (device to host): every status_period_ms and in reply to a STOP.
struct status_msg {
  static constexpr msg type = msg::status;
  static constexpr const char* layout =
      "status:u8 state;u32 uptime_ticks;u32 cycle;u32 frames_sent;u16 frames_dropped;"
      "u16 rx_frames_ok;u16 rx_errors;u16 rdy_timeouts;u8 last_error;u16 retransmits;"
      "u16 history_oldest;u16 line_corrected;u16 line_uncorrectable;u16 start_failures;"
      "u16 stale_results;u16 stack_free;u8 clock_faults;u16 boot_count";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint8_t state = 0;  ///< a device_state
  uint32_t uptime_ticks = 0;
  uint32_t cycle = 0;
  uint32_t frames_sent = 0;
  uint16_t frames_dropped = 0;  ///< frames that did not fit the transmit buffer (RAW first)
  uint16_t rx_frames_ok = 0, rx_errors = 0;
  uint16_t rdy_timeouts = 0;
  uint8_t last_error = 0;           ///< a status code
  uint16_t retransmits = 0;         ///< frames sent again on RESEND
  uint16_t history_oldest = 0;      ///< sequence number of the oldest frame RESEND can still send
  uint16_t line_corrected = 0;      ///< received wire bytes with a bit corrected by the line code
  uint16_t line_uncorrectable = 0;  ///< received wire bytes beyond correction
  uint16_t start_failures = 0;      ///< conversions that could not be started (SPI failure)
  uint16_t stale_results = 0;       ///< conversion results refused as not new (dwell_stale)
  uint16_t stack_free = 0;   ///< stack bytes never used since boot (the high-water mark's margin)
  uint8_t clock_faults = 0;  ///< clock_fault bits seen since boot
  /// INFO's boot_count: a host whose boot INFO was lost still sees the device restarted.
  uint16_t boot_count = 0;
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const status_msg&) const = default;
};

/// ERROR (device to host): a fault the device recovered from, or the reason it stopped.
struct error_msg {
  static constexpr msg type = msg::error;
  static constexpr const char* layout = "error:u8 code;u8 what;u32 value";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint8_t code = 0;  ///< a status code
  uint8_t what = 0;  ///< an error_source
  uint32_t value = 0;
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const error_msg&) const = default;
};

/// GONE (device to host): these sequence numbers will never be sent (again): a RESEND asked for
/// frames the device no longer holds, or never kept (RAW, ACK, STATUS, ...). The host records
/// them as lost.
struct gone_msg {
  static constexpr msg type = msg::gone;
  static constexpr const char* layout = "gone:u8 count;u16 seqs[count]";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  static constexpr uint8_t max_seqs = 16;
  uint8_t count = 0;
  uint16_t seqs[max_seqs] = {};
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const gone_msg&) const = default;
};

/// RESEND (host to device): send these frames again (their sequence numbers as first sent). The
/// frames themselves are the answer; those the device no longer holds come back in a GONE. Not
/// acknowledged.
struct resend_msg {
  static constexpr msg type = msg::resend;
  static constexpr const char* layout = "resend:u8 count;u16 seqs[count]";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  static constexpr uint8_t max_seqs = 16;
  uint8_t count = 0;
  uint16_t seqs[max_seqs] = {};
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const resend_msg&) const = default;
};

/// ACK (device to host): the command with this sequence number and type was done.
struct ack_msg {
  static constexpr msg type = msg::ack;
  static constexpr const char* layout = "ack:u16 seq;u8 of_type;u16 at_seq";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint16_t seq = 0;
  uint8_t of_type = 0;
  /// The device's sequence number of the command's first ACK: when it was done. The ACK of a
  /// retry names the first one, so a host whose first ACK was lost still knows where a run
  /// began (docs/PROTOCOL.md, Commands).
  uint16_t at_seq = 0;
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const ack_msg&) const = default;
};

/// NAK (device to host): the command was refused, with a status code.
struct nak_msg {
  static constexpr msg type = msg::nak;
  static constexpr const char* layout = "nak:u16 seq;u8 of_type;u8 reason";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint16_t seq = 0;
  uint8_t of_type = 0;
  uint8_t reason = 0;  ///< a status code
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const nak_msg&) const = default;
};

/// COMPENSATED (device to host): one cycle's rate with the bias removed and dN subtracted,
/// w = (y_A - y_B) / 2 - dN (paper eqns 7 and 12), in ADC codes x 256.
struct compensated_msg {
  static constexpr msg type = msg::compensated;
  static constexpr const char* layout = "compensated:u32 cycle;i32 rate_q8;i32 bias_q8;u8 flags";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint32_t cycle = 0;
  int32_t rate_q8 = 0;  ///< r - dN, codes x 256
  int32_t bias_q8 = 0;  ///< c = (y_A + y_B) / 2, codes x 256 (the bias itself, paper eqn 7)
  uint8_t flags = 0;    ///< the OR of both dwells' flags
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const compensated_msg&) const = default;
};

/// CAL_RESULT (device to host): dN = mean of r over K cycles (paper eqns 8-11), its sample
/// standard deviation, in ADC codes x 256; the device uses dN from then on.
struct cal_result_msg {
  static constexpr msg type = msg::cal_result;
  static constexpr const char* layout = "cal_result:u16 cycles;i32 delta_n_q8;u32 std_q8;u8 flags";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint16_t cycles = 0;
  int32_t delta_n_q8 = 0;
  uint32_t std_q8 = 0;
  uint8_t flags = 0;  ///< the OR of the dwells' flags over the calibration
  void put(writer& w) const;
  void get(reader& r);
  bool operator==(const cal_result_msg&) const = default;
};

struct ping_msg {
  static constexpr msg type = msg::ping;
  static constexpr const char* layout = "ping:";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  void put(writer&) const {}
  void get(reader&) {}
  bool operator==(const ping_msg&) const = default;
};

/// START (host to device): starts a run from cycle 0 if the device's configuration is the one
/// whose config_crc this carries (configure_crc); otherwise NAK config_mismatch. A START sent
/// before a device reset and arriving after it therefore never starts the rebooted device on
/// its default configuration (its table not homed: every position mislabelled).
struct start_msg {
  static constexpr msg type = msg::start;
  static constexpr const char* layout = "start:u16 config_crc";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint16_t config_crc = 0;
  void put(writer& w) const { w.u16(config_crc); }
  void get(reader& r) { config_crc = r.u16(); }
  bool operator==(const start_msg&) const = default;
};

/// CRC-16/CCITT-FALSE of a configuration's CONFIGURE payload: what START names.
[[nodiscard]] uint16_t configure_crc(const configure_msg& c);

struct stop_msg {
  static constexpr msg type = msg::stop;
  static constexpr const char* layout = "stop:";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  void put(writer&) const {}
  void get(reader&) {}
  bool operator==(const stop_msg&) const = default;
};

struct home_msg {
  static constexpr msg type = msg::home;
  static constexpr const char* layout = "home:";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  void put(writer&) const {}
  void get(reader&) {}
  bool operator==(const home_msg&) const = default;
};

/// SET_DELTA_N (host to device): dN for on-board compensation, ADC codes x 256.
struct set_delta_n_msg {
  static constexpr msg type = msg::set_delta_n;
  static constexpr const char* layout = "set_delta_n:i32 delta_n_q8";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  int32_t delta_n_q8 = 0;
  void put(writer& w) const { w.i32(delta_n_q8); }
  void get(reader& r) { delta_n_q8 = r.i32(); }
  bool operator==(const set_delta_n_msg&) const = default;
};

/// CALIBRATE (host to device): average r over the next K complete cycles (starting the run if
/// idle, and stopping it after), report CAL_RESULT and use the result as dN.
struct calibrate_msg {
  static constexpr msg type = msg::calibrate;
  static constexpr const char* layout = "calibrate:u16 cycles";
  static constexpr uint8_t crc_extra = layout_seed(layout);
  uint16_t cycles = 0;
  void put(writer& w) const { w.u16(cycles); }
  void get(reader& r) { cycles = r.u16(); }
  bool operator==(const calibrate_msg&) const = default;
};

/// The layout seed of message type `t`; false for a type this protocol version does not have.
[[nodiscard]] bool crc_extra_of(uint8_t t, uint8_t& extra);

}  // namespace gyroflip::protocol
