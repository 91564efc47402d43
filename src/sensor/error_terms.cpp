/// \file
/// \brief Gauss-Markov steps, the flicker bank and the slow-bias grid (formulas in the header).
#include "gyroflip/sensor/error_terms.hpp"

#include <algorithm>
#include <cmath>

#include "gyroflip/sensor/det_math.hpp"

namespace gyroflip::sensor {

gauss_markov gauss_markov::make(double tau_s, double sigma, double h_s) {
  const double a = det_exp(-h_s / tau_s);
  return {a, sigma * std::sqrt((1.0 - a) * (1.0 + a))};
}

flicker_bank::flicker_bank(double b_dps, double tau_min_s, double tau_max_s, double h_s,
                           const normal_stream& noise)
    : noise_(noise) {
  if (b_dps <= 0.0) return;
  constexpr double pi = 3.14159265358979323846;
  const double decades = std::log10(tau_max_s / tau_min_s);
  const auto n = static_cast<std::size_t>(std::max(2.0, std::round(2.0 * decades) + 1.0));
  const double ln_r = det_log(tau_max_s / tau_min_s) / static_cast<double>(n - 1);
  const double sigma = b_dps * std::sqrt(ln_r / pi);
  parts_.reserve(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double tau = tau_min_s * det_exp(ln_r * static_cast<double>(j));
    part c;
    c.every = static_cast<std::uint32_t>(std::clamp(std::floor(tau / (10.0 * h_s)), 1.0, 1e9));
    c.inv_every = 1.0 / c.every;
    c.gm = gauss_markov::make(tau, sigma, h_s * c.every);
    c.prev = sigma * noise_.next();  // start stationary
    c.next = c.gm.step(c.prev, noise_.next());
    parts_.push_back(c);
  }
}

double flicker_bank::step() noexcept {
  double sum = 0.0;
  for (auto& c : parts_) {
    if (++c.count == c.every) {
      c.count = 0;
      c.prev = c.next;
      c.next = c.gm.step(c.prev, noise_.next());
    }
    sum += c.prev + (c.next - c.prev) * (static_cast<double>(c.count) * c.inv_every);
  }
  return sum;
}

namespace {
double grid_step(const sensor_params& p) {
  double h = 1.0;
  if (p.bias_instability_dps > 0.0) h = std::min(h, p.flicker_tau_min_s / 10.0);
  if (p.warmup_amplitude_dps != 0.0) h = std::min(h, p.warmup_tau_s / 100.0);
  return h;
}
}  // namespace

slow_bias::slow_bias(const sensor_params& p, double power_on_before_s, std::uint64_t seed)
    : h_(grid_step(p)),
      t_on0_(power_on_before_s),
      warm_(p.warmup_amplitude_dps * det_exp(-power_on_before_s / p.warmup_tau_s)),
      warm_step_(det_exp(-h_ / p.warmup_tau_s)),
      ramp_(p.rate_ramp_dps_per_s),
      rrw_step_(p.rrw_dps_per_rts * std::sqrt(h_)),
      rrw_(0.0),
      flicker_on_(p.bias_instability_dps > 0.0),
      rrw_on_(p.rrw_dps_per_rts > 0.0),
      flicker_(p.bias_instability_dps, p.flicker_tau_min_s, p.flicker_tau_max_s, h_,
               normal_stream(seed, stream::flicker)),
      rrw_noise_(seed, stream::rate_random_walk) {
  // A random walk started at power-on has variance K^2 t_on at run start.
  if (rrw_on_) rrw_ = p.rrw_dps_per_rts * std::sqrt(power_on_before_s) * rrw_noise_.next();
  v_lo_ = grid_value();
  t_lo_ = 0.0;
  advance();
}

double slow_bias::grid_value() noexcept {
  const double t_on = t_on0_ + static_cast<double>(n_) * h_;
  double v = ramp_ * t_on;
  v += warm_;
  warm_ = std::fabs(warm_) < 1e-300 ? 0.0 : warm_ * warm_step_;
  if (flicker_on_) v += flicker_.step();
  if (rrw_on_) {
    v += rrw_;
    rrw_ += rrw_step_ * rrw_noise_.next();
  }
  return v;
}

void slow_bias::mean_block(const double* t_s, double half_s, double inv_width_per_s, double* out,
                           std::size_t n) noexcept {
  std::size_t i = 0;
  while (i < n) {
    if (t_s[i] - half_s >= t_lo_ && t_s[i] + half_s <= t_hi_) {
      // Later windows start later (sorted), so the run ends at the first window past t_hi.
      const double t_hi = t_hi_;
      const double* end =
          std::partition_point(t_s + i + 1, t_s + n, [&](double t) { return t + half_s <= t_hi; });
      const auto m = static_cast<std::size_t>(end - t_s);
      const double v_lo = v_lo_;
      const double slope = slope_;
      const double t_lo = t_lo_;
      for (std::size_t k = i; k < m; ++k) out[k] = v_lo + slope * (t_s[k] - t_lo);
      i = m;
    } else {
      out[i] = mean_over(t_s[i] - half_s, t_s[i] + half_s, inv_width_per_s);
      ++i;
    }
  }
}

void slow_bias::advance() noexcept {
  if (n_ > 0) {
    area_lo_ += 0.5 * (v_lo_ + v_hi_) * h_;
    t_lo_ = t_hi_;
    v_lo_ = v_hi_;
  }
  ++n_;
  t_hi_ = static_cast<double>(n_) * h_;
  v_hi_ = grid_value();
  slope_ = (v_hi_ - v_lo_) / h_;
}

}  // namespace gyroflip::sensor
