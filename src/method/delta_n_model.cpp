/// \file
/// \brief Polynomial dN(T) fit (see delta_n_model.hpp) by the library's weighted least squares
/// (analysis/least_squares.hpp); temperatures are centred on their mean.
#include "gyroflip/method/delta_n_model.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/least_squares.hpp"
#include "gyroflip/core/error.hpp"

namespace gyroflip::method {
namespace {

double power(double x, std::size_t k) {
  double p = 1.0;
  for (std::size_t i = 0; i < k; ++i) p *= x;
  return p;
}

}  // namespace

double delta_n_model::eval(double temp_c) const noexcept {
  if (coeffs_dps.size() == 1) return coeffs_dps[0];
  const double x = temp_c - t_ref_c;
  double v = 0.0;
  for (std::size_t k = coeffs_dps.size(); k-- > 0;) v = v * x + coeffs_dps[k];  // Horner
  return v;
}

double delta_n_model::stderr_at(double temp_c) const noexcept {
  const std::size_t n = coeffs_dps.size();
  if (cov.size() != n * n) return 0.0;
  const double x = n == 1 ? 0.0 : temp_c - t_ref_c;
  double var = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) var += power(x, i) * cov[i * n + j] * power(x, j);
  return std::sqrt(std::max(var, 0.0));
}

double delta_n_model::interval_at(double temp_c) const {
  const double se = stderr_at(temp_c);
  return random_effects ? analysis::t_one_sigma(static_cast<double>(dof)) * se : se;
}

double delta_n_model::new_run_interval_at(double temp_c) const {
  if (!std::isfinite(new_run_var_dps2)) return std::numeric_limits<double>::quiet_NaN();
  const double se = stderr_at(temp_c);
  return analysis::t_one_sigma(static_cast<double>(dof)) * std::sqrt(se * se + new_run_var_dps2);
}

delta_n_model constant_model(double delta_n_dps, double stderr_dps) {
  delta_n_model m;
  m.coeffs_dps = {delta_n_dps};
  m.cov = {stderr_dps * stderr_dps};
  return m;
}

result<delta_n_model> fit_delta_n_model(std::span<const delta_n_point> points, std::size_t degree) {
  if (degree > max_model_degree)
    return parameter_error("degree", fmt::format("the dN(T) degree {} is above the maximum {}",
                                                 degree, max_model_degree));
  std::set<double> temps;
  for (const auto& p : points) {
    if (!std::isfinite(p.temp_c) || !std::isfinite(p.delta_n_dps) || !std::isfinite(p.stderr_dps))
      return usage_error(
          "a temperature model needs a finite temperature and dN for every calibration");
    temps.insert(p.temp_c);
  }
  if (temps.size() < degree + 1)
    return usage_error(
        fmt::format("a degree-{} dN(T) model needs calibrations at {} or more different "
                    "temperatures; got {}",
                    degree, degree + 1, temps.size()));
  const std::size_t n = degree + 1;
  // Errors at rounding level (noise-free data) carry no information about relative weight.
  double scale_dps = 0.0;
  for (const auto& p : points) scale_dps = std::max(scale_dps, std::abs(p.delta_n_dps));
  const double meaningful_dps = 1e-12 * scale_dps;
  const bool weighted = std::all_of(points.begin(), points.end(),
                                    [&](const auto& p) { return p.stderr_dps > meaningful_dps; });
  delta_n_model m;
  double t_sum = 0.0;
  for (const auto& p : points) t_sum += p.temp_c;
  m.t_ref_c = t_sum / static_cast<double>(points.size());
  m.temp_min_c = *temps.begin();
  m.temp_max_c = *temps.rbegin();
  std::vector<double> design;
  std::vector<double> y;
  std::vector<double> w;
  for (const auto& p : points) {
    const double x = p.temp_c - m.t_ref_c;
    for (std::size_t i = 0; i < n; ++i) design.push_back(power(x, i));
    y.push_back(p.delta_n_dps);
    w.push_back(weighted ? 1.0 / (p.stderr_dps * p.stderr_dps) : 1.0);
  }
  auto fit = analysis::weighted_least_squares(design, n, y, w);
  if (!fit) return runtime_error("dN(T) fit is singular (temperatures too close together)");
  m.coeffs_dps = fit->coeffs;
  const double chi2 = fit->chi2;
  const std::size_t dof = points.size() - n;
  m.chi2_per_dof = dof > 0 ? chi2 / static_cast<double>(dof) : 0.0;
  // Unweighted: the residual variance is the only scale. Weighted: inflate by the Birge ratio.
  const double scale = weighted ? std::max(1.0, m.chi2_per_dof) : m.chi2_per_dof;
  m.cov = fit->cov;
  for (double& v : m.cov) v *= scale;
  return m;
}

