/// \file
/// \brief The stationarity test of a calibration run (stationarity.hpp).
#include "gyroflip/method/stationarity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
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

// The drift and step statistics of r (see stationarity.hpp), scaled by sigma, r's long-run std.
struct drift_stats {
  double cusum = 0.0;     // max_k |S_k| before scaling
  double sup_t = 0.0;     // max over trimmed k of |S_k| / sqrt(k (n - k) / n), before scaling
  std::size_t at = 0;     // first cycle after the sup-t's split
  double slope = 0.0;     // least-squares slope of r in time (deg/s per s)
  double slope_se = 0.0;  // its standard error for unit-variance uncorrelated r
};

drift_stats drift_of(std::span<const cycle> cycles, std::span<const double> r, double mean,
                     std::size_t trim) {
  drift_stats out;
  const std::size_t n = r.size();
  const double nd = static_cast<double>(n);
  double s = 0.0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    s += r[k] - mean;
    out.cusum = std::max(out.cusum, std::abs(s));
    const std::size_t left = k + 1;
    if (left < trim || n - left < trim) continue;
    const double kd = static_cast<double>(left);
    const double t = std::abs(s) / std::sqrt(kd * (nd - kd) / nd);
    if (t > out.sup_t) {
      out.sup_t = t;
      out.at = left;
    }
  }
  double t_mean = 0.0;
  for (const auto& cy : cycles) t_mean += cy.time_s;
  t_mean /= nd;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dt = cycles[i].time_s - t_mean;
    sxx += dt * dt;
    sxy += dt * (r[i] - mean);
  }
  if (sxx > 0.0) {
    out.slope = sxy / sxx;
    out.slope_se = 1.0 / std::sqrt(sxx);
  }
  return out;
}

// The slope's t numerator: slope / (its standard error for unit-variance r) = slope sqrt(Sxx).
double sxx_of(const drift_stats& d) {
  return d.slope_se > 0.0 ? 1.0 / (d.slope_se * d.slope_se) : 0.0;
}

// A statistic scaled by sigma; a noise-free run (sigma at rounding level) gives 1e300 when the
// numerator is above rounding, else 0.
double scaled(double numerator, double sigma, double rounding) {
  if (sigma > rounding) return numerator / sigma;
  return numerator > rounding ? 1e300 : 0.0;
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

void check_temperature(std::span<const cycle> cycles, stationarity& out) {
  double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
  for (const auto& cy : cycles)
    if (std::isfinite(cy.temp_c)) {
      t_lo = std::min(t_lo, cy.temp_c);
      t_hi = std::max(t_hi, cy.temp_c);
    }
  out.has_temp = t_lo <= t_hi;
  out.temp_span_c = out.has_temp ? t_hi - t_lo : 0.0;
  out.temp_failed = out.temp_span_c > isothermal_span_c;
}

// r's std against the specification's white noise for these dwells (noise_spec): a dwell mean
// over T has std N / sqrt(T) (ADEV(tau) = N / sqrt(tau)), r the scheme's white variance of it;
// T taken as the cycle period's share per dwell (an upper bound, so the ratio errs high).
void check_noise(std::span<const double> r, std::span<const cycle> cycles,
                 const stationarity_inputs& in, stationarity& out) {
  if (!in.noise || !(in.noise->arw_dps_rthz > 0.0) || cycles.size() < 2) return;
  const auto& t = scheme_of(in.pair).transfer();
  const double period_s =
      (cycles.back().time_s - cycles.front().time_s) / static_cast<double>(cycles.size() - 1);
  const double dwell_s = period_s / static_cast<double>(t.cycle_dwells);
  if (!(dwell_s > 0.0) || !std::isfinite(dwell_s)) return;
  const double expected = in.noise->arw_dps_rthz * std::sqrt(t.white_covariance()[0] / dwell_s);
  out.noise_checked = true;
  out.noise_source = in.noise->source;
  out.noise_ratio = std::min(analysis::mean_and_std(r).std / expected, 1e300);
  out.noise_failed = !(out.noise_ratio <= out.noise_limit);
}

// One cycle far outside the rest (a knock on the bench, a spike): max |r - median| / (1.4826
// MAD), the MAD a robust std that one cycle cannot move (Hampel 1974, JASA 69 383-393).
void check_outlier(std::span<const double> r, std::span<const cycle> cycles, double rounding,
                   stationarity& out) {
  std::vector<double> v(r.begin(), r.end());
  const double med = analysis::upper_median(v);
  for (auto& x : v) x = std::abs(x - med);
  const double mad = 1.4826 * analysis::upper_median(v);
  std::size_t at = 0;
  for (std::size_t k = 1; k < r.size(); ++k)
    if (std::abs(r[k] - med) > std::abs(r[at] - med)) at = k;
  const double dev = std::abs(r[at] - med);
  out.outlier_z = mad > rounding ? std::min(dev / mad, 1e300) : (dev > rounding ? 1e300 : 0.0);
  out.outlier_limit = outlier_limit_z(r.size());
  out.outlier_cycle = at + 1;
  out.outlier_time_s = cycles[at].time_s;
  out.outlier_failed = out.outlier_z > out.outlier_limit;
}

}  // namespace

