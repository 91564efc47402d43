/// \file
/// \brief Stepper step times and the table angle during a turn (formulas in turntable.hpp).
#include "gyroflip/rig/turntable.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::rig {

result<turn_profile> turn_profile::make(const stepper_params& p, double angle_deg) {
  if (p.steps_per_rev < 4 || !(p.start_rate_sps > 0.0) || !(p.max_rate_sps >= p.start_rate_sps) ||
      !(p.accel_sps2 > 0.0) || !std::isfinite(p.max_rate_sps) || !std::isfinite(p.accel_sps2)) {
    return usage_error("stepper: need steps/rev >= 4, 0 < start rate <= max rate, accel > 0");
  }
  turn_profile tp;
  tp.step_deg_ = 360.0 / p.steps_per_rev;
  const double n_real = angle_deg / tp.step_deg_;
  const double n = std::round(n_real);
  if (!(n >= 1.0) || std::abs(n - n_real) > 1e-9 * std::max(1.0, n)) {
    return usage_error(fmt::format("a turn of {} deg is not a whole number of {} deg full steps",
                                   angle_deg, tp.step_deg_));
  }
  const double v0 = p.start_rate_sps;
  const double a = p.accel_sps2;
  // Steps spent accelerating to v_max, capped at half the turn (triangle profile).
  const double k_a = std::min((p.max_rate_sps * p.max_rate_sps - v0 * v0) / (2.0 * a), n / 2.0);
  const double v_peak = std::sqrt(v0 * v0 + 2.0 * a * k_a);
  const auto t_acc = [&](double k) { return (-v0 + std::sqrt(v0 * v0 + 2.0 * a * k)) / a; };
  const double t_a = t_acc(k_a);
  const double total = 2.0 * t_a + (n - 2.0 * k_a) / v_peak;
  const auto steps = static_cast<std::size_t>(n);
  tp.step_t_s_.resize(steps + 1);
  for (std::size_t i = 0; i <= steps; ++i) {
    const double k = static_cast<double>(i);
    if (k <= k_a) {
      tp.step_t_s_[i] = t_acc(k);
    } else if (k <= n - k_a) {
      tp.step_t_s_[i] = t_a + (k - k_a) / v_peak;
    } else {
      tp.step_t_s_[i] = total - t_acc(n - k);
    }
  }
  return tp;
}

double settle_model::residual_deg(double t_s, double t_release_s, int dir) const noexcept {
  if (t_s <= 0.0) return 0.0;
  constexpr double two_pi = 6.283185307179586;
  double a = ring_deg * std::exp(-t_s / ring_tau_s) * std::cos(two_pi * ring_hz * t_s);
  if (t_s > t_release_s) a -= release_deg * (1.0 - std::exp(-(t_s - t_release_s) / release_tau_s));
  return dir * a;
}

double turn_profile::angle_at(double t_s) const noexcept {
  if (t_s <= 0.0) return 0.0;
  if (t_s >= duration_s()) return angle_deg();
  const auto it = std::upper_bound(step_t_s_.begin(), step_t_s_.end(), t_s);
  const auto k =
      static_cast<std::size_t>(it - step_t_s_.begin()) - 1;  // step_t[k] <= t < step_t[k+1]
  const double frac = (t_s - step_t_s_[k]) / (step_t_s_[k + 1] - step_t_s_[k]);
  return step_deg_ * (static_cast<double>(k) + frac);
}

}  // namespace gyroflip::rig
