/// \file
/// \brief The flip-period planner (plan.hpp; derivations in docs/PLANNER.md).
#include "gyroflip/method/plan.hpp"

#include <algorithm>
#include <array>
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

// Golden-section search for the minimum of f over log tau in [lo, hi].
template <class F>
double refine(const F& sigma_of, double lo, double hi) {
  constexpr double inv_phi = 0.6180339887498949;
  double a = std::log(lo), b = std::log(hi);
  const auto f = [&](double u) { return sigma_of(std::exp(u)); };
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

// The dwell in [lo, hi] that minimises sigma_of: a log-spaced scan (the curve by_dwell), then
// golden-section refinement between the lowest point's neighbours. Sets dwell_s and by_dwell.
template <class F>
void search_dwell(const F& sigma_of, double lo, double hi, std::size_t points, flip_plan& p) {
  const auto grid = log_grid(lo, hi, points);
  std::size_t best = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    p.by_dwell.push_back({grid[i], sigma_of(grid[i])});
    if (p.by_dwell[i].sigma_dps < p.by_dwell[best].sigma_dps) best = i;
  }
  const double a = grid[best > 0 ? best - 1 : 0];
  const double b = grid[std::min(best + 1, grid.size() - 1)];
  const double tau = refine(sigma_of, a, b);
  p.dwell_s = sigma_of(tau) <= p.by_dwell[best].sigma_dps ? tau : grid[best];
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
  search_dwell([&](double tau) { return sigma_at(n, tau, dead_s, duration_s); }, lo, hi,
               limits.curve_points, p);
  p.sigma_dps = sigma_at(n, p.dwell_s, dead_s, duration_s);
  p.period_s = 2.0 * (p.dwell_s + dead_s);
  p.sigma_no_dead_dps = sigma_at(n, p.dwell_s, 0.0, duration_s);
  p.closed_form = plan_flip_closed_form(n, dead_s, duration_s);
  for (const double t : log_grid(2.0 * p.period_s, duration_s, 25))
    p.by_duration.push_back({t, sigma_at(n, p.dwell_s, dead_s, t)});
  return p;
}

}  // namespace gyroflip::method

