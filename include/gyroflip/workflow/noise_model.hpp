/// \file
/// \brief The noise the simulator draws, as the gap two-sample variance of dwell means: the
/// noise model of method::harmonic_crlb (the Cramer-Rao bound of an N-position run) for a
/// simulated run (issue 33 item 2; docs/METHOD-NOTES.md, "N-position indexing").
#pragma once

#include <functional>

#include "gyroflip/rig/simulator.hpp"

namespace gyroflip::workflow {

/// sigma^2(tau, S) of two dwell means of length `dwell_s` whose starts are S >= dwell_s apart
/// (Barnes 1971), for the noise simulator `sim` draws: its white noise (the gyro's N and the
/// ADC's rms per conversion over the scale factor, N_adc^2 = s^2 t_conv), its rate random walk
/// K^2 (3S - tau)/6 and its flicker exactly as drawn, the bank of Gauss-Markov processes of
/// sensor/error_terms.hpp (two time constants per decade over [flicker_tau_min_s,
/// flicker_tau_max_s], each of variance B^2 ln(r)/pi; method::gauss_markov_gap_avar each).
/// The deterministic parts (temperature drift, a warm-up) are not noise: the bound's nuisance.
[[nodiscard]] std::function<double(double)> simulated_dwell_gap_avar(const rig::simulator& sim,
                                                                     double dwell_s);

/// The white density (deg/s/sqrt(Hz)) that function uses: sqrt(N^2 + N_adc^2).
[[nodiscard]] double simulated_white_arw(const rig::simulator& sim);

}  // namespace gyroflip::workflow
