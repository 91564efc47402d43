/// \file
/// \brief The paper's figures and the Allan plot as report::figure values (figures.hpp).
#include "gyroflip/report/figures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "gyroflip/analysis/drift.hpp"

namespace gyroflip::report {

namespace {

// The flicker floor of AVAR: sigma = sqrt(2 ln 2 / pi) B (IEEE 952 Annex C; FACTS §7).
const double floor_factor = std::sqrt(2.0 * std::numbers::ln2 / std::numbers::pi);

series points_of(std::string title, int color) {
  series s;
  s.title = std::move(title);
  s.color = color;
  return s;
}

// A horizontal line across [x0, x1].
series level(std::string title, double x0, double x1, double y, int color, bool dashed) {
  series s = points_of(std::move(title), color);
  s.how = series::style::lines;
  s.dashed = dashed;
  s.x = {x0, x1};
  s.y = {y, y};
  return s;
}

std::pair<double, double> span_of(std::span<const double> t) {
  if (t.empty()) return {0.0, 1.0};
  const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
  return {*lo, *hi};
}

}  // namespace

figure dwell_figure(std::span<const method::dwell> dwells, const std::string& title) {
  figure f;
  f.title = title;
  f.x = {"time (s)", false};
  f.y = {"dwell mean (°/s)", false};
  series a = points_of("at 0°", 0), b = points_of("at 180°", 1);
  for (const auto& d : dwells) {
    auto& s = d.sign > 0 ? a : b;
    s.x.push_back(d.time_s);
    s.y.push_back(d.rate_dps);
  }
  f.data = {a, b};
  return f;
}

figure compensated_figure(std::span<const method::compensated_cycle> cycles,
                          const method::compensation_summary& summary, const std::string& title) {
  figure f;
  f.title = title;
  f.caption = fmt::format("{} cycles: mean {:.4g} °/s, std {:.4g} °/s (eqn 12)", summary.cycles,
                          summary.mean_dps, summary.std_dps);
  f.x = {"time (s)", false};
  f.y = {"compensated rate (°/s)", false};
  series s = points_of("w = r − ΔN per cycle", 0);
  for (const auto& c : cycles) {
    s.x.push_back(c.time_s);
    s.y.push_back(c.rate_dps);
  }
  const auto [t0, t1] = span_of(s.x);
  f.data = {s, level("mean", t0, t1, summary.mean_dps, 1, false)};
  return f;
}

figure bias_figure(std::span<const method::cycle> cycles, const std::string& title) {
  figure f;
  f.title = title;
  f.caption = "c = (y₀ + y₁₈₀)/2: the bias and its drift, which the flip removes";
  f.x = {"time (s)", false};
  f.y = {"bias estimate c (°/s)", false};
  series s = points_of("c per cycle", 2);
  for (const auto& c : cycles) {
    s.x.push_back(c.time_s);
    s.y.push_back(c.bias_dps);
  }
  f.data = {s};
  return f;
}

figure delta_n_runs_figure(std::span<const io::calibration_entry> runs, const std::string& title) {
  figure f;
  f.title = title;
  f.x = {"run", false};
  f.y = {"ΔN (°/s)", false};
  series s = points_of("ΔN ± correlated standard error", 0);
  s.how = series::style::errorbars;
  std::vector<double> values;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& c = runs[k].cal;
    s.x.push_back(static_cast<double>(k + 1));
    s.y.push_back(c.delta_n_dps);
    s.y_lo.push_back(c.delta_n_dps - c.stderr_correlated_dps);
    s.y_hi.push_back(c.delta_n_dps + c.stderr_correlated_dps);
    values.push_back(c.delta_n_dps);
  }
  if (values.empty()) return f;
  const auto ms = analysis::mean_and_std(values);
  const double sd = values.size() > 1 ? ms.std : 0.0;
  f.caption = fmt::format("{} runs: mean {:.6g} °/s, std {:.3g} °/s", values.size(), ms.mean, sd);
  const double x0 = 0.5, x1 = static_cast<double>(runs.size()) + 0.5;
  series band = points_of("mean ± std", 1);
  band.how = series::style::band;
  band.x = {x0, x1};
  band.y = {ms.mean, ms.mean};
  band.y_lo = {ms.mean - sd, ms.mean - sd};
  band.y_hi = {ms.mean + sd, ms.mean + sd};
  f.data = {band, level("", x0, x1, ms.mean, 1, false), s};
  return f;
}

