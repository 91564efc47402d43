/// \file
/// \brief Polynomial dN(T) fit (see delta_n_model.hpp) by the library's weighted least squares
/// (analysis/least_squares.hpp); temperatures are centred on their mean.
#include "gyroflip/method/delta_n_model.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <utility>

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

// The moment estimate of tau^2(T) = t0 + t1 x^2 (x = T - T_ref) from a weighted fit's residuals
// (docs/METHOD-NOTES.md, "A run-to-run spread that depends on temperature"). The fit is the
// linear smoother y_hat = X A X'W y, A = (X'WX)^-1, so the residuals are r = R y with R = I - X A
// X'W, and for independent runs of variance S_j = v_j + t0 + t1 x_j^2, E r_i^2 = sum_j R_ij^2
// S_j: linear in (t0, t1), solved by least squares over the runs (as MINQUE-like moment
// estimators; Rao 1970, J. Am. Stat. Assoc. 65, 161-172).
struct spread_moments {
  std::size_t k = 0, p = 0;
  std::vector<double> x, v, w, design, a_inv, r_op, z, d0, d1, l0, l1;
  double t0 = 0.0, t1 = 0.0;
};

std::optional<spread_moments> estimate_spread(std::span<const delta_n_point> runs,
                                              std::span<const double> weights, double t_ref_c,
                                              std::size_t p) {
  spread_moments e;
  e.k = runs.size();
  e.p = p;
  const std::size_t k = e.k;
  std::vector<double> y;
  for (const auto& pt : runs) {
    e.x.push_back(pt.temp_c - t_ref_c);
    e.v.push_back(pt.stderr_dps * pt.stderr_dps);
    y.push_back(pt.delta_n_dps);
    for (std::size_t a = 0; a < p; ++a) e.design.push_back(power(e.x.back(), a));
  }
  e.w.assign(weights.begin(), weights.end());
  auto fit = analysis::weighted_least_squares(e.design, p, y, e.w);
  if (!fit) return std::nullopt;
  e.a_inv = fit->cov;
  e.r_op.assign(k * k, 0.0);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j) {
      double h = 0.0;
      for (std::size_t a = 0; a < p; ++a)
        for (std::size_t b = 0; b < p; ++b)
          h += e.design[i * p + a] * e.a_inv[a * p + b] * e.design[j * p + b];
      e.r_op[i * k + j] = (i == j ? 1.0 : 0.0) - h * e.w[j];
    }
  auto& d0 = e.d0;
  auto& d1 = e.d1;
  d0.assign(k, 0.0);
  d1.assign(k, 0.0);
  e.z.assign(k, 0.0);
  for (std::size_t i = 0; i < k; ++i) {
    double r = 0.0, mv = 0.0;
    for (std::size_t j = 0; j < k; ++j) {
      const double m = e.r_op[i * k + j] * e.r_op[i * k + j];
      r += e.r_op[i * k + j] * y[j];
      mv += m * e.v[j];
      d0[i] += m;
      d1[i] += m * e.x[j] * e.x[j];
    }
    e.z[i] = r * r - mv;
  }
  double s00 = 0.0, s01 = 0.0, s11 = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    s00 += d0[i] * d0[i];
    s01 += d0[i] * d1[i];
    s11 += d1[i] * d1[i];
  }
  const double det = s00 * s11 - s01 * s01;
  if (!(det > 1e-9 * s00 * s11)) return std::nullopt;  // the x^2 do not tell t0 from t1
  e.l0.resize(k);
  e.l1.resize(k);
  for (std::size_t i = 0; i < k; ++i) {
    e.l0[i] = (s11 * d0[i] - s01 * d1[i]) / det;
    e.l1[i] = (s00 * d1[i] - s01 * d0[i]) / det;
    e.t0 += e.l0[i] * e.z[i];
    e.t1 += e.l1[i] * e.z[i];
  }
  return e;
}

