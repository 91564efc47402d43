/// \file
/// \brief The recording generator's hot loop and the dwell averaging (see simulator.hpp).
#include "gyroflip/rig/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

// The iterations of the next loop touch distinct memory, so it vectorises without run-time
// alias checks (GCC applies restrict to function parameters only, and gives up when a loop
// would need more checks than its limit: 8 columns and 8 slot tables here).
#if defined(__clang__)
#define GYROFLIP_INDEPENDENT_ITERATIONS _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define GYROFLIP_INDEPENDENT_ITERATIONS _Pragma("GCC ivdep")
#else
#define GYROFLIP_INDEPENDENT_ITERATIONS
#endif

namespace gyroflip::rig {

sample_block::sample_block(std::size_t capacity, bool with_truth)
    : truth(with_truth),
      time_s(capacity),
      angle_deg(capacity),
      rate_dps(capacity),
      temp_c(capacity),
      bias_dps(capacity),
      g_term_dps(capacity),
      earth_dps(capacity),
      input_dps(capacity),
      dwell(capacity) {}

status coil_heating::check() const {
  if (!(rise_c >= 0.0 && rise_c <= 50.0) || !(tau_s >= 1.0 && tau_s <= 1e6))
    return parameter_error("coil_heat",
                           "the coils' heat: a rise of 0..50 degC, a time constant of 1..1e6 s");
  return ok();
}

namespace {

// The bounds of every value of a simulation (header constants), checked before any work.
status check_ranges(const simulation_config& c) {
  if (!(c.duration_s > 0.0 && c.duration_s <= max_duration_s))
    return parameter_error("duration_s", fmt::format("the duration {:g} s is outside (0, {:g}] s",
                                                     c.duration_s, max_duration_s));
  if (auto s = c.temperature.check_range("the temperature (degC)", -273.15, 1000.0); !s) return s;
  if (auto s = c.rate.check_range("the input rate (deg/s)", -max_rate_dps, max_rate_dps); !s)
    return s;
  if (!(c.power_on_before_s >= 0.0 && c.power_on_before_s <= 1e9))
    return parameter_error("power_on_before_s",
                           "the power-on time before the run must be in "
                           "[0, 1e9] s");
  if (auto s = c.coil.check(); !s) return s;
  if (auto s = c.rig.check(c.adc.mclk_hz); !s) return s;
  const settle_model& m = c.settle;
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(m.ring_deg) || !finite(m.release_deg) || !(m.ring_tau_s > 0.0) ||
      !(m.release_tau_s > 0.0) || !(m.ring_hz >= 0.0) || !finite(m.ring_hz) ||
      !finite(c.release_before_dwell_s))
    return parameter_error("settle", "the settle model: finite angles, time constants > 0");
  return ok();
}

}  // namespace

ad7739_config adc_config(const simulation_config& c) {
  ad7739_config a;
  static_cast<ad7739_part&>(a) = c.adc;
  a.filter_word = c.rig.filter_word;
  a.chop = c.rig.chop;
  return a;
}

result<simulator> simulator::make(const simulation_config& c) {
  if (auto s = check_ranges(c); !s) return s.err();
  auto adc = ad7739::make(adc_config(c), c.seed);
  if (!adc) return adc.err();
  const double t_conv = adc->conversion_time_s();
  auto g = sensor::gyro::make(c.sensor, t_conv, c.power_on_before_s, c.seed);
  if (!g) return g.err();
  schedule_params sched_p = c.rig.schedule(c.flip, c.order);
  sched_p.settle = c.settle;
  sched_p.release_before_dwell_s = c.release_before_dwell_s;
  auto s = schedule::make(sched_p, c.rig.stepper(), t_conv);
  if (!s) return s.err();
  auto geo = rig_geometry::make(c.lat_deg, c.axis, c.table_axis, c.mount);
  if (!geo) return geo.err();
  simulator sim(c, std::move(*s), std::move(*g), *adc, *geo);
  const auto& ph = sim.sched_.phases();
  const auto& sp = c.sensor;
  const sensor::sensor_vec g0 = sim.gyro_.g_sens_g0();
  const sensor::sensor_vec g1 = sim.gyro_.g_sens_g1();
  const auto dot = [](const sensor::sensor_vec& a, const sensor::sensor_vec& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
  };
  for (const auto& p : ph) {
    const frame_terms f = terms_at(*geo, p.angle_deg);
    sim.in_gain_.push_back(sensed(f.input_axis, sp));
    sim.table_.push_back(p.table_rate_dps * sensed(f.table_axis, sp));
    sim.earth_.push_back(sensed(f.earth_dps, sp));
    sim.gf0_.push_back(dot(g0, f.specific_force_g));
    sim.gf1_.push_back(dot(g1, f.specific_force_g));
    sim.angle_out_.push_back(p.moving ? std::numeric_limits<double>::quiet_NaN()
                                      : p.angle_deg - 360.0 * std::floor(p.angle_deg / 360.0));
    sim.dwell_base_.push_back(p.dwell < 0 ? -1 : p.dwell);
    sim.dwell_mask_.push_back(p.dwell < 0 ? 0 : -1);
  }
  sim.total_ = static_cast<std::uint64_t>(std::floor(c.duration_s / t_conv + 1e-9));
  return sim;
}

