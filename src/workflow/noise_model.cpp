/// \file
/// \brief The simulator's noise as the gap two-sample variance of dwell means (noise_model.hpp).
#include "gyroflip/workflow/noise_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gyroflip/method/harmonic.hpp"

namespace gyroflip::workflow {

double simulated_white_arw(const rig::simulator& sim) {
  const auto& p = sim.config().sensor;
  const double adc_dps = sim.adc().noise_v_rms() / p.scale_factor_v_per_dps;
  return std::sqrt(p.arw_dps_rthz * p.arw_dps_rthz + adc_dps * adc_dps * sim.conversion_time_s());
}

std::function<double(double)> simulated_dwell_gap_avar(const rig::simulator& sim, double dwell_s) {
  const auto& p = sim.config().sensor;
  std::vector<double> bank_t;
  double bank_q = 0.0;
  if (p.bias_instability_dps > 0.0) {  // as sensor::flicker_bank builds it
    const double decades = std::log10(p.flicker_tau_max_s / p.flicker_tau_min_s);
    const auto n = static_cast<std::size_t>(std::max(2.0, std::round(2.0 * decades) + 1.0));
    const double ln_r =
        std::log(p.flicker_tau_max_s / p.flicker_tau_min_s) / static_cast<double>(n - 1);
    bank_q = p.bias_instability_dps * p.bias_instability_dps * ln_r / std::numbers::pi;
    for (std::size_t j = 0; j < n; ++j)
      bank_t.push_back(p.flicker_tau_min_s * std::exp(ln_r * static_cast<double>(j)));
  }
  const double white = simulated_white_arw(sim);
  const double kk = p.rrw_dps_per_rts * p.rrw_dps_per_rts;
  return [bank_t, bank_q, white, kk, dwell_s](double spacing_s) {
    const double s = std::max(spacing_s, dwell_s);
    double v = white * white / dwell_s + kk * (3.0 * s - dwell_s) / 6.0;
    for (const double t : bank_t) v += method::gauss_markov_gap_avar(bank_q, t, dwell_s, s);
    return v;
  };
}

}  // namespace gyroflip::workflow
