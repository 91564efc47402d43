/// \file
/// \brief Several calibration runs (power-ups) together: the pooled mean's correlated error and
/// the dN model of the runs (random effects, a dN(T) line when their temperatures span enough).
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "gyroflip/core/result.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/delta_n_model.hpp"

namespace gyroflip::method {

/// The pooled mean's correlated standard error from the runs' own (independent runs):
/// se = sqrt(sum (n_i se_i)^2) / sum n_i, n_i the runs' cycles.
[[nodiscard]] double pooled_correlated_stderr(std::span<const calibration> runs);

/// Runs' temperatures spanning at least this much (degC) get a dN(T) line by default.
inline constexpr double min_model_span_c = 2.0;

/// The dN model of several runs: degree `degree` when given, else 1 when the runs' temperatures
/// span min_model_span_c or more and 0 otherwise (the weighted mean, with the run-to-run scatter
/// in its error: paper Tab. 3's repeat runs at one temperature; fit_delta_n_random_effects). Runs
/// without a temperature give a constant whose temperatures are NaN. Fewer than two runs: no
/// model. Errors: those of fit_delta_n_model.
[[nodiscard]] result<std::optional<delta_n_model>> fit_runs_model(
    std::span<const calibration> runs, std::optional<std::size_t> degree = std::nullopt);

}  // namespace gyroflip::method