namespace gyroflip::method {

std::vector<double> sweep_visits(std::span<const double> angles_deg) {
  std::vector<double> out(angles_deg.begin(), angles_deg.end());
  out.insert(out.end(), angles_deg.rbegin(), angles_deg.rend());
  return out;
}

namespace {

// Solves the symmetric positive definite system a x = b (a n x n row-major, n <= 4) in place by
// Gaussian elimination with partial pivoting; false when singular to working precision.
bool solve_small(std::vector<double> a, std::vector<double>& b, std::size_t n) {
  double scale = 0.0;
  for (const double v : a) scale = std::max(scale, std::abs(v));
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[piv * n + c])) piv = r;
    if (!(std::abs(a[piv * n + c]) > 1e-10 * scale)) return false;
    for (std::size_t k = 0; k < n; ++k) std::swap(a[c * n + k], a[piv * n + k]);
    std::swap(b[c], b[piv]);
    for (std::size_t r = 0; r < n; ++r) {
      if (r == c) continue;
      const double f = a[r * n + c] / a[c * n + c];
      for (std::size_t k = 0; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (std::size_t c = 0; c < n; ++c) b[c] /= a[c * n + c];
  return true;
}

// Periods this many apart and closer are summed exactly. Each period's weights have zero sum and
// zero first moment (the slope is fitted), so white and random-walk terms vanish beyond the first
// lag, and the flicker's cross terms (D(s) ~ -s^2 ln s) fall off as lag^-2 (its fourth
// derivative): beyond, the sum is continued from the last exact lag by that law.
constexpr std::size_t indexed_exact_lags = 64;

}  // namespace

result<indexed_period> indexed_period_of(std::span<const double> visit_deg, double tau_s,
                                         double dead_s) {
  std::vector<double> distinct;
  for (const double a : visit_deg) {
    if (!std::isfinite(a)) return usage_error("the positions' angles must be finite");
    if (std::find(distinct.begin(), distinct.end(), a) == distinct.end()) distinct.push_back(a);
  }
  if (distinct.size() < 3)
    return usage_error(
        "an indexed plan needs at least three distinct positions (two: the flip plan)");
  indexed_period p;
  p.dwell_s = tau_s;
  p.visit_deg.assign(visit_deg.begin(), visit_deg.end());
  const std::size_t k_n = p.visit_deg.size();
  double t = 0.0;
  for (std::size_t k = 0; k < k_n; ++k) {
    if (k > 0) t += tau_s + (p.visit_deg[k] != p.visit_deg[k - 1] ? dead_s : 0.0);
    p.start_s.push_back(t);
  }
  p.period_s = t + tau_s + (visit_deg.front() != visit_deg.back() ? dead_s : 0.0);
  // The design [1, t - mean t, cos, sin] per dwell (mid-dwell times), its normal matrix, and the
  // rows of (X'X)^-1 X' for c1 and s1.
  constexpr std::size_t cols = 4;
  double t_mean = 0.0;
  for (const double s : p.start_s) t_mean += s + 0.5 * tau_s;
  t_mean /= static_cast<double>(k_n);
  std::vector<std::array<double, cols>> x(k_n);
  for (std::size_t k = 0; k < k_n; ++k) {
    const double a = p.visit_deg[k] * std::numbers::pi / 180.0;
    const double span = std::max(p.period_s, 1e-12);
    x[k] = {1.0, (p.start_s[k] + 0.5 * tau_s - t_mean) / span, std::cos(a), std::sin(a)};
  }
  std::vector<double> xtx(cols * cols, 0.0);
  for (const auto& row : x)
    for (std::size_t i = 0; i < cols; ++i)
      for (std::size_t j = 0; j < cols; ++j) xtx[i * cols + j] += row[i] * row[j];
  for (std::size_t k = 0; k < k_n; ++k) {
    std::vector<double> rhs(x[k].begin(), x[k].end());
    if (!solve_small(xtx, rhs, cols))
      return usage_error(
          "these positions' visiting period cannot separate the first harmonic from a bias and "
          "its slope");
    p.weight_c.push_back(rhs[2]);
    p.weight_s.push_back(rhs[3]);
  }
  return p;
}

harmonic_variance indexed_run_variance(const plan_noise& n, const indexed_period& p,
                                       std::size_t periods) noexcept {
  harmonic_variance v;
  if (periods == 0) {
    v.var_c1 = v.var_s1 = std::numeric_limits<double>::infinity();
    return v;
  }
  const std::size_t k_n = p.start_s.size();
  const double tau_s = p.dwell_s;
  const auto g = [&](std::size_t lag, const std::vector<double>& wa,
                     const std::vector<double>& wb) {
    // G(L) = -1/2 sum_jk wa_j wb_k D(|t_j - t_k + L P|), D(0) = 0.
    double s = 0.0;
    const double shift = static_cast<double>(lag) * p.period_s;
    for (std::size_t j = 0; j < k_n; ++j)
      for (std::size_t k = 0; k < k_n; ++k) {
        const double sep = std::abs(p.start_s[j] - p.start_s[k] + shift);
        if (sep <= 0.0) continue;
        s -= wa[j] * wb[k] * gap_avar(n, tau_s, std::max(sep, tau_s));
      }
    return s;  // -1/2 x 2 gap_avar
  };
  const auto m = static_cast<double>(periods);
  const std::size_t last = std::min(periods - 1, indexed_exact_lags);
  const auto total = [&](const std::vector<double>& wa, const std::vector<double>& wb) {
    double s = m * g(0, wa, wb), g_last = 0.0;
    for (std::size_t lag = 1; lag <= last; ++lag) {
      g_last = g(lag, wa, wb) + g(lag, wb, wa);
      s += (m - static_cast<double>(lag)) * g_last;
    }
    if (periods - 1 > last) {
      // sum_{L=last+1}^{periods-1} (m - L) g_last (last/L)^2 by the midpoint integrals.
      const double l = static_cast<double>(last);
      const double a = l + 0.5, b = static_cast<double>(periods - 1) + 0.5;
      s += g_last * l * l * (m * (1.0 / a - 1.0 / b) - std::log(b / a));
    }
    return s / (m * m);
  };
  v.var_c1 = total(p.weight_c, p.weight_c);
  v.var_s1 = total(p.weight_s, p.weight_s);
  v.cov = total(p.weight_c, p.weight_s);
  return v;
}

namespace {

std::size_t periods_in(double duration_s, const indexed_period& p) noexcept {
  const double k = std::floor(duration_s / p.period_s);
  return k > 0.0 ? static_cast<std::size_t>(k) : 0;
}

}  // namespace

result<flip_plan> plan_indexed(const plan_noise& n, std::span<const double> visit_deg,
                               double dead_s, double duration_s, const plan_limits& limits) {
  if (auto s = check_plan_inputs(n, dead_s, duration_s, limits); !s) return s.err();
  auto probe = indexed_period_of(visit_deg, limits.min_dwell_s, dead_s);
  if (!probe) return probe.err();
  const double dwells = static_cast<double>(visit_deg.size());
  const double lo = limits.min_dwell_s;
  // three periods at least
  double hi = (duration_s / 3.0 - (probe->period_s - dwells * lo)) / dwells;
  if (limits.max_dwell_s > 0.0) hi = std::min(hi, limits.max_dwell_s);
  if (!(hi > lo))
    return usage_error("the run must hold at least three visiting periods of the shortest dwell");
  const auto sigma_of = [&](double tau, double dead, double run) {
    auto p = indexed_period_of(visit_deg, tau, dead);
    if (!p) return std::numeric_limits<double>::infinity();
    return std::sqrt(indexed_run_variance(n, *p, periods_in(run, *p)).mean_var());
  };
  flip_plan p;
  p.dead_s = dead_s;
  p.duration_s = duration_s;
  search_dwell([&](double tau) { return sigma_of(tau, dead_s, duration_s); }, lo, hi,
               limits.curve_points, p);
  p.sigma_dps = sigma_of(p.dwell_s, dead_s, duration_s);
  p.period_s = indexed_period_of(visit_deg, p.dwell_s, dead_s)->period_s;
  p.sigma_no_dead_dps = sigma_of(p.dwell_s, 0.0, duration_s);
  p.closed_form = plan_flip_closed_form(n, dead_s, duration_s);
  for (const double t : log_grid(3.0 * p.period_s, duration_s, 25))
    p.by_duration.push_back({t, sigma_of(p.dwell_s, dead_s, t)});
  return p;
}

}  // namespace gyroflip::method