figure delta_n_temperature_figure(std::span<const io::calibration_entry> runs,
                                  const method::delta_n_model& model, const std::string& title) {
  figure f;
  f.title = title;
  f.caption = fmt::format("ΔN(T), degree {}, about {:.1f} °C", model.degree(), model.t_ref_c);
  f.x = {"temperature (°C)", false};
  f.y = {"ΔN (°/s)", false};
  series s = points_of("runs (± correlated standard error)", 0);
  s.how = series::style::errorbars;
  for (const auto& r : runs) {
    s.x.push_back(r.cal.temp_c);
    s.y.push_back(r.cal.delta_n_dps);
    s.y_lo.push_back(r.cal.delta_n_dps - r.cal.stderr_correlated_dps);
    s.y_hi.push_back(r.cal.delta_n_dps + r.cal.stderr_correlated_dps);
  }
  series fit = points_of("fitted ΔN(T)", 1);
  fit.how = series::style::lines;
  series band = points_of("± 1 standard error", 1);
  band.how = series::style::band;
  const double lo = model.temp_min_c, hi = model.temp_max_c;
  const double pad = std::max(0.5, 0.05 * (hi - lo));
  for (int k = 0; k <= 100; ++k) {
    const double t = lo - pad + (hi - lo + 2.0 * pad) * k / 100.0;
    const double v = model.eval(t), se = model.stderr_at(t);
    fit.x.push_back(t);
    fit.y.push_back(v);
    band.x.push_back(t);
    band.y.push_back(v);
    band.y_lo.push_back(v - se);
    band.y_hi.push_back(v + se);
  }
  f.data = {band, fit, s};
  return f;
}

figure allan_figure(std::span<const allan_curve> curves, const std::string& unit,
                    const std::string& title) {
  figure f;
  f.title = title;
  f.x = {"averaging time τ (s)", true};
  f.y = {fmt::format("Allan deviation ({})", unit), true};
  double tau_lo = 1e300, tau_hi = 0.0;
  int color = 0;
  for (const auto& c : curves) {
    series s = points_of(c.name, color++);
    s.how = series::style::errorbars;
    for (const auto& p : c.points) {
      s.x.push_back(p.tau_s);
      s.y.push_back(p.dev);
      // Points without bounds (none computed) show as their value alone.
      s.y_lo.push_back(p.ci_lo > 0.0 ? p.ci_lo : p.dev);
      s.y_hi.push_back(p.ci_hi > 0.0 ? p.ci_hi : p.dev);
      tau_lo = std::min(tau_lo, p.tau_s);
      tau_hi = std::max(tau_hi, p.tau_s);
    }
    f.data.push_back(std::move(s));
  }
  const auto fitted = std::find_if(curves.begin(), curves.end(),
                                   [](const allan_curve& c) { return c.terms.has_value(); });
  if (fitted == curves.end() || tau_hi <= 0.0) return f;
  const auto& t = *fitted->terms;
  // The fitted terms' lines, each over the plot's tau range (IEEE 952 Annex C).
  const auto line = [&](const std::string& name, int col, auto sigma) {
    series s = points_of(name, col);
    s.how = series::style::lines;
    s.dashed = true;
    for (int k = 0; k <= 60; ++k) {
      const double tau = tau_lo * std::pow(tau_hi / tau_lo, k / 60.0);
      s.x.push_back(tau);
      s.y.push_back(sigma(tau));
    }
    f.data.push_back(std::move(s));
  };
  if (t.arw.resolved)
    line(fmt::format("N = {:.3g} {}/√Hz", t.arw.value, unit), 2,
         [&](double tau) { return t.arw.value / std::sqrt(tau); });
  if (t.bias_instability.resolved)
    line(fmt::format("B = {:.3g} {}", t.bias_instability.value, unit), 3,
         [&](double) { return floor_factor * t.bias_instability.value; });
  if (t.rrw.resolved)
    line(fmt::format("K = {:.3g} {}·√Hz", t.rrw.value, unit), 4,
         [&](double tau) { return t.rrw.value * std::sqrt(tau / 3.0); });
  if (t.quantization.resolved)
    line(fmt::format("Q = {:.3g}", t.quantization.value), 5,
         [&](double tau) { return std::sqrt(3.0) * t.quantization.value / tau; });
  if (t.rate_ramp.resolved)
    line(fmt::format("R = {:.3g}", t.rate_ramp.value), 6,
         [&](double tau) { return t.rate_ramp.value * tau / std::numbers::sqrt2; });
  // Read-off points: N at tau = 1 s, K at tau = 3 s (where the lines equal the coefficients),
  // B at the floor.
  if (t.arw.resolved) f.notes.push_back({1.0, t.arw.value, "N at τ = 1 s"});
  if (t.rrw.resolved) f.notes.push_back({3.0, t.rrw.value, "K at τ = 3 s"});
  if (t.bias_floor_dev > 0.0)
    f.notes.push_back({t.bias_floor_tau_s, t.bias_floor_dev,
                       t.bias_floor_reached ? "floor: B = floor / 0.664" : "no floor yet"});
  return f;
}

}  // namespace gyroflip::report
