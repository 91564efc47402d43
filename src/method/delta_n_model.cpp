/// \file
/// \brief Polynomial dN(T) fit (see delta_n_model.hpp). The systems are at most 7x7, so a
/// Gauss-Jordan inverse of the normal matrix is enough; temperatures are centred on their
/// mean to keep it well conditioned.
#include "gyroflip/method/delta_n_model.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::method {
namespace {

// In-place inverse of a small symmetric positive-definite matrix (row-major, n x n) by
// Gauss-Jordan elimination with partial pivoting. Returns false if it is singular.
bool invert(std::vector<double>& a, std::size_t n) {
  std::vector<double> inv(n * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) inv[i * n + i] = 1.0;
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t piv = col;
    for (std::size_t r = col + 1; r < n; ++r)
      if (std::abs(a[r * n + col]) > std::abs(a[piv * n + col])) piv = r;
    if (!(std::abs(a[piv * n + col]) > 1e-300)) return false;
    for (std::size_t k = 0; k < n; ++k) {
      std::swap(a[col * n + k], a[piv * n + k]);
      std::swap(inv[col * n + k], inv[piv * n + k]);
    }
    const double d = a[col * n + col];
    for (std::size_t k = 0; k < n; ++k) {
      a[col * n + k] /= d;
      inv[col * n + k] /= d;
    }
    for (std::size_t r = 0; r < n; ++r) {
      if (r == col) continue;
      const double f = a[r * n + col];
      for (std::size_t k = 0; k < n; ++k) {
        a[r * n + k] -= f * a[col * n + k];
        inv[r * n + k] -= f * inv[col * n + k];
      }
    }
  }
  a = std::move(inv);
  return true;
}

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
  std::vector<double> ata(n * n, 0.0);
  std::vector<double> atb(n, 0.0);
  for (const auto& p : points) {
    const double w = weighted ? 1.0 / (p.stderr_dps * p.stderr_dps) : 1.0;
    const double x = p.temp_c - m.t_ref_c;
    for (std::size_t i = 0; i < n; ++i) {
      atb[i] += w * power(x, i) * p.delta_n_dps;
      for (std::size_t j = 0; j < n; ++j) ata[i * n + j] += w * power(x, i + j);
    }
  }
  if (!invert(ata, n))
    return runtime_error("dN(T) fit is singular (temperatures too close together)");
  m.coeffs_dps.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) m.coeffs_dps[i] += ata[i * n + j] * atb[j];
  double chi2 = 0.0;
  for (const auto& p : points) {
    const double res = p.delta_n_dps - m.eval(p.temp_c);
    chi2 += res * res * (weighted ? 1.0 / (p.stderr_dps * p.stderr_dps) : 1.0);
  }
  const std::size_t dof = points.size() - n;
  m.chi2_per_dof = dof > 0 ? chi2 / static_cast<double>(dof) : 0.0;
  // Unweighted: the residual variance is the only scale. Weighted: inflate by the Birge ratio.
  const double scale = weighted ? std::max(1.0, m.chi2_per_dof) : m.chi2_per_dof;
  m.cov = ata;
  for (double& v : m.cov) v *= scale;
  return m;
}

}  // namespace gyroflip::method