double simulator::earth_at_dps(double angle_deg) const {
  return sensed(terms_at(geo_, angle_deg).earth_dps, cfg_.sensor);
}

double simulator::g_term_at_dps(double angle_deg, double temp_c) const {
  const frame_terms f = terms_at(geo_, angle_deg);
  const auto dot = [](const sensor::sensor_vec& a, const sensor::sensor_vec& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
  };
  return dot(gyro_.g_sens_g0(), f.specific_force_g) +
         dot(gyro_.g_sens_g1(), f.specific_force_g) * (temp_c - gyro_.temp_ref_c());
}

simulator::simulator(const simulation_config& c, schedule s, sensor::gyro g, const ad7739& a,
                     const rig_geometry& geo)
    : cfg_(c),
      sched_(std::move(s)),
      geo_(geo),
      gyro_(std::move(g)),
      adc_(a),
      t_conv_s_(adc_.conversion_time_s()),
      inv_sf_(1.0 / c.sensor.scale_factor_v_per_dps) {}

std::size_t simulator::fill(sample_block& b) noexcept {
  const std::size_t n =
      static_cast<std::size_t>(std::min<std::uint64_t>(b.capacity(), total_ - k_));
  // All stages run on one chunk before the next chunk starts, so that the chunk's columns and
  // scratch (~20 arrays) stay in the L1/L2 cache whatever the caller's block size.
  if (n_arw_.size() < chunk) {
    n_arw_.assign(chunk, 0.0);
    n_adc_.assign(chunk, 0.0);
    w_in_.assign(chunk, 0.0);
    v_rel_.assign(chunk, 0.0);
    bias_.assign(chunk, 0.0);
  }
  for (std::size_t i = 0; i < n; i += chunk) fill_chunk(b, i, std::min(chunk, n - i));
  b.size = n;
  return n;
}

void simulator::fill_chunk(sample_block& b, std::size_t first, std::size_t n) noexcept {
  // Restrict-qualified outputs: stores to the block cannot alias the model's state, so the
  // compiler keeps that state in registers (GCC/Clang extension, 2.5x faster here).
  double* __restrict out_t = b.time_s.data() + first;
  double* __restrict out_rate = b.rate_dps.data() + first;
  double* __restrict out_temp = b.temp_c.data() + first;
  // Normal deviates in batches (tight loops run ~2x faster than interleaved draws); zeros when
  // a term is off, so the per-sample code has no branch.
  if (gyro_.arw_on() && adc_.noise_on()) {
    fill_both(gyro_.arw_stream(), n_arw_.data(), adc_.noise_stream(), n_adc_.data(), n);
  } else if (gyro_.arw_on()) {
    gyro_.arw_stream().fill(n_arw_.data(), n);
  } else if (adc_.noise_on()) {
    adc_.noise_stream().fill(n_adc_.data(), n);
  }
  // Stage 1: time (window centres; k < 2^52 so k + 1/2 is exact), then the profiles.
  const double k0 = static_cast<double>(static_cast<std::int64_t>(k_));
  for (int j = 0; j < static_cast<int>(n); ++j)
    out_t[j] = (k0 + static_cast<double>(j) + 0.5) * t_conv_s_;
  cfg_.temperature.fill(out_t, out_temp, n);
  if (cfg_.coil.rise_c > 0.0) add_coil_heat(out_temp, n);
  cfg_.rate.fill(out_t, w_in_.data(), n);
  // Stage 2: the rig, one run of consecutive cycle slots at a time (contiguous slot tables).
  const std::size_t period = in_gain_.size();
  for (std::size_t i = 0; i < n;) {
    const std::size_t run = std::min(n - i, period - p_);
    if (b.truth) {
      rig_run<true>(b, first + i, i, run);
    } else {
      rig_run<false>(b, first + i, i, run);
    }
    i += run;
    p_ += run;
    if (p_ == period) p_ = 0;
    k_ += run;
  }
  // Stage 3: the gyro (voltages), stage 4: the AD7739 and the recorder (nominal scale factor).
  double* __restrict v_rel = v_rel_.data();
  double* bias = b.truth ? b.bias_dps.data() + first : bias_.data();
  gyro_.sample_block(out_t, out_temp, out_rate, n_arw_.data(), v_rel, bias, n);
  adc_.convert_block(v_rel, n_adc_.data(), out_rate, inv_sf_, n);
}

// The coils' first-order warming, conversion by conversion from the current cycle slot (the
// coils' state is constant over a conversion): energised outside the dwells (turning, settling),
// and in them too with hold_coils.
void simulator::add_coil_heat(double* temp, std::size_t n) noexcept {
  const std::size_t period = dwell_base_.size();
  const bool hold = cfg_.rig.hold_coils;
  std::size_t slot = p_;
  for (std::size_t j = 0; j < n; ++j) {
    heat_dt_c_ = cfg_.coil.step(heat_dt_c_, hold || dwell_base_[slot] < 0, t_conv_s_);
    temp[j] += heat_dt_c_;
    if (++slot == period) slot = 0;
  }
}