double outlier_limit_z(std::size_t n) noexcept {
  // The normal quantile of 1 - alpha / (2 n), by bisection on erfc (monotone).
  const double p = outlier_alpha / (2.0 * static_cast<double>(std::max<std::size_t>(n, 1)));
  double lo = 0.0, hi = 40.0;
  for (int k = 0; k < 100; ++k) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::numbers::sqrt2) > p ? lo : hi) = mid;
  }
  return std::max(outlier_floor_z, 0.5 * (lo + hi));
}

double white_std_over_adev(pairing p) noexcept {
  const auto& t = scheme_of(p).transfer();
  // The reference is c's white noise; r's kernel has c's norm for the 0/180 schemes (the same
  // weights with signs), a larger one for the harmonic scheme (c1 against b: sqrt(2) for a
  // sweep), whose ratio then scales it.
  const auto cv = t.white_covariance();
  if (cv[0] == cv[2]) return t.white_std_over_adev();
  return t.white_std_over_adev() * std::sqrt(cv[0] / cv[2]);
}

double sup_t_tail(double x, double pi0) noexcept {
  if (!(pi0 > 0.0 && pi0 < 0.5)) return 1.0;
  const double log_ratio = 2.0 * std::log((1.0 - pi0) / pi0);
  const double phi = std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
  return x * phi * (log_ratio * (1.0 - 1.0 / (x * x)) + 4.0 / (x * x));
}

double step_statistic_limit(std::size_t n, std::size_t trim, double edf) {
  const double pi0 = static_cast<double>(std::max<std::size_t>(trim, 1)) / static_cast<double>(n);
  if (!(pi0 < 0.5)) return slope_statistic_limit(edf);  // one split: a single t
  // The x with sup_t_tail(x) = drift_false_alarm (decreasing for x > 2), by bisection.
  double lo = 2.0, hi = 40.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (sup_t_tail(mid, pi0) > drift_false_alarm ? lo : hi) = mid;
  }
  // Student's t at the normal's tail probability there (erfc(x / sqrt 2) two-sided).
  const double p_two_sided = std::erfc(0.5 * (lo + hi) / std::numbers::sqrt2);
  return edf > 0.0 ? analysis::student_t_quantile(1.0 - 0.5 * p_two_sided, edf) : 0.5 * (lo + hi);
}

double slope_statistic_limit(double edf) {
  const double dof = edf > 0.0 ? edf : 1e6;
  return analysis::student_t_quantile(1.0 - 0.5 * drift_false_alarm, dof);
}

