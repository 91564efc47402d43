/// \file
/// \brief A run's dwells as a compact print, and the test that finds a copy of a run in
/// another recording by its content (fifth review of issue 31, F5: a copy rounded, shifted in
/// time, trimmed, split or exported passed as an independent check of its own calibration).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// Quantisation steps per standard deviation of a run's print values in its print.
inline constexpr double print_steps_per_std = 8.0;
/// Two print values the same to within this many steps (a quarter of the run's std): a copy's
/// rates rounded to two fewer digits move them by a few hundredths of their std.
inline constexpr double print_match_steps = 2.0;
/// Consecutive print values that must all match for a copy: an independent run matches one with
/// probability P(|z1 - z2| < 0.25) = 0.14 (z standard normal), 32 in a row 0.14^32 = 5e-28 per
/// alignment.
inline constexpr std::size_t print_window = 32;

/// A run's content as a print: for its paired dwells' rates z_j in order (recording_cycles::
/// dwell_rates), d_j = z_(j+2) - z_j (the same position a cycle apart: no bias level, no dN, and
/// the same series whatever the pairing and wherever a copy starts, a dwell later or a cycle
/// later), each as round((d_j - offset) / step) with offset their mean and step their sample std
/// / print_steps_per_std (about 3 characters a dwell in JSON).
struct cycle_print {
  double offset_dps = 0.0;
  double step_dps = 0.0;
  std::vector<std::int32_t> q;
  bool operator==(const cycle_print&) const = default;
};

/// The print of a run's dwell rates; nullopt with fewer than print_window + 2 dwells or values
/// without scatter.
[[nodiscard]] std::optional<cycle_print> print_of(std::span<const double> dwell_rates);

/// Where a run repeats the printed run: the longest stretch of consecutive dwells whose print
/// values match the print's (each within print_match_steps steps) at one alignment.
struct print_match {
  std::size_t first = 0;        ///< index of the stretch's first dwell in the run
  std::size_t first_print = 0;  ///< the same dwell's index in the printed run
  std::size_t length = 0;       ///< dwells in the stretch
};

/// The longest stretch of at least print_window + 2 consecutive dwells of a run (its dwell
/// rates) that are the printed run's at one alignment (any shift: a trimmed or split copy, a copy
/// shifted in time); nullopt if none (an independent run: no false copy in 1320 independent pairs,
/// bench/copy_null.py, docs/PERFORMANCE.md). Cost: about n m / print_window comparisons.
[[nodiscard]] std::optional<print_match> find_in_print(std::span<const double> dwell_rates,
                                                       const cycle_print& print);

}  // namespace gyroflip::method