// The moment equations E z = t0 d0 + t1 d1 solved under t0 >= 0, t1 >= 0: non-negative least
// squares (Lawson & Hanson 1974, Solving Least Squares Problems, ch. 23; for two unknowns the
// active sets can be tried in turn: the unconstrained solution where it is feasible, else the
// feasible one-term fits and 0, the one of least residual). A variance function estimated
// negative at some temperature drew a band below the line's own error there (fifth review of
// issue 31, F14). Each estimate stays a linear combination l'z of the squared residuals, on the
// active set's own l (the Satterthwaite degrees of freedom below take that l).
void constrain_spread(spread_moments& e) {
  if (e.t0 >= 0.0 && e.t1 >= 0.0) return;
  const std::size_t k = e.k;
  const auto dot = [k](const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < k; ++i) s += a[i] * b[i];
    return s;
  };
  const double s00 = dot(e.d0, e.d0), s11 = dot(e.d1, e.d1);
  const auto residual = [&](double t0, double t1) {
    double ss = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
      const double r = e.z[i] - t0 * e.d0[i] - t1 * e.d1[i];
      ss += r * r;
    }
    return ss;
  };
  // Candidates: t1 = 0 (t0 fitted alone), t0 = 0 (t1 alone), both 0.
  double best = residual(0.0, 0.0);
  std::vector<double> l0(k, 0.0), l1(k, 0.0);
  const double only0 = s00 > 0.0 ? dot(e.d0, e.z) / s00 : -1.0;
  const double only1 = s11 > 0.0 ? dot(e.d1, e.z) / s11 : -1.0;
  if (only0 >= 0.0 && residual(only0, 0.0) < best) {
    best = residual(only0, 0.0);
    for (std::size_t i = 0; i < k; ++i) l0[i] = e.d0[i] / s00;
  }
  if (only1 >= 0.0 && residual(0.0, only1) < best) {
    std::fill(l0.begin(), l0.end(), 0.0);
    for (std::size_t i = 0; i < k; ++i) l1[i] = e.d1[i] / s11;
  }
  e.l0 = std::move(l0);
  e.l1 = std::move(l1);
  e.t0 = dot(e.l0, e.z);
  e.t1 = dot(e.l1, e.z);
}

// The run variances S_j = v_j + t0 + t1 x_j^2 (never below v_j) and the variance of a linear
// combination l'z of the squared residuals under them: 2 sum_il l_i l_l C_il^2, C = R S R'
// (Gaussian residuals).
double var_of_combination(const spread_moments& e, std::span<const double> l) {
  const std::size_t k = e.k;
  std::vector<double> s_run(k);
  for (std::size_t j = 0; j < k; ++j)
    s_run[j] = std::max(e.v[j] + e.t0 + e.t1 * e.x[j] * e.x[j], e.v[j]);
  double out = 0.0;
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t m = 0; m < k; ++m) {
      double c = 0.0;
      for (std::size_t j = 0; j < k; ++j) c += e.r_op[i * k + j] * s_run[j] * e.r_op[m * k + j];
      out += 2.0 * l[i] * l[m] * c * c;
    }
  return out;
}