template <bool truth>
void simulator::rig_run(sample_block& b, std::size_t first, std::size_t scratch,
                        std::size_t n) noexcept {
  // Conversions k_ .. k_ + n - 1 are cycle slots p_ .. p_ + n - 1 of cycle k_ / period.
  const double t_ref = gyro_.temp_ref_c();
  const double* __restrict temp = b.temp_c.data() + first;
  const double* __restrict w_in = w_in_.data() + scratch;
  double* __restrict out_g = b.g_term_dps.data() + first;
  double* __restrict out_earth = b.earth_dps.data() + first;
  double* __restrict out_input = b.input_dps.data() + first;
  double* __restrict out_rate = b.rate_dps.data() + first;
  double* __restrict out_angle = b.angle_deg.data() + first;
  std::int64_t* __restrict out_dwell = b.dwell.data() + first;
  const double* __restrict gain = in_gain_.data() + p_;
  const double* __restrict table = table_.data() + p_;
  const double* __restrict earth = earth_.data() + p_;
  const double* __restrict gf0 = gf0_.data() + p_;
  const double* __restrict gf1 = gf1_.data() + p_;
  const double* __restrict angle = angle_out_.data() + p_;
  const std::int64_t* __restrict dwell_base = dwell_base_.data() + p_;
  const std::int64_t* __restrict dwell_mask = dwell_mask_.data() + p_;
  const auto two_cycles = static_cast<std::int64_t>(
      static_cast<std::uint64_t>(sched_.dwells_per_cycle()) * (k_ / in_gain_.size()));
  GYROFLIP_INDEPENDENT_ITERATIONS
  for (std::size_t j = 0; j < n; ++j) {
    const double g_term = gf0[j] + gf1[j] * (temp[j] - t_ref);
    const double input = w_in[j] * gain[j] + table[j];
    if constexpr (truth) {
      out_g[j] = g_term;
      out_earth[j] = earth[j];
      out_input[j] = input;
    }
    out_rate[j] = input + earth[j] + g_term;
    out_angle[j] = angle[j];
    out_dwell[j] = dwell_base[j] + (dwell_mask[j] & two_cycles);
  }
}

void dwell_averager::add(const sample_block& b, std::vector<dwell_row>& out) {
  std::size_t i = 0;
  while (i < b.size) {
    const std::int64_t d = b.dwell[i];
    if (d != current_) {
      emit(out);
      current_ = d;
    }
    std::size_t j = i + 1;  // the run of conversions of this dwell (or outside dwells)
    while (j < b.size && b.dwell[j] == d) ++j;
    if (d < 0) {
      i = j;
      continue;
    }
    while (i < j) {  // a dwell is complete after n_avg conversions, even inside a run
      const auto m = std::min(j - i, static_cast<std::size_t>(n_avg_ - n_));
      if (b.truth) {
        accumulate<true>(b, i, m);
      } else {
        accumulate<false>(b, i, m);
      }
      angle_ = b.angle_deg[i + m - 1];
      n_ += static_cast<int>(m);
      i += m;
      if (n_ == n_avg_) emit(out);
    }
  }
}

template <bool truth>
void dwell_averager::accumulate(const sample_block& b, std::size_t first, std::size_t n) noexcept {
  // One loop with an accumulator per column: independent add chains run side by side.
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  double s0 = sum_[0], s1 = sum_[1], s2 = sum_[2], s3 = sum_[3], s4 = sum_[4], s5 = sum_[5],
         s6 = sum_[6];
  for (std::size_t k = first; k < first + n; ++k) {
    s0 += b.time_s[k];
    s1 += b.rate_dps[k];
    s2 += b.temp_c[k];
    if constexpr (truth) {
      s3 += b.bias_dps[k];
      s4 += b.g_term_dps[k];
      s5 += b.earth_dps[k];
      s6 += b.input_dps[k];
    }
  }
  if constexpr (!truth) s3 = s4 = s5 = s6 = nan;
  sum_[0] = s0;
  sum_[1] = s1;
  sum_[2] = s2;
  sum_[3] = s3;
  sum_[4] = s4;
  sum_[5] = s5;
  sum_[6] = s6;
}

void dwell_averager::emit(std::vector<dwell_row>& out) {
  if (n_ == n_avg_ && n_ > 0) {
    const double inv = 1.0 / n_;
    out.push_back({sum_[0] * inv, angle_, sum_[1] * inv, sum_[2] * inv, n_, sum_[3] * inv,
                   sum_[4] * inv, sum_[5] * inv, sum_[6] * inv});
  }
  n_ = 0;
  for (auto& s : sum_) s = 0.0;
}

}  // namespace gyroflip::rig
