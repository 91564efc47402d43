/// \file
/// \brief Compensation, paper eqn 12: w_in = r - dN, per cycle, and its summary.
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "gyroflip/core/result.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// One compensated cycle.
struct compensated_cycle {
  double time_s = 0.0;
  double rate_dps = 0.0;  ///< w_in = r - dN(T)  (paper eqn 12)
  double bias_dps = 0.0;  ///< c, the bias the flip removed
  double temp_c = no_value;
  double delta_n_dps = 0.0;  ///< the dN that was subtracted
};

/// Paper eqn 12 for one cycle, with dN evaluated at the cycle's temperature.
[[nodiscard]] compensated_cycle compensate(const cycle& c, const delta_n_model& dn) noexcept;

/// Statistics of a compensated series (paper Figs. 4-10 quote mean and std).
struct compensation_summary {
  std::size_t cycles = 0;
  double mean_dps = 0.0;
  double std_dps = 0.0;
  double stderr_dps = 0.0;
  double stderr_correlated_dps = 0.0;
  std::optional<double> drift_dps;  ///< max - min of the moving mean (none if too short)
  double drift_window_s = 0.0;
  double duration_s = 0.0;
};

/// Default moving-mean window for `drift_dps` (s).
inline constexpr double drift_window_default_s = 100.0;
/// Longest moving-mean window (s): 1e9 s, some 30 years.
inline constexpr double drift_window_max_s = 1e9;

/// The rules for a dN a user gives as a number (`compensate --delta-n`, Python's
/// `delta_n_dps`): finite, |dN| <= max_input_magnitude (deg/s), as any number gyroflip reads.
/// Error (parameter `delta_n_dps`) otherwise.
[[nodiscard]] status check_delta_n(double delta_n_dps);

/// The rules for the drift's moving-mean window (`--drift-window`, `drift_window_s`): in
/// (0, drift_window_max_s] s. Error (parameter `window_s`) otherwise.
[[nodiscard]] status check_drift_window(double window_s);

/// Mean, std, standard errors and drift (moving-mean range over `window_s`).
/// Precondition: at least one cycle.
[[nodiscard]] compensation_summary summarize(std::span<const compensated_cycle> cycles,
                                             double window_s = drift_window_default_s);

}  // namespace gyroflip::method
