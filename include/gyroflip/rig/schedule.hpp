/// \file
/// \brief The acquisition schedule (paper section 4): dwell at A, turn to B, settle, dwell at
/// B, turn back to A (or on to A, one way round through a rotary joint), settle, repeat.
///
/// Everything runs on the ADC clock: the ADC converts continuously, so one cycle is
///   [N acquisitions at A][M_AB turning][M_s settling][N at B][M_BA turning][M_s settling]
/// conversions, M = ceil(duration / t_conv). Defaults (N = 256, FW = 94 -> t_conv = 1.99886 ms,
/// 180-deg turn 0.300 s -> 151 conversions, settle 0.08 s -> 41 conversions): 896 conversions
/// = 1.791 s per cycle, the paper's "about 1.79 s". A conversion is "moving" when the table
/// turns during any part of it (its angle is then empty in raw recordings).
#pragma once

#include <cstdint>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/rig/turntable.hpp"

namespace gyroflip::rig {

struct schedule_params {
  int n_avg = 256;           ///< conversions averaged per dwell
  double settle_s = 0.08;    ///< wait after a turn before acquiring (s)
  double pos_a_deg = 0.0;    ///< first position (deg)
  double pos_b_deg = 180.0;  ///< second position (deg)
  /// false: no flipping at all, the table stays at A and dwell follows dwell (a stationary
  /// recording of the raw sensor, to compare its Allan curve with the compensated one).
  bool flip = true;
  /// true: B -> A turns on the same way round (360 - (B - A) degrees, through a rotary joint);
  /// false: back by B - A, as the device turns unless told otherwise (configure_msg cfg_one_way).
  bool one_way = false;
  /// The table after each turn (turntable.hpp; off by default) and when the device releases the
  /// coils before a dwell's first conversion: a negative value is half the settling time before
  /// it (the firmware's: docs/FIRMWARE.md), 0.0002 the firmware before issue 32.
  settle_model settle;
  double release_before_dwell_s = -1.0;
  /// More than two positions (issue 33): the angles visited in one cycle, in order (deg, each in
  /// [0, 360), consecutive visits may repeat an angle: the table then stays and the next dwell
  /// follows at once). Empty: the two-position cycle A, B above. With back-and-forth turns the
  /// table turns by the plain difference of the angles (it never passes 360 -> 0, a cable's
  /// stop); with `one_way` always forwards. Each dwell is its own slot (phase::dwell = its visit).
  std::vector<double> visits;
};

/// How the simulator visits a table of positions (issue 33).
enum class visit_order {
  automatic,  ///< two positions: A, B (the paper's cycle); three or more: sweep
  sweep,      ///< forwards then backwards, each end dwelt twice (sweep_order)
  cycle,      ///< the table's order over and over (as the device runs its angle table)
};

/// The drift-cancelling visiting order of a table's positions (issue 33, docs/SIMULATOR.md §4):
/// forwards then backwards, each end dwelt twice (0, 1, ..., n-1, n-1, ..., 1, 0: for two
/// positions A B B A). Every position's visits are centred on the cycle's middle, so a bias
/// linear in time enters each position's mean alike (it cancels in any contrast of them), and
/// every position gets the same time.
[[nodiscard]] std::vector<double> sweep_order(const std::vector<double>& angles_deg);

/// One conversion slot of the cycle. With a settle model, a slot after a turn (settling, and
/// the dwell that follows) carries the residual's rate and angle.
struct phase {
  double angle_deg = 0.0;       ///< table angle at mid-conversion (deg, unwrapped)
  double table_rate_dps = 0.0;  ///< mean table rate over the conversion (deg/s)
  bool moving = false;          ///< the table turns during this conversion
  std::int8_t dwell = -1;       ///< 0 = acquiring at A, 1 = acquiring at B (the visit's number with
                                ///< schedule_params::visits), -1 = not acquiring
};

class schedule {
 public:
  /// Errors: N < 1, settle < 0, positions not a whole number of steps apart or equal.
  [[nodiscard]] static result<schedule> make(const schedule_params& s, const stepper_params& m,
                                             double t_conv_s);
  [[nodiscard]] const std::vector<phase>& phases() const noexcept { return phases_; }
  [[nodiscard]] double cycle_s() const noexcept {
    return t_conv_s_ * static_cast<double>(phases_.size());
  }
  [[nodiscard]] double turn_ab_s() const noexcept { return turn_ab_s_; }
  [[nodiscard]] double turn_ba_s() const noexcept { return turn_ba_s_; }
  [[nodiscard]] const schedule_params& params() const noexcept { return p_; }
  /// Dwells per cycle (2 for the two-position cycle and without flipping, as before issue 33).
  [[nodiscard]] int dwells_per_cycle() const noexcept {
    return p_.visits.empty() ? 2 : static_cast<int>(p_.visits.size());
  }
  /// Table-turning and settling time per dwell, the run's dead time per dwell (s).
  [[nodiscard]] double dead_time_per_dwell_s() const noexcept;

 private:
  schedule_params p_;
  double t_conv_s_ = 0.0, turn_ab_s_ = 0.0, turn_ba_s_ = 0.0;
  std::vector<phase> phases_;
};

}  // namespace gyroflip::rig
