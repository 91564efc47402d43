/// \file
/// \brief The emulated rig (emulator.hpp).
#include "host/emulator/emulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "gyroflip/core/error.hpp"
#include "gyroflip/rig/geometry.hpp"

namespace gyroflip::host {

namespace {

// ADXRS150 TEMP output (docs/FACTS.md §9, [U]): 2.50 V at 298 K,
// 8.4 mV/K, read differentially against the 2.5 V reference on AIN3 (docs/HARDWARE.md).
constexpr double temp_out_v_per_k = 8.4e-3;
constexpr double temp_out_ref_c = 24.85;  // 298 K

constexpr std::uint8_t gyro_channel = 0;  // AIN0/AIN1 (docs/HARDWARE.md)
constexpr std::uint8_t temp_channel = 1;  // AIN2/AIN3

double dot(const sensor::sensor_vec& a, const sensor::sensor_vec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

}  // namespace

struct emulator::parts {
  // The ADC model's code source is this object (its address is stable; `owner` is set by the
  // emulator that owns it).
  parts(sensor::gyro g, const rig::ad7739& a, std::uint32_t mclk_hz, std::uint32_t serial)
      : gyro(std::move(g)),
        adc(a),
        board(&emulator::source, this, mclk_hz),
        facts{serial, mclk_hz, protocol::board_kind::host_emulator} {
    dev.emplace(board.hw(), facts);
  }
  emulator* owner = nullptr;
  sensor::gyro gyro;
  rig::ad7739 adc;
  rig::profile rate = rig::profile::constant(0.0);
  rig::profile temp_gyro = rig::profile::constant(20.0);  // at the gyro's windows
  rig::profile temp_chan = rig::profile::constant(20.0);  // at the temperature conversions
  // Per table step (0 .. steps_per_rev - 1): sensed gains and terms (rig/geometry.hpp).
  std::vector<double> in_gain, table_gain, earth, gf0, gf1, accel_x, accel_y;
  double dt_s = 0.0;
  fw::model::host_board board;
  fw::board_facts facts;
  std::optional<fw::device> dev;  // replaced by a new one when the firmware is reset
};

result<std::unique_ptr<emulator>> emulator::make(const emulator_config& c) {
  const rig::simulation_config& s = c.sim;
  if (!(s.adc.mclk_hz >= 1e6 && s.adc.mclk_hz <= 10e6))
    return usage_error("ADC clock: 1 to 10 MHz");
  if (auto r = s.rig.check(s.adc.mclk_hz); !r) return r.err();
  if (auto r = s.coil.check(); !r) return r.err();
  if (!(c.accel_period_s > 0.0 && c.accel_period_s <= 0.1) ||
      !(c.accel_capture_hz >= 1e3 && c.accel_capture_hz <= 1e8))
    return usage_error("accelerometer: period (0, 0.1] s, capture clock 1 kHz to 100 MHz");
  auto adc = rig::ad7739::make(rig::adc_config(s), s.seed);
  if (!adc) return adc.err();
  const double dt = adc->conversion_time_s();
  auto g = sensor::gyro::make(s.sensor, dt, s.power_on_before_s, s.seed);
  if (!g) return g.err();
  auto geo = rig::rig_geometry::make(s.lat_deg, s.axis, s.table_axis, s.mount);
  if (!geo) return geo.err();
  const auto mclk = static_cast<std::uint32_t>(std::lround(s.adc.mclk_hz));
  auto p = std::make_unique<parts>(std::move(*g), *adc, mclk, c.serial);
  p->dt_s = dt;
  p->rate = s.rate;
  p->temp_gyro = s.temperature;
  p->temp_chan = s.temperature;
  const sensor::sensor_vec g0 = p->gyro.g_sens_g0();
  const sensor::sensor_vec g1 = p->gyro.g_sens_g1();
  const int rev = s.rig.steps_per_rev;
  for (int k = 0; k < rev; ++k) {
    const rig::frame_terms f = rig::terms_at(*geo, 360.0 * k / rev);
    p->in_gain.push_back(rig::sensed(f.input_axis, s.sensor));
    p->table_gain.push_back(rig::sensed(f.table_axis, s.sensor));
    p->earth.push_back(rig::sensed(f.earth_dps, s.sensor));
    p->gf0.push_back(dot(g0, f.specific_force_g));
    p->gf1.push_back(dot(g1, f.specific_force_g));
    p->accel_x.push_back(f.specific_force_g.x);
    p->accel_y.push_back(f.specific_force_g.y);
  }
  return std::unique_ptr<emulator>(new emulator(c, std::move(p)));
}

emulator::emulator(const emulator_config& c, std::unique_ptr<parts> p) : cfg_(c), p_(std::move(p)) {
  p_->owner = this;
  // The gyro's first window ends half a window after t = 0 (sensor/gyro.hpp: t >= dt/2).
  t_last_s_ = -0.5 * p_->dt_s;
  next_idle_sample_ = static_cast<std::uint64_t>(std::ceil(1.5 * p_->dt_s * tick_hz));
  p_->board.steps_per_rev = c.sim.rig.steps_per_rev;
  p_->board.home_at = 0;
  const double period_ticks = c.accel_period_s * tick_hz;
  for (int a = 0; a < 2; ++a) {
    p_->board.pwm_period_ticks[a] =
        static_cast<std::uint32_t>(std::max(1.0, std::round(period_ticks)));
    p_->board.pwm_high_ticks[a] = p_->board.pwm_period_ticks[a] / 2;
    p_->board.pwm_capture_period[a] =
        static_cast<std::uint32_t>(std::round(c.accel_period_s * c.accel_capture_hz));
  }
  update_accel();
}

emulator::~emulator() = default;

const fw::device& emulator::device() const noexcept {
  return *p_->dev;
}

void emulator::boot() {
  boots_ = 1;
  resets_at_.clear();
  p_->dev->boot({static_cast<std::uint8_t>(protocol::reset_cause::power_on), boots_});
}

// A reset (watchdog, brown-out, the reset button) clears the microcontroller's RAM: a new firmware
// state on the same board. The table stays where it stood, the ADC keeps its registers until the
// boot resets it, and bytes already on the wire arrive.
void emulator::reset() {
  p_->dev.emplace(p_->board.hw(), p_->facts);
  ++boots_;  // kept in memory a reset does not clear (on the MSP430F149: .noinit)
  resets_at_.push_back(ticks_);
  p_->dev->boot({static_cast<std::uint8_t>(protocol::reset_cause::reset_pin), boots_});
}

std::uint16_t emulator::boot_at(std::uint32_t board_ticks) const noexcept {
  const std::uint64_t ago =
      static_cast<std::uint32_t>(static_cast<std::uint32_t>(ticks_) - board_ticks);
  const std::uint64_t at = ticks_ - std::min(ticks_, ago);
  const auto after =
      std::upper_bound(resets_at_.begin(), resets_at_.end(), at) - resets_at_.begin();
  return static_cast<std::uint16_t>(boots_ - resets_at_.size() + static_cast<std::size_t>(after));
}

std::size_t emulator::step_index() const noexcept {
  const std::int32_t rev = cfg_.sim.rig.steps_per_rev;
  return static_cast<std::size_t>(((p_->board.motors.position[0] % rev) + rev) % rev);
}

double emulator::table_angle_deg() const noexcept {
  return 360.0 * static_cast<double>(step_index()) / cfg_.sim.rig.steps_per_rev;
}

// Half the difference of A and B (paper eqn 11): what is the same at both (a tilted table's
// gravity along its axis, for one) is bias, not dN.
double emulator::delta_n_truth_dps(double temp_c) const noexcept {
  const auto at = [&](std::size_t k) {
    return p_->earth[k] + p_->gf0[k] + p_->gf1[k] * (temp_c - p_->gyro.temp_ref_c());
  };
  return 0.5 * (at(0) - at(static_cast<std::size_t>(cfg_.sim.rig.steps_per_rev / 2)));
}

// The first Fourier coefficients over every table step: exact for what the geometry gives, a
// constant plus a first harmonic of the table angle (a vector fixed in the world, or in the
// table's frame, read along an axis turning about the table axis: rig/geometry.hpp).
harmonic_truth emulator::harmonic_truth_at(double temp_c) const noexcept {
  const std::size_t m = p_->earth.size();
  harmonic_truth t;
  for (std::size_t k = 0; k < m; ++k) {
    const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(m);
    const double g = p_->gf0[k] + p_->gf1[k] * (temp_c - p_->gyro.temp_ref_c());
    t.earth_c1_dps += p_->earth[k] * std::cos(a);
    t.earth_s1_dps += p_->earth[k] * std::sin(a);
    t.g_c1_dps += g * std::cos(a);
    t.g_s1_dps += g * std::sin(a);
    t.mean_dps += p_->earth[k] + g;
  }
  const double n = static_cast<double>(m);
  t.earth_c1_dps *= 2.0 / n;
  t.earth_s1_dps *= 2.0 / n;
  t.g_c1_dps *= 2.0 / n;
  t.g_s1_dps *= 2.0 / n;
  t.mean_dps /= n;
  return t;
}

void emulator::update_accel() {
  const std::int32_t pos = p_->board.motors.position[0];
  if (pos == pos_accel_) return;
  pos_accel_ = pos;
  const std::size_t k = step_index();
  const double f[2] = {p_->accel_x[k], p_->accel_y[k]};
  for (int a = 0; a < 2; ++a) {
    // Duty 0.5 + 0.125 g^-1 f, within the output's 0..100 % (data sheet p. 1).
    const double duty = std::clamp(0.5 + 0.125 * f[a], 0.0, 1.0);
    p_->board.pwm_capture_high[a] =
        static_cast<std::uint32_t>(std::lround(duty * p_->board.pwm_capture_period[a]));
  }
}

// The coils' heat at `t_s` (rig::coil_heating): advanced from the last time asked with the
// flip motor's coils as the firmware has them now. The gyro is sampled every conversion (and
// every two conversion times when idle), so a change of the coils is seen within ~4 ms.
double emulator::coil_heat_c(double t_s) {
  const rig::coil_heating& h = cfg_.sim.coil;
  if (h.rise_c == 0.0) return 0.0;
  if (t_s > heat_t_s_) {
    const bool on = p_->board.motors.energised(p_->dev->config().flip_motor & 1);
    heat_c_ = h.step(heat_c_, on, t_s - heat_t_s_);
    heat_t_s_ = t_s;
  }
  return heat_c_;
}

double emulator::sample_gyro(double t_s) {
  const std::size_t k = step_index();
  const std::int32_t pos = p_->board.motors.position[0];
  const double step_deg = 360.0 / cfg_.sim.rig.steps_per_rev;
  // The table's mean rate since the last window: what the gyro integrated meanwhile.
  const double table_dps = t_s > t_last_s_ ? (pos - pos_last_) * step_deg / (t_s - t_last_s_) : 0.0;
  const double temp_c = p_->temp_gyro.at(t_s) + coil_heat_c(t_s);
  const double w = p_->in_gain[k] * p_->rate.at(t_s) + p_->table_gain[k] * table_dps +
                   p_->earth[k] + p_->gf0[k] + p_->gf1[k] * (temp_c - p_->gyro.temp_ref_c());
  t_last_s_ = t_s;
  pos_last_ = pos;
  next_idle_sample_ = static_cast<std::uint64_t>(std::ceil((t_s + 2.0 * p_->dt_s) * tick_hz));
  return p_->gyro.sample(t_s, temp_c, w).v_rel;
}

std::int32_t emulator::gyro_code(double t_end_s) {
  const double t = std::max(t_end_s - 0.5 * p_->dt_s, t_last_s_);
  conv_table_deg_ = table_angle_deg();
  if (stations_.empty() || stations_.back().second != conv_table_deg_) {
    if (stations_.size() >= 4096) stations_.erase(stations_.begin(), stations_.begin() + 2048);
    stations_.emplace_back(ticks_, conv_table_deg_);
  }
  return p_->adc.convert(sample_gyro(t)) - rig::ad7739::code_zero;
}

double emulator::table_deg_at(std::uint32_t board_ticks) const noexcept {
  // The 64-bit tick of that 32-bit one: the latest not after now.
  const std::uint64_t back =
      static_cast<std::uint32_t>(static_cast<std::uint32_t>(ticks_) - board_ticks);
  if (back > ticks_) return std::numeric_limits<double>::quiet_NaN();
  const std::uint64_t t = ticks_ - back;
  const auto after = std::upper_bound(
      stations_.begin(), stations_.end(), t,
      [](std::uint64_t v, const std::pair<std::uint64_t, double>& s) { return v < s.first; });
  if (after == stations_.begin()) return std::numeric_limits<double>::quiet_NaN();
  return std::prev(after)->second;
}

void emulator::hold_transmitter(bool on) noexcept {
  p_->board.uart_stalled = on;
}

std::int32_t emulator::temp_code(double t_s) {
  const double v = temp_out_v_per_k * (p_->temp_chan.at(t_s) + coil_heat_c(t_s) - temp_out_ref_c);
  return p_->adc.convert(v) - rig::ad7739::code_zero;
}

std::int32_t emulator::source(void* ctx, std::uint8_t ch, std::uint32_t /*index*/) {
  emulator& e = *static_cast<parts*>(ctx)->owner;
  const double t = e.time_s();
  if (ch == gyro_channel) return e.gyro_code(t);
  if (ch == temp_channel) return e.temp_code(t);
  return 0;  // unconnected inputs read 0 V
}

void emulator::run(std::uint32_t n) {
  for (std::uint32_t i = 0; i < n; ++i) {
    p_->dev->poll();
    // A busy wait (the ADC's reset and self-calibration, at a boot or a CONFIGURE) moves the
    // board's clock within a pass: the device's time is the board's and never goes back (it
    // was set back to the pass count, and a STATUS sent after such a wait said the uptime went
    // back: a recorder took that for a reset).
    ticks_ += static_cast<std::uint32_t>(p_->board.now - static_cast<std::uint32_t>(ticks_)) + 1u;
    p_->board.now = static_cast<std::uint32_t>(ticks_);
    if (ticks_ >= next_idle_sample_) {
      // No conversion for two windows: the gyro still runs (a turn, a pause, idle).
      sample_gyro(t_last_s_ + p_->dt_s);
      update_accel();
    }
  }
}

std::size_t emulator::send(const std::uint8_t* p, std::size_t n) {
  const std::size_t k = std::min(n, p_->board.host_free());
  return p_->board.host_send(p, k) ? k : 0;
}

std::size_t emulator::receive(std::uint8_t* out, std::size_t cap) {
  return p_->board.host_receive(out, cap);
}

}  // namespace gyroflip::host
