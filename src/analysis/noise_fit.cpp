/// \file
/// \brief Weighted non-negative least squares of the IEEE 952 model (see noise_fit.hpp).
#include "gyroflip/analysis/noise_fit.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/least_squares.hpp"
#include "gyroflip/core/error.hpp"

namespace gyroflip::analysis {
namespace {

constexpr std::size_t terms = 5;  // Q, N, B, K, R (squared coefficients c_k)
const double b_factor = 2.0 * std::numbers::ln2 / std::numbers::pi;

// AVAR contribution of term k with unit coefficient at tau. For a demodulator's estimates whose
// neighbours share dwells (abba: spacing T, kappa 9/16), white dwell noise gives N^2 (1/tau -
// kappa T/tau^2), not N^2/tau (docs/ANALYSIS.md, "Cycle series of the abba pairing"); `deficit_t`
// is kappa T (0: uncorrelated estimates or any other series).
double basis(std::size_t k, double tau, double deficit_t) {
  switch (k) {
    case 0:
      return 3.0 / (tau * tau);
    case 1:
      return (1.0 - deficit_t / tau) / tau;
    case 2:
      return b_factor;
    case 3:
      return tau / 3.0;
    default:
      return tau * tau / 2.0;
  }
}

struct subset_fit {
  std::array<double, terms> c{};
  /// (A^T W A)^-1 of the terms in the subset, in the unscaled coefficients (zero elsewhere)
  std::array<std::array<double, terms>, terms> inv{};
  double chi2 = std::numeric_limits<double>::infinity();
  bool ok = false;
};

// Weighted LS on the terms in `mask` (analysis/least_squares.hpp: column-scaled QR, the basis
// values span ~10 decades).
subset_fit solve(std::span<const deviation_point> p, const std::vector<double>& w, unsigned mask,
                 double deficit_t, bool allow_negative = false) {
  std::array<std::size_t, terms> idx{};
  std::size_t n = 0;
  for (std::size_t k = 0; k < terms; ++k)
    if (mask & (1u << k)) idx[n++] = k;
  subset_fit out;
  if (n == 0 || n > p.size()) return out;
  std::vector<double> design;
  std::vector<double> y;
  design.reserve(p.size() * n);
  for (const auto& q : p) {
    for (std::size_t a = 0; a < n; ++a) design.push_back(basis(idx[a], q.tau_s, deficit_t));
    y.push_back(q.dev * q.dev);
  }
  const auto fit = weighted_least_squares(design, n, y, w);
  if (!fit) return out;  // degenerate subset
  for (std::size_t a = 0; a < n; ++a) {
    out.c[idx[a]] = fit->coeffs[a];
    for (std::size_t b = 0; b < n; ++b) out.inv[idx[a]][idx[b]] = fit->cov[a * n + b];
    if (out.c[idx[a]] < 0.0 && !allow_negative) return out;  // not a non-negative solution
  }
  out.chi2 = fit->chi2;
  out.ok = true;
  return out;
}

// The non-negative subset with the lowest chi^2 + 2 (number of terms) (Akaike): a term stays
// only if it lowers chi^2 by more than 2.
subset_fit best_nonnegative(std::span<const deviation_point> p, const std::vector<double>& w,
                            double deficit_t) {
  subset_fit best;
  double best_score = std::numeric_limits<double>::infinity();
  for (unsigned mask = 1; mask < (1u << terms); ++mask) {
    const auto f = solve(p, w, mask, deficit_t);
    if (!f.ok) continue;
    const double score = f.chi2 + 2.0 * static_cast<double>(std::popcount(mask));
    if (score < best_score) {
      best_score = score;
      best = f;
    }
  }
  return best;
}

noise_term make_term(double c, double sd, double z) {
  // c is the squared coefficient, sd its standard error; the interval is c +- z sd, mapped
  // through the square root (so it is asymmetric in the coefficient).
  noise_term t;
  t.resolved = c > 2.0 * sd && c > 0.0;
  t.value = std::sqrt(std::max(c, 0.0));
  t.lo = std::sqrt(std::max(c - z * sd, 0.0));
  t.hi = std::sqrt(std::max(c, 0.0) + z * sd);
  return t;
}

// Model discrepancy: 5 % of AVAR per point, independent between points. Without it the
// short-tau points (EDF ~ 1e6) would force the five-term model onto features it does not have
// (a real sensor's anti-alias filter), at the expense of every longer tau.
constexpr double discrepancy = 0.05;

// Variance of an AVAR estimate: chi-squared (2 model^2 / edf) plus the discrepancy.
double weight(double edf, double model) {
  return 1.0 / (model * model * (2.0 / edf + discrepancy * discrepancy));
}

// Large-N correlation of two overlapping AVAR estimates of one series at averaging factors
// m and 2^d m, for noise exponent alpha (2 WPM, 1 FPM, 0 WFM, -1 FFM, -2 RWFM), d = 1..6.
// White PM, white FM, random-walk FM: exact, from the estimators' kernels (Isserlis' theorem;
// scripts/derive/allan_octave_correlation.py). Flicker FM: Monte Carlo of the project's flicker
// generator (same script's notes; +-0.05). Flicker PM: mean of white PM and white FM.
constexpr std::array<std::array<double, 6>, 5> octave_correlation = {{
    {0.400, 0.514, 0.514, 0.514, 0.514, 0.514},  // alpha = 2
    {0.465, 0.351, 0.290, 0.269, 0.261, 0.259},  // alpha = 1
    {0.530, 0.187, 0.066, 0.023, 0.008, 0.003},  // alpha = 0
    {0.680, 0.300, 0.120, 0.048, 0.019, 0.008},  // alpha = -1 (tail: x0.4 an octave)
    {0.888, 0.676, 0.488, 0.347, 0.246, 0.174},  // alpha = -2
}};

// The table at a (possibly fractional) octave distance d >= 0: linear between octaves, 1 at
// d = 0, and beyond d = 6 the last octave's ratio continued (white PM stays at 0.514).
double correlation(int alpha, double d) {
  const auto& row = octave_correlation[static_cast<std::size_t>(2 - std::clamp(alpha, -2, 2))];
  if (d <= 1.0) return 1.0 + d * (row[0] - 1.0);
  if (d >= 6.0) return row[5] * std::pow(row[5] / row[4], d - 6.0);
  const auto i = static_cast<std::size_t>(d);  // 1..5
  const double f = d - static_cast<double>(i);
  return row[i - 1] + f * (row[i] - row[i - 1]);
}

}  // namespace

short_tau_shaping detect_short_tau_shaping(std::span<const deviation_point> pts) {
  short_tau_shaping out;
  const std::size_t n = pts.size();
  if (n < 7) return out;
  for (const auto& p : pts)
    if (!(p.edf >= 1.0 && p.dev > 0.0 && std::isfinite(p.dev))) return out;
  // The first local minimum: beyond it the curve is the long-tau terms' and few clusters'.
  std::size_t floor = 0;
  while (floor + 1 < n && pts[floor + 1].dev < pts[floor].dev) ++floor;
  const auto slope = [&](std::size_t i) {
    return std::log(pts[i + 1].dev / pts[i].dev) / std::log(pts[i + 1].tau_s / pts[i].tau_s);
  };
  constexpr double z_min = 3.5;
  std::size_t last_convex = 0;  // a strong convex kink after a concave one: bumps, not a roll-off
  bool seen_concave = false;
  for (std::size_t j = 1; j + 1 < n && j + 1 < floor && n - (j + 1) >= 4; ++j) {
    const double l1 = std::log(pts[j].tau_s / pts[j - 1].tau_s);
    const double l2 = std::log(pts[j + 1].tau_s / pts[j].tau_s);
    const double kink = slope(j - 1) - slope(j);
    const std::array<double, 3> a{-1.0 / l1, 1.0 / l1 + 1.0 / l2, -1.0 / l2};
    double var = 0.0;
    for (std::size_t p = 0; p < 3; ++p)
      for (std::size_t q = 0; q < 3; ++q) {
        const auto& u = pts[j - 1 + p];
        const auto& v = pts[j - 1 + q];
        const double d = std::abs(std::log2(v.tau_s / u.tau_s));
        const double rho = std::sqrt(correlation(u.alpha, d) * correlation(v.alpha, d));
        var += a[p] * a[q] * rho / (2.0 * std::sqrt(u.edf * v.edf));
      }
    const double z = kink / std::sqrt(std::max(var, 1e-300));
    if (z <= -z_min && kink < -0.1 && seen_concave) last_convex = j;
    if (z >= z_min && slope(j - 1) < -0.25) {
      seen_concave = true;
      out.points = j + 1;
      out.kink_tau_s = pts[j].tau_s;
      out.kink_z = z;
    }
  }
  if (out.points > 0) {
    // A slope steeper than white noise's among the points left out, or bumps: a line.
    bool steep = false;
    for (std::size_t i = 0; i + 1 < out.points; ++i) steep = steep || slope(i) < -0.75;
    const bool alternating = last_convex > 0 && last_convex < out.points;
    out.cause = alternating || steep ? "line" : "filter";
  }
  return out;
}

namespace {

// Standard errors of the coefficients of `f` (terms in `mask`) by the sandwich
// inv (A^T W S W A) inv, where W are the fit's (diagonal) weights and S the covariance of the
// AVAR estimates: chi-squared variances 2 model^2/edf correlated between taus as above (the
// geometric mean of the two points' correlations), plus the independent discrepancy. Treating
// the octave points as independent (W^-1 as covariance) gives intervals that cover a random
// walk's K in only half of the cases at 1 sigma; this covers it near the nominal rate.
std::array<double, terms> sandwich_sd(std::span<const deviation_point> p,
                                      const std::vector<double>& w,
                                      const std::vector<double>& model, const subset_fit& f,
                                      unsigned mask, double deficit_t) {
  const std::size_t np = p.size();
  std::vector<double> sampling_sd(np);
  for (std::size_t i = 0; i < np; ++i) sampling_sd[i] = model[i] * std::sqrt(2.0 / p[i].edf);
  // meat = A^T W S W A over the terms in mask
  std::array<std::array<double, terms>, terms> meat{};
  for (std::size_t i = 0; i < np; ++i) {
    for (std::size_t j = 0; j < np; ++j) {
      const double d = std::abs(std::log2(p[j].tau_s / p[i].tau_s));
      double s = std::sqrt(correlation(p[i].alpha, d) * correlation(p[j].alpha, d)) *
                 sampling_sd[i] * sampling_sd[j];
      if (i == j) s += discrepancy * discrepancy * model[i] * model[i];
      const double wsw = w[i] * s * w[j];
      for (std::size_t a = 0; a < terms; ++a) {
        if (!(mask & (1u << a))) continue;
        for (std::size_t b = 0; b < terms; ++b)
          if (mask & (1u << b))
            meat[a][b] += basis(a, p[i].tau_s, deficit_t) * wsw * basis(b, p[j].tau_s, deficit_t);
      }
    }
  }
  std::array<double, terms> sd{};
  for (std::size_t a = 0; a < terms; ++a) {
    if (!(mask & (1u << a))) continue;
    double v = 0.0;
    for (std::size_t b = 0; b < terms; ++b)
      for (std::size_t c = 0; c < terms; ++c) v += f.inv[a][b] * meat[b][c] * f.inv[c][a];
    sd[a] = std::sqrt(std::max(v, 0.0));
  }
  return sd;
}

}  // namespace

result<noise_terms> fit_noise_terms(std::span<const deviation_point> pts, double level,
                                    const noise_series& series) {
  const double deficit_t = series.shaped() ? series.white_avar_deficit * series.cycle_s : 0.0;
  if (!(level > 0.0 && level < 1.0))
    return usage_error(fmt::format("confidence level {} must be in (0, 1)", level));
  std::vector<deviation_point> p;
  for (const auto& q : pts)
    if (q.edf >= 1.0 && q.dev > 0.0 && std::isfinite(q.dev)) p.push_back(q);
  if (std::all_of(pts.begin(), pts.end(), [](const deviation_point& q) { return q.dev == 0.0; }))
    return runtime_error(
        "every Allan deviation is 0: the series is constant (a stuck sensor, a wrong column?), so "
        "there is no noise to fit");
  if (p.size() < 3)
    return runtime_error(
        fmt::format("the series gives {} Allan-deviation point{} with EDF >= 1; the noise fit "
                    "needs 3 (a longer "
                    "record: at least ~20 samples)",
                    p.size(), p.size() == 1 ? "" : "s"));
  std::vector<double> w(p.size());
  std::vector<double> model(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) w[i] = weight(p[i].edf, p[i].dev * p[i].dev);
  subset_fit f;
  for (int iter = 0; iter < 3; ++iter) {
    f = best_nonnegative(p, w, deficit_t);
    if (!f.ok) return runtime_error("noise fit found no non-negative solution");
    for (std::size_t i = 0; i < p.size(); ++i) {  // reweight with the model (IRLS)
      model[i] = 0.0;
      for (std::size_t k = 0; k < terms; ++k) model[i] += f.c[k] * basis(k, p[i].tau_s, deficit_t);
      w[i] = weight(p[i].edf, model[i]);
    }
  }
  noise_terms out;
  // Where the fitted curve is lowest within the data's taus (a log grid of 400 points): the tau
  // at which a plot marks the fitted flicker floor 0.664 B.
  double lowest = std::numeric_limits<double>::infinity();
  const double tau_first = p.front().tau_s, tau_last = p.back().tau_s;
  for (int j = 0; j <= 400; ++j) {
    const double tau = tau_first * std::pow(tau_last / tau_first, j / 400.0);
    double avar = 0.0;
    for (std::size_t k = 0; k < terms; ++k) avar += f.c[k] * basis(k, tau, deficit_t);
    if (avar < lowest) {
      lowest = avar;
      out.fit_min_tau_s = tau;
    }
  }
  std::size_t used = 0;
  for (std::size_t k = 0; k < terms; ++k) used += f.c[k] > 0.0 ? 1u : 0u;
  const double dof = static_cast<double>(p.size()) - static_cast<double>(used);
  out.chi2_per_dof = dof > 0 ? f.chi2 / dof : 0.0;
  unsigned mask = 0;
  for (std::size_t k = 0; k < terms; ++k)
    if (f.c[k] > 0.0) mask |= 1u << k;
  auto sd = sandwich_sd(p, w, model, f, mask, deficit_t);
  // A dropped term gets an upper limit from the fit that includes it (its value may be < 0).
  for (std::size_t k = 0; k < terms; ++k) {
    if (mask & (1u << k)) continue;
    const auto with = solve(p, w, mask | (1u << k), deficit_t, true);
    if (with.ok) {
      f.c[k] = std::min(with.c[k], 0.0);  // still not part of the estimate
      sd[k] = sandwich_sd(p, w, model, with, mask | (1u << k), deficit_t)[k];
    }
  }
  // Two-sided normal interval of the squared coefficient at `level`: z = sqrt(chi2_1(level)).
  const double z = std::sqrt(chi2_quantile(level, 1.0));
  out.level = level;
  out.quantization = make_term(f.c[0], sd[0], z);
  out.arw = make_term(f.c[1], sd[1], z);
  out.bias_instability = make_term(f.c[2], sd[2], z);
  out.rrw = make_term(f.c[3], sd[3], z);
  out.rate_ramp = make_term(f.c[4], sd[4], z);
  for (auto* t : {&out.quantization, &out.arw, &out.bias_instability, &out.rrw, &out.rate_ramp})
    t->range_lo = t->range_hi = t->value;
  out.fit_tau_lo_s = p.front().tau_s;
  out.fit_tau_hi_s = p.back().tau_s;
  // The bias-instability floor is the first local minimum of OADEV: later minima at long tau
  // rest on a handful of clusters (ADIS16405 X: 2 % lower at 1311 s than at 82 s, +-40 %).
  auto floor = p.begin();
  while (floor + 1 != p.end() && (floor + 1)->dev < floor->dev) ++floor;
  out.bias_floor_tau_s = floor->tau_s;
  out.bias_floor_dev = floor->dev;
  out.bias_floor_reached = floor + 1 != p.end();
  // A curve still falling at its longest tau has no floor: B is then only bounded, by the flicker
  // floor 0.6643 B <= OADEV at every tau (FACTS §7), at the upper end of that last point's
  // interval - however the fit shares the curve among its terms.
  if (!out.bias_floor_reached) {
    const double bound = floor->ci_hi / 0.6643;
    auto& b = out.bias_instability;
    b.hi = std::isfinite(bound) ? std::min(std::max(b.hi, b.value), bound) : b.hi;
    b.resolved = false;
    out.notes.push_back(fmt::format(
        "bias instability: OADEV still falls at the longest tau ({:g} s), so there is no floor; "
        "B is only bounded (< {:.4g} deg/s, from that point's upper bound / 0.6643)",
        floor->tau_s, b.hi));
  }
  // Where the fitted curve leaves the measured points' intervals, say so (at `level` a fraction
  // 1 - level of them is expected outside by chance).
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double model_dev = std::sqrt(std::max(model[i], 0.0));
    if (model_dev < p[i].ci_lo || model_dev > p[i].ci_hi)
      out.misfit.push_back({p[i].tau_s, p[i].dev, model_dev, p[i].ci_lo, p[i].ci_hi});
  }
  if (!out.misfit.empty())
    out.notes.push_back(fmt::format(
        "the fitted model lies outside the measured interval at {} of {} taus ({:.1f} expected by "
        "chance at this level); chi2/dof {:.3g}",
        out.misfit.size(), p.size(), (1.0 - level) * static_cast<double>(p.size()),
        out.chi2_per_dof));
  if (series.shaped() && !series.note.empty()) out.notes.push_back(series.note);
  const std::pair<const char*, const noise_term*> named[] = {
      {"quantization", &out.quantization},
      {"angle random walk", &out.arw},
      {"bias instability", &out.bias_instability},
      {"rate random walk", &out.rrw},
      {"rate ramp", &out.rate_ramp}};
  for (const auto& [name, t] : named)
    if (!t->resolved)
      out.notes.push_back(fmt::format(
          "{} not resolved by the data (upper limit at the interval's level given)", name));
  return out;
}

}  // namespace gyroflip::analysis
