/// \file
/// \brief The harmonic fit of an indexed run and the heading (see harmonic.hpp).
#include "gyroflip/method/harmonic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/least_squares.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/calibration.hpp"

namespace gyroflip::method {

std::vector<indexed_dwell> indexed_dwells(std::span<const row> rows) {
  std::vector<indexed_dwell> out;
  double t = 0.0, y = 0.0, w = 0.0;
  int pos = table_moving;
  const auto flush = [&] {
    if (w > 0.0) out.push_back({t / w, pos, y / w, w});
    t = y = w = 0.0;
  };
  for (const auto& r : rows) {
    if (r.position == table_moving) {
      flush();
      continue;
    }
    // A row that is a dwell of its own, or a raw conversion at another position, ends a dwell.
    if (r.n_avg > 1 || r.position != pos) flush();
    pos = r.position;
    const double n = static_cast<double>(r.n_avg);
    t += n * r.time_s;
    y += n * r.rate_dps;
    w += n;
    if (r.n_avg > 1) flush();
  }
  flush();
  return out;
}

namespace {

// The smallest period of the positions' sequence (2..2 x max_positions), checked over the
// first few periods; 0 if none.
std::size_t period_of(std::span<const indexed_dwell> d) {
  const std::size_t max_p = 2 * position_table::max_positions;
  for (std::size_t p = 2; p <= max_p; ++p) {
    const std::size_t span = std::min(d.size(), 4 * p);
    if (span < 2 * p) break;
    bool same = true;
    for (std::size_t k = 0; k + p < span && same; ++k) same = d[k].position == d[k + p].position;
    if (same) return p;
  }
  return 0;
}

// The standard error of a series' mean with its correlation read from its own overlapping Allan
// variance (NIST SP1065 eqn 11): se^2 = the variance of the mean that AVAR(m) m / n gives at
// the octaves m = m*/4, m*/2, m* (m* = n/8, as method::correlated_stderr), pooled with weights
// 1/m (each octave's degrees of freedom ~ n/m; ~60 pooled against ~10 at m* alone). For white
// blocks it equals s^2/n in expectation; positively correlated (random walk, flicker of what the
// blocks measure) it is larger; anti-correlated (the bias's flicker leaks into neighbouring
// blocks' contrasts with opposite signs: docs/PLANNER.md, eqn 1) smaller. Not the maximum with
// s^2/n as correlated_stderr takes: with ~10 degrees of freedom that maximum is biased high
// (the heading's 1 sigma then covered 75 % of the errors instead of 68 %: docs/NORTH.md).
// Fewer than 32 blocks: the naive error.
double pooled_correlated_stderr(std::span<const double> y, double naive) {
  const std::size_t n = y.size();
  if (n < 32) return naive;
  const std::size_t m_top = n / 8;
  const auto phase = analysis::phase_from_rate(y, 1.0);
  double num = 0.0, den = 0.0;
  for (std::size_t m = std::max<std::size_t>(m_top / 4, 1); m <= m_top; m *= 2) {
    const double adev = analysis::deviation_at(analysis::dev_kind::oadev, phase, 1.0, m).dev;
    const double w = 1.0 / static_cast<double>(m);
    num += w * adev * adev * static_cast<double>(m) / static_cast<double>(n);
    den += w;
  }
  return std::sqrt(num / den);
}

}  // namespace

result<harmonic_fit> fit_harmonics(std::span<const indexed_dwell> dwells,
                                   const position_table& table, const harmonic_options& options) {
  if (options.harmonics != 1 && options.harmonics != 2)
    return usage_error("one or two harmonics are fitted");
  const std::size_t n_h = static_cast<std::size_t>(options.harmonics);
  const bool projection = options.projection_of_two && table.size() == 2 && n_h == 1;
  if (projection &&
      std::abs(angle_between_deg(table.angle_deg(0), table.angle_deg(1)) - 180.0) > 1e-6)
    return runtime_error(fmt::format(
        "two positions give the Earth rate's projection only when 180 deg apart; the table "
        "has {}",
        table.describe()));
  const std::size_t need = projection ? 2 : 2 * n_h + 1;
  if (table.size() < need)
    return runtime_error(
        fmt::format("{} harmonic{} need at least {} table positions; the run has {} ({})", n_h,
                    n_h == 1 ? "" : "s", need, table.size(), table.describe()));
  std::size_t period = period_of(dwells);
  if (period == 0)
    return runtime_error(
        "the dwells' positions do not repeat with a period of 2 to 16 dwells: not an indexed "
        "run");
  // The block's design: bias, slope, then the harmonics (cols = 2 + 2 n_h; the projection: 3).
  const std::size_t cols = projection ? 3 : 2 + 2 * n_h;
  // A projection's block spans whole periods up to a residual degree of freedom (A B A B).
  const std::size_t visit_period = period;
  if (projection)
    while (period < cols + 1) period += visit_period;
  if (period < cols)
    return runtime_error(
        fmt::format("a visiting period of {} dwells cannot separate {} terms "
                    "and the bias's slope",
                    period, cols - 1));
  if (dwells.size() < period)
    return runtime_error(
        fmt::format("{} dwells: fewer than one block of {}", dwells.size(), period));
  std::vector<std::array<double, 4>> trig(period);  // cos, sin, cos 2, sin 2 of each slot
  for (std::size_t k = 0; k < period; ++k) {
    const int p = dwells[k].position;
    if (!table.holds(p))
      return runtime_error(fmt::format("dwell {}: position {} is not in the table", k, p));
    const double a =
        (table.angle_deg(p) - (projection ? table.angle_deg(0) : 0.0)) * units::rad_per_deg;
    trig[k] = {std::cos(a), std::sin(a), std::cos(2.0 * a), std::sin(2.0 * a)};
  }
  harmonic_fit fit;
  fit.names = {"b", "c1", "s1"};
  if (projection) fit.names = {"b", "p1"};
  if (n_h == 2) fit.names.insert(fit.names.end(), {"c2", "s2"});
  fit.period = period;
  const std::size_t n_terms = fit.names.size();
  std::vector<std::vector<double>> per_block(n_terms);
  std::vector<double> design(period * cols), y(period), w(period);
  double rss = 0.0, first_start_s = 0.0, last_start_s = 0.0, last_span_s = 0.0;
  std::size_t dof = 0;
  for (std::size_t start = 0; start + period <= dwells.size();) {
    const auto b = dwells.subspan(start, period);
    bool same = true;
    for (std::size_t k = 0; k < period && same; ++k) same = b[k].position == dwells[k].position;
    if (!same) {  // a dwell missing (a gap): find the pattern again
      ++fit.skipped_dwells;
      ++start;
      continue;
    }
    start += period;
    double t_mean = 0.0;
    for (const auto& d : b) t_mean += d.time_s;
    t_mean /= static_cast<double>(period);
    const double t_span = std::max(b.back().time_s - b.front().time_s, 1e-9);
    for (std::size_t k = 0; k < period; ++k) {
      double* row = &design[k * cols];
      row[0] = 1.0;
      row[1] = (b[k].time_s - t_mean) / t_span;  // scaled: the solver equilibrates anyway
      for (std::size_t h = 0; h < n_h && !projection; ++h) {
        row[2 + 2 * h] = trig[k][2 * h];
        row[3 + 2 * h] = trig[k][2 * h + 1];
      }
      if (projection) row[2] = trig[k][0];
      y[k] = b[k].rate_dps;
      w[k] = 1.0;  // equal dwells: ordinary least squares
    }
    auto f = analysis::weighted_least_squares(design, cols, y, w);
    if (!f)
      return runtime_error(fmt::format(
          "the table's positions ({} deg) cannot separate {} harmonic{} from the bias: {}",
          table.describe(), n_h, n_h == 1 ? "" : "s", f.err().message));
    per_block[0].push_back(f->coeffs[0]);
    for (std::size_t i = 1; i < n_terms; ++i) per_block[i].push_back(f->coeffs[i + 1]);
    rss += f->chi2;
    dof += period - cols;
    if (fit.blocks == 0) first_start_s = b.front().time_s;
    last_start_s = b.front().time_s;
    last_span_s = t_span;
    ++fit.blocks;
  }
  if (fit.blocks < 3)
    return runtime_error(
        fmt::format("{} complete visiting period{} of {} dwells found; the fit "
                    "needs at least 3",
                    fit.blocks, fit.blocks == 1 ? "" : "s", period));
  const auto nb = static_cast<double>(fit.blocks);
  fit.dwells = fit.blocks * period;
  // From one block's first dwell to the next's (the blocks' spacing is uneven within a sweep).
  fit.block_s = (last_start_s - first_start_s) / (nb - 1.0);
  if (!(fit.block_s > last_span_s))
    fit.block_s = last_span_s * static_cast<double>(period) / static_cast<double>(period - 1);
  fit.dwell_sigma_dps = dof > 0 ? std::sqrt(rss / static_cast<double>(dof)) : 0.0;
  fit.value.assign(n_terms, 0.0);
  std::vector<double> inflate(n_terms, 1.0);
  for (std::size_t i = 0; i < n_terms; ++i) {
    double m = 0.0;
    for (const double v : per_block[i]) m += v;
    fit.value[i] = m / nb;
  }
  fit.covariance.assign(n_terms * n_terms, 0.0);
  for (std::size_t i = 0; i < n_terms; ++i)
    for (std::size_t j = 0; j < n_terms; ++j) {
      double s = 0.0;
      for (std::size_t k = 0; k < fit.blocks; ++k)
        s += (per_block[i][k] - fit.value[i]) * (per_block[j][k] - fit.value[j]);
      fit.covariance[i * n_terms + j] = s / (nb - 1.0) / nb;
    }
  // Each term's variance widened to its correlated error (flicker, random walk of the bias).
  for (std::size_t i = 0; i < n_terms; ++i) {
    const double naive = std::sqrt(fit.covariance[i * n_terms + i]);
    const double se = pooled_correlated_stderr(per_block[i], naive);
    fit.correlated = fit.blocks >= 32;
    inflate[i] = naive > 0.0 ? se / naive : 1.0;
  }
  fit.correlated_factor = inflate;
  for (std::size_t i = 0; i < n_terms; ++i)
    for (std::size_t j = 0; j < n_terms; ++j)
      fit.covariance[i * n_terms + j] *= inflate[i] * inflate[j];
  return fit;
}

heading_estimate heading_of(double c1, double s1, double var_c1, double var_s1, double cov_c1_s1,
                            bool table_axis_up) {
  if (!table_axis_up) {
    s1 = -s1;
    cov_c1_s1 = -cov_c1_s1;
  }
  heading_estimate h;
  const double a2 = c1 * c1 + s1 * s1;
  h.amplitude_dps = std::sqrt(a2);
  double psi = std::atan2(s1, c1) / units::rad_per_deg;
  if (psi < 0.0) psi += 360.0;
  h.heading_deg = psi >= 360.0 ? 0.0 : psi;
  // d psi = (c1 ds1 - s1 dc1) / a2
  const double var = (s1 * s1 * var_c1 + c1 * c1 * var_s1 - 2.0 * c1 * s1 * cov_c1_s1) / (a2 * a2);
  h.sigma_deg = std::sqrt(std::max(var, 0.0)) / units::rad_per_deg;
  return h;
}

projection_heading heading_of_projection(double p1, double var_p1, double earth_horizontal_dps,
                                         double axis_angle_deg, bool table_axis_up) {
  projection_heading h;
  const double x = p1 / earth_horizontal_dps;
  const double sx = std::sqrt(std::max(var_p1, 0.0)) / earth_horizontal_dps;
  h.cos_value = x;
  const double a = std::acos(std::clamp(x, -1.0, 1.0)) / units::rad_per_deg;  // [0, 180]
  const auto wrap = [](double v) {
    v = std::fmod(v, 360.0);
    if (v < 0.0) v += 360.0;
    return v >= 360.0 ? 0.0 : v;
  };
  const double base = table_axis_up ? axis_angle_deg : -axis_angle_deg;
  h.heading_deg = wrap(base + a);
  h.mirror_deg = wrap(base - a);
  h.at_edge = std::abs(x) > 1.0 - sx;
  if (h.at_edge)
    h.sigma_deg = std::acos(std::max(-1.0, 1.0 - sx)) / units::rad_per_deg;
  else
    h.sigma_deg = sx / std::sqrt(1.0 - x * x) / units::rad_per_deg;
  return h;
}

double heading_white_limit_deg(double arw_dps_rthz, double lat_deg, double run_s, double k) {
  const double w_h = earth::earth_rate_wgs84_dps * std::cos(lat_deg * units::rad_per_deg);
  return k * arw_dps_rthz / (w_h * std::sqrt(run_s)) / units::rad_per_deg;
}

double heading_dead_time_limit_deg(double arw_dps_rthz, double bias_instability_dps,
                                   double dead_time_s, double lat_deg, double run_s, double k) {
  return heading_white_limit_deg(
      arw_dps_rthz + 0.664 * bias_instability_dps * std::sqrt(dead_time_s), lat_deg, run_s, k);
}

result<two_azimuth_heading> heading_two_azimuths(std::array<double, 2> h1,
                                                 std::array<double, 4> cov1,
                                                 std::array<double, 2> h2,
                                                 std::array<double, 4> cov2, double base_turn_deg,
                                                 bool table_axis_up) {
  if (!table_axis_up) {  // as seen with the axis up: s1 -> -s1
    h1[1] = -h1[1];
    h2[1] = -h2[1];
    cov1[1] = cov1[2] = -cov1[1];
    cov2[1] = cov2[2] = -cov2[1];
  }
  const double turn = base_turn_deg * units::rad_per_deg;
  // w = 1 / (1 - e^{i turn})
  const double den_r = 1.0 - std::cos(turn), den_i = -std::sin(turn);
  const double den2 = den_r * den_r + den_i * den_i;
  if (!(den2 > 1e-6))
    return usage_error(
        fmt::format("base azimuths {} deg apart do not separate the table's term from the Earth's",
                    base_turn_deg));
  const double wr = den_r / den2, wi = -den_i / den2;
  const double dr = h1[0] - h2[0], di = h1[1] - h2[1];
  const double qr = wr * dr - wi * di, qi = wi * dr + wr * di;
  // cov(q) = M cov(d) M^T, M = [[wr, -wi], [wi, wr]]
  const double c00 = cov1[0] + cov2[0], c01 = cov1[1] + cov2[1], c11 = cov1[3] + cov2[3];
  const double q00 = wr * wr * c00 - 2.0 * wr * wi * c01 + wi * wi * c11;
  const double q11 = wi * wi * c00 + 2.0 * wr * wi * c01 + wr * wr * c11;
  const double q01 = wr * wi * c00 + (wr * wr - wi * wi) * c01 - wr * wi * c11;
  two_azimuth_heading out;
  out.first = heading_of(qr, qi, q00, q11, q01, true);
  out.table_term_c1_dps = h1[0] - qr;
  out.table_term_s1_dps = (h1[1] - qi) * (table_axis_up ? 1.0 : -1.0);
  out.table_term_dps = std::hypot(h1[0] - qr, h1[1] - qi);
  return out;
}

}  // namespace gyroflip::method
