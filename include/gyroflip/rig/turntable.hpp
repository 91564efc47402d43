/// \file
/// \brief The turntable: a unipolar stepper in full-step mode with a trapezoidal step-rate ramp.
///
/// A turn of `angle_deg` is n = round(angle_deg / (360/steps_per_rev)) full steps. The step
/// rate v(t) (steps/s) starts at `start_rate_sps`, rises with `accel_sps2` to `max_rate_sps`,
/// cruises, and falls symmetrically (a triangle when n is too small to reach the maximum).
/// Step k (k = 1..n) happens when the integral of v reaches k:
///   accelerating: t = (-v0 + sqrt(v0^2 + 2 a k)) / a,  cruising: t = t_a + (k - k_a)/v_max,
///   decelerating: t = T - t_acc(n - k)  (mirror image).
/// Between steps the angle moves linearly (rotor inertia smooths the full-step jumps), so the
/// table rate is piecewise constant = step angle / step interval.
/// Defaults (200 steps/rev, 200 -> 400 steps/s at 2000 steps/s^2): 180 deg in 0.300 s.
#pragma once

#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::rig {

struct stepper_params {
  int steps_per_rev = 200;        ///< full steps per table revolution (1.8 deg/step)
  double start_rate_sps = 200.0;  ///< pull-in step rate (steps/s)
  double max_rate_sps = 400.0;    ///< cruise step rate (steps/s)
  double accel_sps2 = 2000.0;     ///< ramp (steps/s^2)
};

/// What the table does after a turn's last step (docs/SIMULATOR.md §4, "Settling"; a model with
/// assumed figures, off by default). While the coils hold it, it rings about its new position,
/// damped: ring_deg e^(-t/ring_tau_s) cos(2 pi ring_hz t), in the direction it arrived. When the
/// coils are released (at t_release after the last step) the rotor leaves its energised rest for
/// its unpowered one: a move of release_deg against the direction it came from (the load's
/// friction left it lagging the field), first order with release_tau_s. The gyro integrates
/// whatever of either is left when a dwell begins; with back-and-forth turns their signs differ
/// at A and B, so they enter r (and dN) instead of cancelling in it; one-way turns put them in c.
struct settle_model {
  double ring_deg = 0.0;         ///< ring-down amplitude after the last step (deg)
  double ring_hz = 60.0;         ///< its frequency (Hz)
  double ring_tau_s = 0.02;      ///< its decay time constant (s)
  double release_deg = 0.0;      ///< the move when the coils are released (deg)
  double release_tau_s = 0.005;  ///< its time constant (s)
  [[nodiscard]] bool on() const noexcept { return ring_deg != 0.0 || release_deg != 0.0; }
  /// Angle (deg) from the nominal final position at `t_s` after the last step of a turn in
  /// direction `dir` (+1 or -1), the coils released at `t_release_s` (infinity: held).
  [[nodiscard]] double residual_deg(double t_s, double t_release_s, int dir) const noexcept;
};

class turn_profile {
 public:
  /// A turn of `angle_deg` (deg, > 0) with `p`. Errors: invalid parameters, angle not a
  /// positive whole number of full steps.
  [[nodiscard]] static result<turn_profile> make(const stepper_params& p, double angle_deg);
  [[nodiscard]] double duration_s() const noexcept { return step_t_s_.back(); }
  [[nodiscard]] double angle_deg() const noexcept { return step_deg_ * n_steps(); }
  [[nodiscard]] double n_steps() const noexcept {
    return static_cast<double>(step_t_s_.size() - 1);
  }
  /// Angle turned (deg) at `t_s` (s) after the turn started; 0 before, angle_deg() after.
  [[nodiscard]] double angle_at(double t_s) const noexcept;
  /// Instants of the steps (s), starting with 0.
  [[nodiscard]] const std::vector<double>& step_times_s() const noexcept { return step_t_s_; }

 private:
  double step_deg_ = 0.0;
  std::vector<double> step_t_s_;
};

}  // namespace gyroflip::rig
