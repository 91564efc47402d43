/// \file
/// \brief The stationarity test of a calibration run (stationarity.hpp).
#include "gyroflip/method/stationarity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/method/demodulator.hpp"

namespace gyroflip::method {
namespace {

// Overlapping Allan variance of a unit-spaced series at factor m (NIST SP1065 eqn 11).
double oavar(std::span<const double> y, std::size_t m) {
  const double d =
      analysis::deviation_at(analysis::dev_kind::oadev, analysis::phase_from_rate(y, 1.0), 1.0, m)
          .dev;
  return d * d;
}

std::string num(double v) {
  return fmt::format("{:.3g}", v);
}

struct split {
  double statistic = 0.0;  // max |S_k| before scaling
  std::size_t at = 0;      // first cycle after the split
};

// The OLS-CUSUM's largest partial sum of y - mean(y) and where it is reached.
split largest_partial_sum(std::span<const double> y, double mean) {
  split out;
  double s = 0.0;
  for (std::size_t k = 0; k + 1 < y.size(); ++k) {
    s += y[k] - mean;
    if (std::abs(s) > out.statistic) out = {std::abs(s), k + 1};
  }
  return out;
}

double mean_of(std::span<const double> y) {
  double s = 0.0;
  for (double v : y) s += v;
  return y.empty() ? 0.0 : s / static_cast<double>(y.size());
}

void check_g_term(const calibration& cal, const stationarity_inputs& in, stationarity& out) {
  if (!in.spec || !(in.spec->limit_dps() > 0.0)) return;
  out.g_checked = true;
  out.g_exact = in.lat_deg && in.axis;
  // Exactly with the geometry; else at least |dN| - W_E, whatever the axis.
  out.g_term_dps = out.g_exact
                       ? std::abs(split_delta_n(cal.delta_n_dps, *in.lat_deg, *in.axis).g_term_dps)
                       : std::max(0.0, std::abs(cal.delta_n_dps) - earth::earth_rate_wgs84_dps);
  out.g_limit_dps = in.spec->limit_dps();
  out.g_margin_dps = 3.0 * cal.stderr_correlated_dps;
  out.g_source = in.spec->source;
  out.g_failed = out.g_term_dps - out.g_margin_dps > out.g_limit_dps;
}

}  // namespace

double white_std_over_adev(pairing p) noexcept {
  const auto& t = scheme_of(p).transfer();
  // The reference is c's white noise; r's kernel has c's norm for the 0/180 schemes (the same
  // weights with signs), a larger one for the harmonic scheme (c1 against b: sqrt(2) for a
  // sweep), whose ratio then scales it.
  const auto cv = t.white_covariance();
  if (cv[0] == cv[2]) return t.white_std_over_adev();
  return t.white_std_over_adev() * std::sqrt(cv[0] / cv[2]);
}

stationarity check_stationarity(std::span<const cycle> cycles, const calibration& cal,
                                const stationarity_inputs& in) {
  stationarity out;
  const std::size_t n = cycles.size();
  out.cycles = n;
  if (n < min_stationarity_cycles) {
    out.why_not = fmt::format("{} cycles: the test needs at least {}", n, min_stationarity_cycles);
    return out;
  }
  std::vector<double> r(n);
  std::vector<double> c(n);
  for (std::size_t i = 0; i < n; ++i) {
    r[i] = cycles[i].rate_dps;
    c[i] = cycles[i].bias_dps;
  }
  out.checked = true;
  const double nd = static_cast<double>(n);
  // Scatter: r's std against the same dwells' white noise, read from c at tau0.
  const double std_r = analysis::mean_and_std(r).std;
  const double white = white_std_over_adev(in.pair) * std::sqrt(oavar(c, 1));
  const double mean = mean_of(r);
  // Rounding level: a noise-free run (synthetic data) has no scale, and what is below it is 0.
  const double rounding = 1e-12 * (std::abs(mean) + std::abs(mean_of(c)));
  out.scatter_ratio = white > rounding ? std_r / white : (std_r > rounding ? 1e300 : 1.0);
  out.scatter_limit = std::max(1.25, 1.0 + 7.0 / std::sqrt(nd));
  out.scatter_low_limit = 0.75 * std::max(0.0, 1.0 - 3.0 / std::sqrt(nd));
  out.scatter_failed =
      out.scatter_ratio > out.scatter_limit || out.scatter_ratio < out.scatter_low_limit;
  double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
  for (const auto& cy : cycles)
    if (std::isfinite(cy.temp_c)) {
      t_lo = std::min(t_lo, cy.temp_c);
      t_hi = std::max(t_hi, cy.temp_c);
    }
  out.temp_span_c = t_lo <= t_hi ? t_hi - t_lo : 0.0;
  out.temp_failed = out.temp_span_c > isothermal_span_c;
  // Drift or step: the CUSUM scaled by r's long-run std at short averaging times.
  const std::size_t m = std::clamp<std::size_t>(n / 8, 1, drift_scale_cycles);
  const double long_run_var = oavar(r, m) * static_cast<double>(m);
  const auto sp = largest_partial_sum(r, mean);
  const double scale = std::sqrt(long_run_var * nd);
  out.drift_statistic = scale > rounding * std::sqrt(nd)
                            ? sp.statistic / scale
                            : (sp.statistic > rounding * nd ? 1e300 : 0.0);
  const auto head = std::span<const double>(r).first(sp.at);
  const auto tail = std::span<const double>(r).subspan(sp.at);
  out.step_dps = sp.at > 0 && !tail.empty() ? mean_of(tail) - mean_of(head) : 0.0;
  out.step_time_s = cycles[std::min(sp.at, n - 1)].time_s;
  out.step_limit_dps = 3.0 * cal.stderr_correlated_dps;
  out.drift_failed = out.drift_statistic > drift_limit &&
                     std::abs(out.step_dps) > std::max(out.step_limit_dps, rounding);
  check_g_term(cal, in, out);
  // Every statistic written is finite (a run of identical values gives 1e300, never inf).
  out.scatter_ratio = std::min(out.scatter_ratio, 1e300);
  out.drift_statistic = std::min(out.drift_statistic, 1e300);
  return out;
}

std::vector<std::string> stationarity::failures() const {
  std::vector<std::string> out;
  if (scatter_failed && scatter_ratio > scatter_limit)
    out.push_back(fmt::format(
        "its per-cycle scatter is {} times the sensor's white noise in the same dwells (limit "
        "{}): the input rate was not constant",
        num(scatter_ratio), num(scatter_limit)));
  if (scatter_failed && scatter_ratio < scatter_low_limit)
    out.push_back(fmt::format(
        "its per-cycle scatter is only {} of the sensor's white noise in the same dwells (lower "
        "limit {}): the half-sum c scatters more than the dwells' noise, as an input that "
        "alternates with the turns does (a vibration or oscillation of the table)",
        num(scatter_ratio), num(scatter_low_limit)));
  if (drift_failed)
    out.push_back(fmt::format(
        "r drifts or steps by {} °/s at t = {:.0f} s (CUSUM {} > {}; beyond 3 correlated errors, "
        "{} °/s){}",
        num(step_dps), step_time_s, num(drift_statistic), num(drift_limit_value),
        num(step_limit_dps),
        temp_span_c > 1.0
            ? fmt::format("; the temperature moved {:.1f} °C over the run, and ΔN follows it: "
                          "calibrate at a steady temperature, or fit ΔN(T) over runs at several",
                          temp_span_c)
            : std::string()));
  if (temp_failed)
    out.push_back(fmt::format(
        "the temperature moved {:.1f} °C during the run: not isothermal (more than {:g} °C), "
        "so its dN is a mean over temperatures and no dN(T) can place it; calibrate at a steady "
        "temperature",
        temp_span_c, isothermal_span_c));
  if (g_failed)
    out.push_back(fmt::format(
        "its g-term is {}{} °/s, {} times the limit {} °/s at 1 g ({}), beyond 3 correlated "
        "errors: a rate input, or a tilted or moving rig",
        g_exact ? "" : "at least ", num(g_term_dps), num(g_term_dps / g_limit_dps),
        num(g_limit_dps), g_source));
  return out;
}

std::vector<std::string> stationarity::caveats() const {
  if (!checked || failed() || g_checked) return {};
  return {
      "its g-term was not checked (no sensor specification), so a constant input rate of any "
      "size passes the scatter and drift tests and enters dN whole (a turning or tilted table); "
      "check it by naming the sensor's specification (a built-in preset or a TOML preset file)"};
}

stationarity stationarity::rejudged() const {
  stationarity s = *this;
  if (!checked) return s;
  s.scatter_failed = scatter_ratio > scatter_limit || scatter_ratio < scatter_low_limit;
  s.drift_failed = drift_statistic > drift_limit_value && std::abs(step_dps) > step_limit_dps;
  s.g_failed = g_checked && g_term_dps - g_margin_dps > g_limit_dps;
  s.temp_failed = temp_span_c > isothermal_span_c;
  return s;
}

std::string stationarity::summary() const {
  if (!checked) return "not checked: " + why_not;
  if (failed()) {
    std::string s = "NOT stationary: ";
    const auto f = failures();
    for (std::size_t k = 0; k < f.size(); ++k) s += (k ? "; " : "") + f[k];
    return s;
  }
  std::string s = fmt::format("{} (scatter {} <= {}, drift {} <= {}",
                              g_checked ? "stationary" : "stationary in scatter and drift only",
                              num(scatter_ratio), num(scatter_limit), num(drift_statistic),
                              num(drift_limit_value));
  s += g_checked ? fmt::format(", g-term {}{} °/s <= {} °/s)",
                               g_exact ? "" : ">= ", num(g_term_dps), num(g_limit_dps))
                 : "; g-term NOT checked: no specification, a constant input of any size passes)";
  return s;
}

std::size_t next_stationarity_look(std::size_t n_cycles) noexcept {
  if (n_cycles < first_live_look_cycles) return first_live_look_cycles;
  return std::max(n_cycles + 1, (n_cycles * 5 + 3) / 4);
}

}  // namespace gyroflip::method