// The smallest tau^2 / mean v_i at which tau^2(T) is estimated (the gate above).
constexpr double min_between_to_within_for_spread_model = 5.0;
// The smallest moment estimate of the curvature, in its own standard errors, at which tau^2(T)
// is used (a preliminary test, Bancroft 1944, Ann. Math. Stat. 15, 190-204): below it the runs do
// not resolve a spread that grows away from the middle and the constant tau^2 stands. A choice
// made on the simulations of docs/METHOD-NOTES.md: the truncated estimate alone (every campaign)
// over-covers the ends where the spread is constant (0.80) and where it grows (0.73-0.75), as
// truncation biases a curvature of 0 upwards; 1 standard error under-covers the ends where it
// grows (0.61).
constexpr double min_curvature_to_its_error = 0.85;

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
  if (std::isfinite(tau2_centre_dps2) && fitted_runs.size() == fitted_weights.size()) {
    if (auto e = estimate_spread(fitted_runs, fitted_weights, t_ref_c, coeffs_dps.size())) {
      constrain_spread(*e);
      // V(T) = tau^2(T) + mean v + sum_j g_j^2 S_j, g the fit's weights on the runs at T.
      const std::size_t k = e->k, p = e->p;
      const double xn = temp_c - t_ref_c;
      double v_mean = 0.0;
      for (const double v : e->v) v_mean += v / static_cast<double>(k);
      double cst = v_mean, c0 = 1.0, c1 = xn * xn;
      for (std::size_t j = 0; j < k; ++j) {
        double g = 0.0;
        for (std::size_t a = 0; a < p; ++a)
          for (std::size_t b = 0; b < p; ++b)
            g += e->design[j * p + a] * e->a_inv[a * p + b] * power(xn, b);
        g *= e->w[j];
        cst += g * g * e->v[j];
        c0 += g * g;
        c1 += g * g * e->x[j] * e->x[j];
      }
      std::vector<double> lin(k);
      double var = cst;
      for (std::size_t i = 0; i < k; ++i) {
        lin[i] = c0 * e->l0[i] + c1 * e->l1[i];
        var += lin[i] * e->z[i];
      }
      var = std::max(var, cst);  // (t0, t1 >= 0: never below the runs' own errors)
      // var(V) = 2 sum_il lin_i lin_l C_il^2 for Gaussian residuals of covariance C = R S R'.
      const double var_var = var_of_combination(*e, lin);
      if (var > 0.0) {
        const double nu = var_var > 0.0 ? std::clamp(2.0 * var * var / var_var, 1.0, 1e6) : 1e6;
        // Never below the line's own interval (fifth review of issue 31, F14): a new run is the
        // line and its own scatter.
        return std::max(analysis::t_one_sigma(nu) * std::sqrt(var), interval_at(temp_c));
      }
    }
  }
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
  // ordinary least-squares covariance, the same thing with equal weights). Weighted, the scale is
  // the modified one, q* = max(1, q) (Roever, Knapp & Friede 2015, BMC Med. Res. Methodol. 15:99;
  // Jackson, Law, Ruecker & Schwarzer 2017, Stat. Med. 36, 3923-3934): with 2-3 runs that happen
  // to agree, q can be far below 1 and the error far below the runs' own (fourth review of issue
  // 31, F1: two runs 0.6 sigma off the truth in the same direction gave +-0.000015 for a dN
  // 0.00022 off); never below the fixed-effect error sqrt(1 / sum 1/(v_i + tau^2)).
  const double q_raw = re->chi2 / static_cast<double>(m.dof);
  const double q = weighted ? std::max(1.0, q_raw) : q_raw;
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
  // tau^2(T), where the runs can tell its two terms apart (issue 31 review, H3): 3 or more
  // degrees of freedom, two or more distinct |T - T_ref|, and a between-run variance of at least
  // 5 times the runs' own (tau > 2.2 within-run errors; the paper's runs scatter 14-30 times
  // theirs). Below that the squared residuals are mostly the runs' own noise, and the band of
  // tau^2(T) over-covers (0.82-0.90 for tau of 0-1 within-run errors) where the constant one
  // holds 0.68-0.70 (docs/METHOD-NOTES.md).
  std::set<double> abs_x;
  for (const auto& pt : points) abs_x.insert(std::abs(pt.temp_c - m.t_ref_c));
  if (degree >= 1 && m.dof >= 3 && abs_x.size() >= 2 &&
      tau2 >= min_between_to_within_for_spread_model * v_mean) {
    if (auto e = estimate_spread(points, w, m.t_ref_c, p);
        e && e->t1 > min_curvature_to_its_error * std::sqrt(var_of_combination(*e, e->l1))) {
      constrain_spread(*e);
      m.tau2_centre_dps2 = e->t0;
      m.tau2_curvature_dps2_per_c2 = e->t1;
      m.fitted_runs.assign(points.begin(), points.end());
      m.fitted_weights = w;
    }
  }
  return m;
}

}  // namespace gyroflip::method
