/// \file
/// \brief The slowly varying error processes of the gyro, each a small value type: first-order
/// Gauss-Markov, the flicker (1/f) bank, rate random walk, and `slow_bias`, which runs them on
/// a grid of its own and interpolates linearly to any sample time.
///
/// Why a grid: these processes have no power above ~1/tau_min, so stepping them at a period
/// independent of the ADC rate makes the simulation (a) independent of the sample rate and
/// (b) cheap: one linear interpolation per sample instead of several normal deviates.
/// White noise (ARW) is per sample and lives in sensor/gyro.hpp.
#pragma once

#include <cstdint>
#include <vector>

#include "gyroflip/sensor/params.hpp"
#include "gyroflip/sensor/random.hpp"

namespace gyroflip::sensor {

/// Exact discretisation of a first-order Gauss-Markov process dx = -x/tau dt + q sqrt(2/tau) dW
/// with stationary variance q^2, over a step h: x' = a x + q sqrt(1 - a^2) w, a = e^{-h/tau},
/// w ~ N(0,1) (e.g. Maybeck vol. 1 section 4.9). Exact for any h, so the process statistics
/// do not depend on the step (the bug fixed in gnss-ins-sim #19 and PX4 #73, FACTS §8).
struct gauss_markov {
  double decay = 0.0;  ///< a = e^{-h/tau} (-)
  double drive = 0.0;  ///< q sqrt(1 - a^2) (same unit as x)

  /// Step `h_s` (s) for time constant `tau_s` (s) and stationary std `sigma` (any unit).
  [[nodiscard]] static gauss_markov make(double tau_s, double sigma, double h_s);
  [[nodiscard]] double step(double x, double w) const noexcept { return decay * x + drive * w; }
};

/// Flicker (bias instability) as a bank of first-order Gauss-Markov processes with time
/// constants spaced two per decade over [tau_min, tau_max], each of variance
/// q^2 = B^2 ln(r) / pi (r = ratio of neighbouring time constants).
///
/// Derivation: a GM process of variance q^2 and time constant T has the one-sided PSD
/// 4 q^2 T / (1 + (2 pi f T)^2). Summed over log-spaced T (spacing ln r), the sum approximates
/// (4 q^2/ln r) int dT/(1 + (2 pi f T)^2) = q^2 / (f ln r). Equating it to the flicker PSD of
/// IEEE Std 952-1997 Annex C, S(f) = B^2/(pi f) one-sided (= B^2/(2 pi f) two-sided), gives q^2,
/// and the Allan deviation has the floor sqrt(2 ln 2/pi) B = 0.6643 B. Closed-form check of the
/// sum (docs/SIMULATOR.md): within +-10 % of the floor for tau in [~5 tau_min, ~tau_max/3].
///
/// Multi-rate: component j is updated every m_j = max(1, floor(tau_j / (10 h))) grid steps with
/// the exact GM step over m_j h, and interpolated linearly in between, so the slow components
/// cost almost nothing.
class flicker_bank {
 public:
  /// `b_dps` = B (deg/s), time-constant range (s), grid step `h_s` (s). B = 0 gives zero.
  flicker_bank(double b_dps, double tau_min_s, double tau_max_s, double h_s,
               const normal_stream& noise);
  /// Advances one grid step and returns the bank's value there (deg/s).
  double step() noexcept;
  /// Number of Gauss-Markov components.
  [[nodiscard]] std::size_t size() const noexcept { return parts_.size(); }

