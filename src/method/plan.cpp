/// \file
/// \brief The flip-period planner (plan.hpp; derivations in docs/PLANNER.md).
#include "gyroflip/method/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "gyroflip/core/error.hpp"

namespace gyroflip::method {
namespace {

constexpr double pi = std::numbers::pi;

// Flicker FM's two-sample variance with gap, over B^2/(2 pi), at r = T/tau >= 1:
// g(r) = (r+1)^2 ln(r+1) + (r-1)^2 ln(r-1) - 2 r^2 ln r (docs/PLANNER.md, from the phase
// structure function D_x(s) = -(B^2/pi) s^2 ln s). g(1) = 4 ln 2 (Allan: 2 ln2/pi B^2). For
// large r the three terms cancel to 2 ln r + 3 - 1/(6r^2) - ...: the series is used there.
double flicker_g_tail(double r) noexcept {
  const double x = 1.0 / (r * r);
  return 3.0 - x * (1.0 / 6 + x * (1.0 / 30 + x * (1.0 / 84 + x * (1.0 / 180))));
}

constexpr double series_from_r = 20.0;  // next series term there: 3e-16

double flicker_g(double r) noexcept {
  if (r >= series_from_r) return 2.0 * std::log(r) + flicker_g_tail(r);
  const double rm = r - 1.0;
  const double lower = rm > 0.0 ? rm * rm * std::log(rm) : 0.0;
  return (r + 1.0) * (r + 1.0) * std::log(r + 1.0) + lower - 2.0 * r * r * std::log(r);
}

// g(r + rho) + g(r - rho) - 2 g(r) with r = m rho (m >= 2): the covariance of two pairs'
// differences m dwells apart, over B^2/(2 pi). In the series region the logs combine exactly into
// 2 ln(1 - 1/m^2), which keeps the small difference free of cancellation.
double flicker_second_difference(double m, double rho) noexcept {
  const double r = m * rho;
  if (r - rho >= series_from_r)
    return 2.0 * std::log1p(-1.0 / (m * m)) + flicker_g_tail(r + rho) + flicker_g_tail(r - rho) -
           2.0 * flicker_g_tail(r);
  return flicker_g(r + rho) + flicker_g(r - rho) - 2.0 * flicker_g(r);
}

// Pairs beyond this lag enter through the asymptotic sum: their second difference is
// 2 ln(1 - 1/m^2) + O(m^-4) ~ -2/m^2 (relative error < 1e-6 from here on).
constexpr std::size_t exact_lags = 2048;

// sum_{g=1}^{M-1} (M - g) C(2g) / (B^2/(2 pi)) for the flicker term.
double flicker_cross_sum(std::size_t pairs, double rho) noexcept {
  const std::size_t last = pairs - 1;
  const std::size_t exact = std::min(last, exact_lags);
  const double m_pairs = static_cast<double>(pairs);
  double sum = 0.0;
  for (std::size_t g = 1; g <= exact; ++g)
    sum += (m_pairs - static_cast<double>(g)) *
           flicker_second_difference(2.0 * static_cast<double>(g), rho);
  if (last > exact) {
    // sum_{g=a}^{b} (M - g)(-2/(4 g^2)) by the midpoint integrals of 1/g^2 and 1/g.
    const double a = static_cast<double>(exact) + 0.5, b = static_cast<double>(last) + 0.5;
    sum += -0.5 * (m_pairs * (1.0 / a - 1.0 / b) - std::log(b / a));
  }
  return sum;
}

bool finite_non_negative(double v) noexcept {
  return std::isfinite(v) && v >= 0.0;
}

}  // namespace

double gap_avar(const plan_noise& n, double tau_s, double spacing_s) noexcept {
  const double r = spacing_s / tau_s;
  const bool adjacent = r <= 1.0 + 1e-12;
  const double q = n.quantization_deg, w = n.arw_dps_rthz, b = n.bias_instability_dps,
               k = n.rrw_dps_per_rts;
  const double white_pm = (adjacent ? 3.0 : 2.0) * q * q / (tau_s * tau_s);
  const double white_fm = w * w / tau_s;
  const double flicker = b * b / (2.0 * pi) * flicker_g(std::max(r, 1.0));
  const double walk = k * k * (3.0 * std::max(spacing_s, tau_s) - tau_s) / 6.0;
  return white_pm + white_fm + flicker + walk;
}

double flip_mean_variance(const plan_noise& n, double tau_s, double dead_s,
                          std::size_t pairs) noexcept {
  if (pairs == 0) return std::numeric_limits<double>::infinity();
  const double spacing = tau_s + dead_s;
  const double m = static_cast<double>(pairs);
  double v = gap_avar(n, tau_s, spacing) / (2.0 * m);
  // Between pairs only flicker is correlated: white PM/FM give a constant and random-walk FM a
  // linear gap_avar beyond the first lag, whose second differences vanish.
  const double b = n.bias_instability_dps;
  if (b > 0.0 && pairs > 1)
    v += b * b / (2.0 * pi) * flicker_cross_sum(pairs, spacing / tau_s) / (2.0 * m * m);
  return v;
}

std::size_t pairs_in(double duration_s, double tau_s, double dead_s) noexcept {
  const double p = std::floor(duration_s / (2.0 * (tau_s + dead_s)));
  return p > 0.0 ? static_cast<std::size_t>(p) : 0;
}

flip_plan_closed_form plan_flip_closed_form(const plan_noise& n, double dead_s,
                                            double duration_s) noexcept {
  constexpr double flicker_avar = 2.0 * std::numbers::ln2 / pi;  // 0.4413: ADEV floor 0.664 B
  const double w = n.arw_dps_rthz, b = n.bias_instability_dps;
  flip_plan_closed_form c;
  if (b > 0.0) {
    c.corner_tau_s = w * w / (flicker_avar * b * b);
    c.dwell_s = std::sqrt(dead_s * c.corner_tau_s);
  }
  c.sigma_dps = (w + std::sqrt(flicker_avar) * b * std::sqrt(dead_s)) / std::sqrt(duration_s);
  return c;
}

namespace {

double sigma_at(const plan_noise& n, double tau_s, double dead_s, double duration_s) {
  return std::sqrt(flip_mean_variance(n, tau_s, dead_s, pairs_in(duration_s, tau_s, dead_s)));
}

std::vector<double> log_grid(double lo, double hi, std::size_t points) {
  std::vector<double> g(points);
  for (std::size_t i = 0; i < points; ++i) {
    const double f = points > 1 ? static_cast<double>(i) / static_cast<double>(points - 1) : 0.0;
    g[i] = lo * std::pow(hi / lo, f);
  }
  return g;
}

// Golden-section search for the minimum of sigma over log tau in [lo, hi].
double refine(const plan_noise& n, double dead_s, double duration_s, double lo, double hi) {
  constexpr double inv_phi = 0.6180339887498949;
  double a = std::log(lo), b = std::log(hi);
  const auto f = [&](double u) { return sigma_at(n, std::exp(u), dead_s, duration_s); };
  double c = b - inv_phi * (b - a), d = a + inv_phi * (b - a);
  double fc = f(c), fd = f(d);
  for (int i = 0; i < 60 && b - a > 1e-6; ++i) {
    if (fc <= fd) {
      b = d, d = c, fd = fc;
      c = b - inv_phi * (b - a), fc = f(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + inv_phi * (b - a), fd = f(d);
    }
  }
  return std::exp(fc <= fd ? c : d);
}

status check_plan_inputs(const plan_noise& n, double dead_s, double duration_s,
                         const plan_limits& limits) {
  for (const double v :
       {n.quantization_deg, n.arw_dps_rthz, n.bias_instability_dps, n.rrw_dps_per_rts})
    if (!finite_non_negative(v))
      return usage_error("the noise terms must be finite and non-negative");
  if (n.quantization_deg == 0.0 && n.arw_dps_rthz == 0.0 && n.bias_instability_dps == 0.0 &&
      n.rrw_dps_per_rts == 0.0)
    return usage_error("no noise to plan against: every noise term is zero");
  if (!finite_non_negative(dead_s)) return usage_error("the dead time must be finite and >= 0 s");
  if (!(std::isfinite(limits.min_dwell_s) && limits.min_dwell_s > 0.0))
    return usage_error("the shortest dwell must be finite and > 0 s");
  if (!(std::isfinite(duration_s) && duration_s >= 4.0 * (limits.min_dwell_s + dead_s)))
    return usage_error("the run must hold at least two pairs of the shortest dwell");
  if (limits.curve_points < 3) return usage_error("a curve needs at least 3 points");
  return ok();
}

}  // namespace

result<flip_plan> plan_flip(const plan_noise& n, double dead_s, double duration_s,
                            const plan_limits& limits) {
  if (auto s = check_plan_inputs(n, dead_s, duration_s, limits); !s) return s.err();
  const double lo = limits.min_dwell_s;
  double hi = duration_s / 4.0 - dead_s;  // two pairs at least
  if (limits.max_dwell_s > 0.0) hi = std::min(hi, limits.max_dwell_s);
  if (!(hi > lo)) return usage_error("the longest dwell must exceed the shortest");

  flip_plan p;
  p.dead_s = dead_s;
  p.duration_s = duration_s;
  const auto grid = log_grid(lo, hi, limits.curve_points);
  std::size_t best = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    p.by_dwell.push_back({grid[i], sigma_at(n, grid[i], dead_s, duration_s)});
    if (p.by_dwell[i].sigma_dps < p.by_dwell[best].sigma_dps) best = i;
  }
  const double a = grid[best > 0 ? best - 1 : 0];
  const double b = grid[std::min(best + 1, grid.size() - 1)];
  const double tau = refine(n, dead_s, duration_s, a, b);
  const double tau_sigma = sigma_at(n, tau, dead_s, duration_s);
  p.dwell_s = tau_sigma <= p.by_dwell[best].sigma_dps ? tau : grid[best];
  p.sigma_dps = sigma_at(n, p.dwell_s, dead_s, duration_s);
  p.period_s = 2.0 * (p.dwell_s + dead_s);
  p.sigma_no_dead_dps = sigma_at(n, p.dwell_s, 0.0, duration_s);
  p.closed_form = plan_flip_closed_form(n, dead_s, duration_s);
  for (const double t : log_grid(2.0 * p.period_s, duration_s, 25))
    p.by_duration.push_back({t, sigma_at(n, p.dwell_s, dead_s, t)});
  return p;
}

}  // namespace gyroflip::method