stationarity check_stationarity(std::span<const cycle> cycles, const calibration& cal,
                                const stationarity_inputs& in) {
  stationarity out;
  const std::size_t n = cycles.size();
  out.cycles = n;
  // The g-term and the temperature need no minimum of cycles (fifth review of issue 31, F16: a
  // 14-cycle run on a 0.5 deg/s table was vouched for).
  check_g_term(cal, in, out);
  check_temperature(cycles, out);
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
  check_noise(r, cycles, in, out);
  check_outlier(r, cycles, rounding, out);
  // Drift or step: r's long-run std from short averaging times (a drift or step barely enters
  // it), the OLS-CUSUM, the step statistic (sup-t) and the slope's t.
  const std::size_t m = std::clamp<std::size_t>(n / 8, 1, drift_scale_cycles);
  const double sigma = std::sqrt(oavar(r, m) * static_cast<double>(m));
  const double edf = analysis::edf(analysis::dev_kind::oadev, 0, m, n + 1);
  out.long_run_std_dps = sigma;
  out.trim_cycles = std::min(step_trim_cycles, n / 4);
  const auto d = drift_of(cycles, r, mean, out.trim_cycles);
  out.drift_statistic = scaled(d.cusum / std::sqrt(nd), sigma, rounding);
  out.step_statistic = scaled(d.sup_t, sigma, rounding);
  out.step_statistic_limit_value = step_statistic_limit(n, out.trim_cycles, edf);
  const auto head = std::span<const double>(r).first(d.at);
  const auto tail = std::span<const double>(r).subspan(d.at);
  out.step_dps = d.at > 0 && !tail.empty() ? mean_of(tail) - mean_of(head) : 0.0;
  out.step_time_s = cycles[std::min(d.at, n - 1)].time_s;
  out.step_limit_dps = std::max(3.0 * cal.stderr_correlated_dps, rounding);
  out.slope_statistic =
      std::copysign(scaled(std::abs(d.slope) * std::sqrt(sxx_of(d)), sigma, rounding), d.slope);
  out.slope_limit = slope_statistic_limit(edf);
  out.ramp_dps = d.slope * (cycles[n - 1].time_s - cycles[0].time_s);
  // The sizes that reach each limit (see stationarity.hpp): a step at k of n moves the sup-t by
  // delta sqrt(k (n - k) / n) / sigma; a ramp of R over the run moves the slope's t by
  // R / ((t_n - t_1) slope_se sigma).
  const double end = 0.03 * nd;
  out.step_hidden_dps = out.step_statistic_limit_value * sigma * 2.0 / std::sqrt(nd);
  out.step_hidden_end_dps =
      out.step_statistic_limit_value * sigma / std::sqrt(std::max(1.0, end * (nd - end) / nd));
  out.ramp_hidden_dps =
      out.slope_limit * sigma * d.slope_se * (cycles[n - 1].time_s - cycles[0].time_s);
  out.drift_failed = out.drift_judged_failed();
  // Every statistic written is finite (a run of identical values gives 1e300, never inf).
  out.scatter_ratio = std::min(out.scatter_ratio, 1e300);
  out.drift_statistic = std::min(out.drift_statistic, 1e300);
  out.step_statistic = std::min(out.step_statistic, 1e300);
  out.slope_statistic = std::clamp(out.slope_statistic, -1e300, 1e300);
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
  if (drift_failed) {
    const bool step =
        step_statistic_limit_value > 0.0 && step_statistic > step_statistic_limit_value;
    const bool slope = slope_limit > 0.0 && std::abs(slope_statistic) > slope_limit;
    std::string what;
    if (step || !slope)
      what = fmt::format("r steps by {} °/s at t = {:.0f} s ({}CUSUM {} against {})", num(step_dps),
                         step_time_s,
                         step_statistic_limit_value > 0.0
                             ? fmt::format("step statistic {} against {}, ", num(step_statistic),
                                           num(step_statistic_limit_value))
                             : std::string(),
                         num(drift_statistic), num(drift_limit_value));
    if (slope)
      what += fmt::format("{}r drifts by {} °/s over the run (slope t {} > {})",
                          what.empty() ? "" : "; ", num(ramp_dps), num(slope_statistic),
                          num(slope_limit));
    out.push_back(fmt::format(
        "{}; beyond 3 correlated errors, {} °/s{}", what, num(step_limit_dps),
        temp_span_c > 1.0
            ? fmt::format("; the temperature moved {:.1f} °C over the run, and ΔN follows it: "
                          "calibrate at a steady temperature, or fit ΔN(T) over runs at several",
                          temp_span_c)
            : std::string()));
  }
  if (temp_failed)
    out.push_back(fmt::format(
        "the temperature moved {:.1f} °C during the run: not isothermal (more than {:g} °C), "
        "so its dN is a mean over temperatures and no dN(T) can place it; calibrate at a steady "
        "temperature",
        temp_span_c, isothermal_span_c));
  if (checked && noise_failed)
    out.push_back(fmt::format(
        "its per-cycle scatter is {} times what the sensor's noise gives for these dwells (limit "
        "{}; {}): a disturbed or faulty run, not a calibration",
        num(noise_ratio), num(noise_limit), noise_source));
  if (checked && outlier_failed)
    out.push_back(fmt::format(
        "its cycle {} (t = {:.0f} s) lies {} robust standard deviations from the median r (limit "
        "{} for {} cycles): a knock or a spike",
        outlier_cycle, outlier_time_s, num(outlier_z), num(outlier_limit), cycles));
  if (g_failed)
    out.push_back(fmt::format(
        "its g-term is {}{} °/s, {} times the limit {} °/s at 1 g ({}), beyond 3 correlated "
        "errors: a rate input, or a tilted or moving rig",
        g_exact ? "" : "at least ", num(g_term_dps), num(g_term_dps / g_limit_dps),
        num(g_limit_dps), g_source));
  return out;
}