result<delta_n_model> fit_delta_n_random_effects(std::span<const delta_n_point> points,
                                                 std::size_t degree) {
  // The weighted fit checks the input and gives the centring, range and design.
  auto base = fit_delta_n_model(points, degree);
  if (!base) return base.err();
  delta_n_model m = std::move(*base);
  const std::size_t k = points.size();
  const std::size_t p = degree + 1;
  m.random_effects = true;
  m.dof = k - p;
  struct {
    std::vector<double> design, y, v;  // design row-major, centred as the weighted fit's
  } d;
  for (const auto& pt : points) {
    for (std::size_t i = 0; i < p; ++i) d.design.push_back(power(pt.temp_c - m.t_ref_c, i));
    d.y.push_back(pt.delta_n_dps);
    d.v.push_back(pt.stderr_dps * pt.stderr_dps);
  }
  if (m.dof == 0) {  // through its runs: no scatter to estimate, no error
    m.between_run_var_dps2 = std::numeric_limits<double>::quiet_NaN();
    std::fill(m.cov.begin(), m.cov.end(), 0.0);
    return m;
  }
  // Within-run errors at rounding level (noise-free data) carry no weight information: then
  // every run has the same weight and tau^2 is the residual variance.
  double scale_dps = 0.0;
  for (const auto& pt : points) scale_dps = std::max(scale_dps, std::abs(pt.delta_n_dps));
  const bool weighted = std::all_of(points.begin(), points.end(), [&](const auto& pt) {
    return pt.stderr_dps > 1e-12 * scale_dps;
  });
  std::vector<double> w(k);
  for (std::size_t i = 0; i < k; ++i) w[i] = weighted ? 1.0 / d.v[i] : 1.0;
  double tau2 = 0.0;
  if (weighted) {
    // DerSimonian-Laird: Q = sum w r^2 of the fixed-effect fit, trace of P = W - WX(X'WX)^-1X'W.
    auto fe = analysis::weighted_least_squares(d.design, p, d.y, w);
    if (!fe) return runtime_error("dN(T) fit is singular (temperatures too close together)");
    double sum_w = 0.0;
    std::vector<double> xw2x(p * p, 0.0);
    for (std::size_t i = 0; i < k; ++i) {
      sum_w += w[i];
      for (std::size_t a = 0; a < p; ++a)
        for (std::size_t b = 0; b < p; ++b)
          xw2x[a * p + b] += d.design[i * p + a] * w[i] * w[i] * d.design[i * p + b];
    }
    double trace = 0.0;  // tr((X'WX)^-1 X'W^2X)
    for (std::size_t a = 0; a < p; ++a)
      for (std::size_t b = 0; b < p; ++b) trace += fe->cov[a * p + b] * xw2x[b * p + a];
    const double denom = sum_w - trace;
    tau2 = denom > 0.0 ? std::max(0.0, (fe->chi2 - static_cast<double>(m.dof)) / denom) : 0.0;
    for (std::size_t i = 0; i < k; ++i) w[i] = 1.0 / (d.v[i] + tau2);
  }
  auto re = analysis::weighted_least_squares(d.design, p, d.y, w);
  if (!re) return runtime_error("dN(T) fit is singular (temperatures too close together)");
  m.coeffs_dps = re->coeffs;
  // Knapp-Hartung: the covariance scaled by the weighted residual variance (unweighted: the
  // ordinary least-squares covariance, the same thing with equal weights).
  const double q = re->chi2 / static_cast<double>(m.dof);
  m.cov = re->cov;
  for (double& c : m.cov) c *= q;
  // A new run: weight 1/(tau^2 + v) with v the runs' mean within-run variance, on the same
  // scale q (equal weights of 1: q itself, the residual variance of ordinary least squares).
  double v_mean = 0.0;
  for (const double v : d.v) v_mean += v / static_cast<double>(k);
  m.new_run_var_dps2 = weighted ? q * (tau2 + v_mean) : q;
  if (!weighted) {
    tau2 = q;  // equal weights of 1: q is the residual variance, all of it between runs
  }
  m.between_run_var_dps2 = tau2;
  return m;
}

}  // namespace gyroflip::method