 private:
  struct part {
    gauss_markov gm;
    std::uint32_t every = 1;  // update interval in grid steps
    std::uint32_t count = 0;  // grid steps since the last update
    double inv_every = 1.0;   // 1 / every (a multiply per step instead of a division)
    double prev = 0.0;
    double next = 0.0;
  };
  std::vector<part> parts_;
  normal_stream noise_;
};

/// Everything in the bias that is slow and does not reverse with the flip, on a time grid of
/// step h: flicker bank + rate random walk (w' = w + K sqrt(h) n, IEEE 952: ADEV = K sqrt(tau/3))
/// + warm-up A e^{-t_on/tau_w} + rate ramp R t_on, where t_on = t + power_on_before_s is the
/// time since power-on. Linear interpolation between grid points; `at` takes non-decreasing t.
/// Grid step: h = min(1 s, tau_min/10, tau_w/100), independent of the sample rate.
/// The warm-up steps by the factor e^{-h/tau_w} per grid point (one multiply instead of an
/// exp): after n steps its relative error is <= n 1.1e-16, so its absolute error stays below
/// max_n n 1.1e-16 A e^{-n h/tau_w} = 1.1e-16 A tau_w / (e h) (4e-14 deg/s for the presets);
/// below 1e-300 deg/s it is set to 0 (no subnormal arithmetic).
class slow_bias {
 public:
  slow_bias(const sensor_params& p, double power_on_before_s, std::uint64_t seed);
  /// The slow bias (deg/s) at run time `t_s` (s, >= 0, non-decreasing between calls).
  double at(double t_s) noexcept {
    while (t_s > t_hi_) advance();
    return v_lo_ + slope_ * (t_s - t_lo_);
  }
  /// The mean of the slow bias (deg/s) over the window [t0_s, t1_s] (s, 0 <= t0 < t1, windows
  /// non-decreasing): (I(t1) - I(t0)) / (t1 - t0) with I the exact integral of the piecewise-
  /// linear process. This is what an integrating ADC sees, so the sampled process has the same
  /// Allan deviation at any sample rate (no aliasing of the flicker bank's fast components).
  double mean_over(double t0_s, double t1_s) noexcept {
    return mean_over(t0_s, t1_s, 1.0 / (t1_s - t0_s));
  }
  /// The mean over the window [t_s - half_s, t_s + half_s] (s) with 1/(2 half_s) precomputed.
  /// A window inside one grid interval takes the value of the linear piece at its centre (the
  /// exact mean of a linear function over a symmetric window; no difference of two large
  /// integrals); a window across grid points takes mean_over().
  double mean_at(double t_s, double half_s, double inv_width_per_s) noexcept {
    if (t_s - half_s >= t_lo_ && t_s + half_s <= t_hi_) return v_lo_ + slope_ * (t_s - t_lo_);
    return mean_over(t_s - half_s, t_s + half_s, inv_width_per_s);
  }
  /// mean_at() for the non-decreasing window centres `t_s[0..n)` into `out`, bit-identical to n
  /// calls in order: the windows inside one grid interval form a run that is one tight
  /// (vectorisable) loop.
  void mean_block(const double* t_s, double half_s, double inv_width_per_s, double* out,
                  std::size_t n) noexcept;
  /// The same with 1/(t1 - t0) precomputed by the caller (no division per sample).
  double mean_over(double t0_s, double t1_s, double inv_width_per_s) noexcept {
    const double i0 = t0_s == t_end_ ? i_end_ : integral_to(t0_s);
    const double i1 = integral_to(t1_s);
    t_end_ = t1_s;
    i_end_ = i1;
    return (i1 - i0) * inv_width_per_s;
  }
  [[nodiscard]] double grid_step_s() const noexcept { return h_; }
  /// Gauss-Markov parts of the flicker bank (0 when off). The work per simulated second is
  /// about (parts + 2) / grid_step_s(): sensor_params' bounds keep it below ~3e5.
  [[nodiscard]] std::size_t flicker_poles() const noexcept { return flicker_.size(); }

 private:
  void advance() noexcept;
  // Integral of the process from 0 to t_s (deg): area up to the grid point t_lo plus the
  // trapezoid to t_s.
  double integral_to(double t_s) noexcept {
    while (t_s > t_hi_) advance();
    const double d = t_s - t_lo_;
    return area_lo_ + d * (v_lo_ + 0.5 * slope_ * d);
  }
  double grid_value() noexcept;
  double h_;
  double t_on0_;
  double warm_, warm_step_, ramp_;  // warm-up at the next grid point (deg/s), its factor
  double rrw_step_, rrw_;
  bool flicker_on_, rrw_on_;
  flicker_bank flicker_;
  normal_stream rrw_noise_;
  std::uint64_t n_ = 0;
  double t_lo_ = 0.0, t_hi_ = 0.0, v_lo_ = 0.0, v_hi_ = 0.0, slope_ = 0.0, area_lo_ = 0.0;
  double t_end_ = -1.0, i_end_ = 0.0;  // the previous window's end and its integral
};

}  // namespace gyroflip::sensor