std::vector<std::string> stationarity::caveats() const {
  if (vouched() || failed()) return {};
  std::vector<std::string> out;
  if (!checked)
    out.push_back(fmt::format(
        "NOT VOUCHED FOR: its scatter and drift could not be tested ({}), so an input rate that "
        "changes during the run passes unseen; record a longer run",
        why_not.empty() ? "a file that predates the test" : why_not));
  if (!g_checked)
    out.emplace_back(
        "its g-term was not checked (no sensor specification), so a constant input rate of any "
        "size passes the scatter and drift tests and enters dN whole (a turning or tilted "
        "table); check it by naming the sensor's specification (a built-in preset or a TOML "
        "preset file)");
  return out;
}

bool stationarity::drift_judged_failed() const noexcept {
  const auto beyond = [this](double change) { return std::abs(change) > step_limit_dps; };
  const bool cusum = drift_statistic > drift_limit_value && beyond(step_dps);
  const bool step = step_statistic_limit_value > 0.0 &&
                    step_statistic > step_statistic_limit_value && beyond(step_dps);
  const bool slope =
      slope_limit > 0.0 && std::abs(slope_statistic) > slope_limit && beyond(ramp_dps);
  return cusum || step || slope;
}

stationarity stationarity::rejudged() const {
  stationarity s = *this;
  s.g_failed = g_checked && g_term_dps - g_margin_dps > g_limit_dps;
  s.temp_failed = temp_span_c > isothermal_span_c;
  if (!checked) return s;
  s.noise_failed = noise_checked && !(noise_ratio <= noise_limit);
  s.outlier_failed = outlier_limit > 0.0 && outlier_z > outlier_limit;
  s.scatter_failed = scatter_ratio > scatter_limit || scatter_ratio < scatter_low_limit;
  s.drift_failed = drift_judged_failed();
  s.g_failed = g_checked && g_term_dps - g_margin_dps > g_limit_dps;
  s.temp_failed = temp_span_c > isothermal_span_c;
  return s;
}

// The g-term against its limit, said as it is: above the limit but within the margin of 3
// correlated errors passes, and says so (fifth review of issue 31, F11(c)).
namespace {
std::string g_text(const stationarity& s) {
  const std::string term =
      fmt::format("g-term {}{} °/s", s.g_exact ? "" : ">= ", num(s.g_term_dps));
  if (s.g_term_dps <= s.g_limit_dps) return fmt::format("{} <= {} °/s", term, num(s.g_limit_dps));
  return fmt::format("{}, above the limit {} °/s by less than 3 errors ({} °/s)", term,
                     num(s.g_limit_dps), num(s.g_margin_dps));
}
}  // namespace

std::string stationarity::summary() const {
  if (!checked && !failed())
    return fmt::format("NOT VOUCHED FOR: scatter and drift not tested ({}){}",
                       why_not.empty() ? "a file that predates the test" : why_not,
                       g_checked ? "; " + g_text(*this)
                                 : "; g-term NOT checked: no specification, a constant input of "
                                   "any size passes");
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
  // A statistic beyond its limit whose level change is within 3 correlated errors passes.
  const auto against = [](double v, double limit) {
    return fmt::format("{} {} {}", num(v), v > limit ? ">" : "<=", num(limit));
  };
  if (step_statistic_limit_value > 0.0)
    s += ", step " + against(step_statistic, step_statistic_limit_value);
  if (slope_limit > 0.0) s += ", slope " + against(std::abs(slope_statistic), slope_limit);
  if (noise_checked)
    s += fmt::format(", noise {} <= {} of the specification's", num(noise_ratio), num(noise_limit));
  if (outlier_limit > 0.0)
    s += fmt::format(", largest cycle {} <= {} robust std", num(outlier_z), num(outlier_limit));
  if (!has_temp) s += ", temperature not checked (no temp_c)";
  s += g_checked ? ", " + g_text(*this) + ")"
                 : "; g-term NOT checked: no specification, a constant input of any size passes)";
  return s;
}

std::size_t next_stationarity_look(std::size_t n_cycles) noexcept {
  if (n_cycles < first_live_look_cycles) return first_live_look_cycles;
  return std::max(n_cycles + 1, (n_cycles * 5 + 3) / 4);
}

}  // namespace gyroflip::method
