/// \file
/// \brief The paper's figures and the Allan plot as report::figure values (figures.hpp).
#include "gyroflip/report/figures.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include <fmt/format.h>

#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/digits.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/method/runs.hpp"

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

figure dwell_figure(std::span<const method::dwell> dwells, const std::string& title,
                    const method::flip_pair& pair, const position_table& table) {
  figure f;
  f.title = title;
  f.x = {"time (s)", false};
  f.y = {"dwell mean (°/s)", false};
  const auto at = [&table](int p) {
    return fmt::format("at {}°", table.holds(p) ? table.angle_deg(p) : 0.0);
  };
  series a = points_of(at(pair.plus), 0), b = points_of(at(pair.minus), 1);
  // A table of more positions (issue 33): one series per position, the pair's first in their
  // colours, then the others in the table's order (a 0/180 table draws exactly the pair).
  std::vector<series> others;
  std::vector<int> other_index;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const int p = static_cast<int>(i);
    if (p == pair.plus || p == pair.minus) continue;
    others.push_back(points_of(at(p), static_cast<int>(2 + others.size())));
    other_index.push_back(p);
  }
  for (const auto& d : dwells) {
    series* s = d.position == pair.plus ? &a : d.position == pair.minus ? &b : nullptr;
    for (std::size_t i = 0; s == nullptr && i < other_index.size(); ++i)
      if (other_index[i] == d.position) s = &others[i];
    if (s == nullptr) continue;
    s->x.push_back(d.time_s);
    s->y.push_back(d.rate_dps);
  }
  f.data = {a, b};
  for (auto& o : others)
    if (!o.x.empty()) f.data.push_back(std::move(o));
  return f;
}

figure compensated_figure(std::span<const method::compensated_cycle> cycles,
                          const method::compensation_summary& summary, const std::string& title,
                          bool show_mean) {
  figure f;
  f.title = title;
  f.caption = show_mean
                  ? fmt::format("{} cycles: mean {} °/s, std {} °/s (eqn 12)", summary.cycles,
                                to_digits_of(summary.mean_dps, summary.stderr_correlated_dps, 4),
                                fixed_significant(summary.std_dps, 3))
                  : fmt::format("{} cycles: std {} °/s about the run's own ΔN (eqn 12)",
                                summary.cycles, fixed_significant(summary.std_dps, 3));
  f.x = {"time (s)", false};
  f.y = {"compensated rate (°/s)", false};
  series s = points_of("w = r − ΔN per cycle", 0);
  for (const auto& c : cycles) {
    s.x.push_back(c.time_s);
    s.y.push_back(c.rate_dps);
  }
  const auto [t0, t1] = span_of(s.x);
  f.data = {s};
  if (show_mean) f.data.push_back(level("mean", t0, t1, summary.mean_dps, 1, false));
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
  // Runs 1..n with half a run of room at each end: the frame cut the first and the last runs'
  // error bars in half (review of issue 31).
  f.x = {"run", false, std::ceil(static_cast<double>(runs.size()) / 20.0), 0.5,
         static_cast<double>(runs.size()) + 0.5};
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
  double t_lo = 1e300, t_hi = -1e300;
  for (const auto& r : runs)
    if (std::isfinite(r.cal.temp_c)) {
      t_lo = std::min(t_lo, r.cal.temp_c);
      t_hi = std::max(t_hi, r.cal.temp_c);
    }
  // Runs at different temperatures are not one population: no pooled mean +- std over them
  // (review of issue 22, R16; ΔN(T) has its own figure).
  if (t_hi - t_lo >= method::min_model_span_c) {
    f.caption = fmt::format(
        "{} runs over {:.1f}–{:.1f} °C: ΔN depends on temperature, so no pooled mean ± std is "
        "drawn (see ΔN(T))",
        values.size(), t_lo, t_hi);
    f.data = {s};
    return f;
  }
  // The mean to the digits its standard error supports (review of issue 31: "mean 0.004548, std
  // 0.00157" for 13 runs).
  const double se = sd / std::sqrt(static_cast<double>(values.size()));
  f.caption = fmt::format("{} runs: mean {} °/s, std {} °/s", values.size(),
                          to_digits_of(ms.mean, se, 4), fixed_significant(sd, 2));
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
  // Two bands, each named for what it holds (review of issue 31: the fitted line's interval was
  // labelled as if it held the runs, and 3 of 5 runs lay outside it): the line's own 68.3 %
  // interval, which holds the true ΔN(T), and the prediction band of a new run (a new power-up's
  // ΔN as a run like these measures it: the between-run change and the run's own error), which
  // holds 68.3 % of new runs (delta_n_model::new_run_interval_at).
  series fit = points_of("fitted ΔN(T)", 1);
  fit.how = series::style::lines;
  series band = points_of("ΔN(T) fit, 68 %", 1);
  band.how = series::style::band;
  series runs_band = points_of("a new power-up's run, 68 % (prediction)", 4);
  runs_band.how = series::style::band;
  const double lo = model.temp_min_c, hi = model.temp_max_c;
  const double pad = std::max(0.5, 0.05 * (hi - lo));
  bool any_width = false;  // a line through its runs (0 degrees of freedom) has no interval
  for (int k = 0; k <= 100; ++k) {
    const double t = lo - pad + (hi - lo + 2.0 * pad) * k / 100.0;
    const double v = model.eval(t), se = model.interval_at(t), pred = model.new_run_interval_at(t);
    fit.x.push_back(t);
    fit.y.push_back(v);
    band.x.push_back(t);
    band.y.push_back(v);
    band.y_lo.push_back(v - se);
    band.y_hi.push_back(v + se);
    any_width = any_width || se > 0.0;
    if (std::isfinite(pred)) {
      runs_band.x.push_back(t);
      runs_band.y.push_back(v);
      runs_band.y_lo.push_back(v - pred);
      runs_band.y_hi.push_back(v + pred);
    }
  }
  f.caption = fmt::format("ΔN(T), degree {}, about {:.1f} °C", model.degree(), model.t_ref_c);
  if (!any_width) {
    // No zero-width band (third review of issue 31, M1): a line through its runs has no error.
    f.caption += fmt::format(
        "; the line passes through its {} runs exactly (0 degrees of freedom): no interval, no "
        "band",
        runs.size());
    f.data = {fit, s};
  } else if (runs_band.x.empty()) {
    f.caption += "; no prediction band (the runs' scatter about the line is not estimated)";
    f.data = {band, fit, s};
  } else if (std::isfinite(model.tau2_centre_dps2)) {
    // A run-to-run spread that may change with T, estimated from the runs (review of issue 31,
    // H3: with a constant one the band held 0.54-0.64 of new runs at the ends of the hz1
    // preset's 4-36 °C and 0.77 in the middle; now 0.63-0.73, docs/METHOD-NOTES.md).
    f.caption +=
        "; the prediction band holds 68 % of new runs at each temperature (the fitted runs more "
        "often), the run-to-run spread estimated as a function of temperature from the runs";
    f.data = {runs_band, band, fit, s};
  } else {
    // Too few runs to estimate how the spread changes with T (fewer than 5 about a line): the
    // band assumes it does not (docs/METHOD-NOTES.md).
    f.caption +=
        "; the prediction band holds 68 % of new runs (the fitted runs more often) if the "
        "run-to-run spread does not change with temperature (too few runs to tell): where it "
        "grows away from the middle, fewer at the ends, more in the middle";
    f.data = {runs_band, band, fit, s};
  }
  return f;
}

namespace {

// How an Allan plot shows its curves and the fitted terms: the factor from the curves' unit to
// the plotted one, and each term's label unit, factor and read-off tau.
struct term_units {
  std::string dev_unit;
  double dev_scale = 1.0;
  std::string n_unit, b_unit, k_unit;
  double n_factor = 1.0, k_factor = 1.0, b_factor = 1.0;
  double n_tau_s = 1.0, k_tau_s = 3.0;
  std::string n_at, k_at;  // the read-off taus in words
};

// The number as the report's tables print it (3 significant digits).
std::string g3(double v) {
  return fixed_significant(v, 3);
}

// A curve's name up to its first ':' or " (" ("raw: dwell means at 0°" -> "raw"), to name its
// fitted lines and marks when several curves are fitted.
std::string short_name(const std::string& name) {
  return name.substr(0, std::min(name.find(':'), name.find(" (")));
}

figure allan_plot(std::span<const allan_curve> curves, const term_units& u,
                  const std::string& title) {
  figure f;
  f.title = title;
  f.x = {"averaging time τ (s)", true};
  f.y = {fmt::format("Allan deviation ({})", u.dev_unit), true};
  const double k = u.dev_scale;
  // The taus the plot spans: every curve's, and the read-off taus of the resolved N and K (IEEE
  // 952 Annex C), so that an extrapolated read-off lies on its line.
  double from = 1e300, to = 0.0;
  for (const auto& c : curves) {
    for (const auto& p : c.points) {
      from = std::min(from, p.tau_s);
      to = std::max(to, p.tau_s);
    }
    for (const auto& p : c.beyond) to = std::max(to, p.tau_s);
    if (c.terms && !c.points.empty())
      for (const auto& [resolved, tau] : {std::pair{c.terms->arw.resolved, u.n_tau_s},
                                          std::pair{c.terms->rrw.resolved, u.k_tau_s}})
        if (resolved) {
          from = std::min(from, tau);
          to = std::max(to, tau);
        }
  }
  const std::size_t fitted = static_cast<std::size_t>(std::count_if(
      curves.begin(), curves.end(), [](const allan_curve& c) { return c.terms.has_value(); }));
  std::vector<std::string> not_drawn;
  int color = 0;
  for (const auto& c : curves) {
    const int col = color++;
    series s = points_of(c.name, col);
    s.how = series::style::errorbars;
    s.joined = true;  // one curve
    for (const auto& p : c.points) {
      s.x.push_back(p.tau_s);
      s.y.push_back(p.dev * k);
      // Points without bounds (none computed) show as their value alone.
      s.y_lo.push_back((p.ci_lo > 0.0 ? p.ci_lo : p.dev) * k);
      s.y_hi.push_back((p.ci_hi > 0.0 ? p.ci_hi : p.dev) * k);
    }
    f.data.push_back(std::move(s));
    if (!c.beyond.empty()) {
      series b = points_of(col == 0 ? "open: beyond Stable32's m ≤ (N−1)/4" : "", col);
      b.how = series::style::errorbars;
      b.open = true;
      for (const auto& p : c.beyond) {
        b.x.push_back(p.tau_s);
        b.y.push_back(p.dev * k);
        b.y_lo.push_back((p.ci_lo > 0.0 ? p.ci_lo : p.dev) * k);
        b.y_hi.push_back((p.ci_hi > 0.0 ? p.ci_hi : p.dev) * k);
      }
      f.data.push_back(std::move(b));
    }
    if (!c.terms || c.points.empty()) continue;
    // This curve's fitted terms, in its colour, dashed, named after it when several are fitted.
    const auto& t = *c.terms;
    const std::string who = fitted > 1 ? short_name(c.name) + ": " : "";
    const auto [lo, hi] =
        std::minmax_element(c.points.begin(), c.points.end(),
                            [](const auto& a, const auto& b) { return a.tau_s < b.tau_s; });
    const double tau_lo = lo->tau_s, tau_hi = hi->tau_s;
    const auto line = [&](const std::string& name, auto sigma) {
      series l = points_of(who + name, col);
      l.how = series::style::lines;
      l.dashed = true;
      for (int j = 0; j <= 60; ++j) {
        const double tau = from * std::pow(to / from, j / 60.0);
        l.x.push_back(tau);
        l.y.push_back(sigma(tau));
      }
      f.data.push_back(std::move(l));
    };
    // Read-off points on the lines, where each equals its coefficient (N at n_tau, K at
    // k_tau), "extrapolated" when that tau lies outside this curve's data; B on its flicker
    // floor 0.664 B at the tau where the fitted curve is lowest (inside the data by
    // construction). Each line's key entry says where it is read; the point on the plot
    // carries only the term's letter, in the curve's colour (whole sentences beside the points
    // collided with each other and with the data: review of issue 31).
    const auto inside = [&](double tau) { return tau >= tau_lo * 0.999 && tau <= tau_hi * 1.001; };
    const auto read = [&](double tau, const std::string& at) {
      return fmt::format("at τ = {}{}", at, inside(tau) ? "" : ", extrapolated");
    };
    const double tau_b = std::clamp(t.fit_min_tau_s, tau_lo, tau_hi);
    const std::string n_text = fmt::format("N = {} {} ({})", g3(t.arw.value * u.n_factor), u.n_unit,
                                           read(u.n_tau_s, u.n_at));
    const std::string b_text =
        fmt::format("B = {} {} (floor 0.664 B {})", g3(t.bias_instability.value * u.b_factor),
                    u.b_unit, read(tau_b, fmt::format("{} s", g3(tau_b))));
    const std::string k_text = fmt::format("K = {} {} ({})", g3(t.rrw.value * u.k_factor), u.k_unit,
                                           read(u.k_tau_s, u.k_at));
    if (t.arw.resolved) line(n_text, [&](double tau) { return k * t.arw.value / std::sqrt(tau); });
    if (t.bias_instability.resolved)
      line(b_text, [&](double) { return k * floor_factor * t.bias_instability.value; });
    if (t.rrw.resolved)
      line(k_text, [&](double tau) { return k * t.rrw.value * std::sqrt(tau / 3.0); });
    if (t.quantization.resolved)
      line(fmt::format("Q = {}", g3(t.quantization.value)),
           [&](double tau) { return k * std::sqrt(3.0) * t.quantization.value / tau; });
    if (t.rate_ramp.resolved)
      line(fmt::format("R = {}", g3(t.rate_ramp.value)),
           [&](double tau) { return k * t.rate_ramp.value * tau / std::numbers::sqrt2; });
    const auto mark = [&](const char* letter, double tau, double y) {
      // With several fitted curves, the first one's letters left of their points and the
      // others' right (two curves read at one tau stay apart); with one, the letter left of a
      // point in the right half of the plot, so that it stays on it.
      const bool left = fitted > 1 ? col == 0 : tau > std::sqrt(from * to);
      f.notes.push_back({tau, y, letter, left, col});
    };
    if (t.arw.resolved) mark("N", u.n_tau_s, k * t.arw.value / std::sqrt(u.n_tau_s));
    if (t.bias_instability.resolved) mark("B", tau_b, k * floor_factor * t.bias_instability.value);
    if (t.rrw.resolved) mark("K", u.k_tau_s, k * t.rrw.value * std::sqrt(u.k_tau_s / 3.0));
    // Upper limits are not drawn (a line or point would read as a value); the caption names them.
    for (const auto& [sym, term, factor, unit] :
         {std::tuple{"N", &t.arw, u.n_factor, &u.n_unit},
          std::tuple{"B", &t.bias_instability, u.b_factor, &u.b_unit},
          std::tuple{"K", &t.rrw, u.k_factor, &u.k_unit}})
      if (!term->resolved)
        not_drawn.push_back(fmt::format("{}{} < {} {}", who, sym, g3(term->hi * factor), *unit));
  }
  if (!not_drawn.empty()) {
    f.caption = "upper limits, not drawn: ";
    for (std::size_t j = 0; j < not_drawn.size(); ++j)
      f.caption += (j > 0 ? "; " : "") + not_drawn[j];
  }
  return f;
}

}  // namespace

figure allan_figure(std::span<const allan_curve> curves, const std::string& unit,
                    const std::string& title) {
  term_units u;
  u.dev_unit = unit;
  u.n_unit = unit + "/√Hz";
  u.b_unit = unit;
  u.k_unit = unit + "·√Hz";
  u.n_at = "1 s";
  u.k_at = "3 s";
  return allan_plot(curves, u, title);
}

figure gyro_allan_figure(std::span<const allan_curve> curves_dps, const std::string& title) {
  term_units u;
  u.dev_unit = "°/h";
  u.dev_scale = units::dph_per_dps;
  u.n_unit = "°/√h";
  u.n_factor = units::deg_rth_per_deg_rts;
  u.b_unit = "°/h";
  u.b_factor = units::dph_per_dps;
  u.k_unit = "°/h/√h";
  u.k_factor = units::dph_rth_per_dps_rts;
  u.n_tau_s = units::s_per_h;        // sigma(1 h) in deg/h = N in deg/sqrt(h)
  u.k_tau_s = 3.0 * units::s_per_h;  // sigma(3 h) in deg/h = K in deg/h/sqrt(h)
  u.n_at = "1 h";
  u.k_at = "3 h";
  return allan_plot(curves_dps, u, title);
}

result<figure> noise_figure(std::span<const allan_curve> curves_dps, const std::string& unit,
                            const std::string& title) {
  figure f;
  if (unit == "deg/h") {
    f = gyro_allan_figure(curves_dps, title);
  } else if (unit == "deg/s") {
    f = allan_figure(curves_dps, "°/s", title);
  } else if (unit == "rad/s") {
    term_units u;
    u.dev_unit = "rad/s";
    u.dev_scale = units::rad_per_deg;
    u.n_unit = "rad/s/√Hz";
    u.b_unit = "rad/s";
    u.k_unit = "rad/s²/√Hz";
    u.n_factor = u.b_factor = u.k_factor = units::rad_per_deg;
    u.n_at = "1 s";
    u.k_at = "3 s";
    f = allan_plot(curves_dps, u, title);
  } else if (units::is_accel_unit(unit)) {
    // Accelerometer curves in m/s^2: N (VRW) read at 1 s, K (acceleration random walk) at 3 s.
    const bool si = unit == "m/s^2";
    const std::string shown = si ? "m/s²" : unit == "ug" ? "µg" : unit;
    term_units u;
    u.dev_unit = shown;
    u.dev_scale = 1.0 / units::mps2_per_unit(unit);
    u.n_unit = si ? "m/s²/√Hz" : shown + "/√Hz";
    u.b_unit = shown;
    u.k_unit = si ? "m/s³/√Hz" : shown + "/√s";
    u.n_factor = u.b_factor = u.k_factor = u.dev_scale;
    u.n_at = "1 s";
    u.k_at = "3 s";
    f = allan_plot(curves_dps, u, title);
  } else {
    return usage_error(
        "the plot's unit must be deg/h, deg/s or rad/s (gyro), m/s^2, mg or ug "
        "(accelerometer); got " +
        unit);
  }
  f.key_inside = true;
  for (const auto& c : curves_dps)
    if (!c.beyond.empty() && !c.points.empty()) {
      f.caption += fmt::format(
          "{}Stable32 stops at τ = {} s (m ≤ (N−1)/4); open points to "
          "m ≤ (N−1)/2, as MATLAB and allantools, rest on few terms",
          f.caption.empty() ? "" : "; ", g3(c.points.back().tau_s));
      break;
    }
  return f;
}

allan_curve noise_curve(const io::noise_report& r) {
  const double k = r.quantity == "accel" ? r.mps2_per_unit : r.deg_per_unit;
  allan_curve curve{r.column, r.result.oadev, r.result.terms, r.result.long_oadev};
  for (auto* v : {&curve.points, &curve.beyond})
    for (auto& p : *v) {
      p.dev *= k;
      p.ci_lo *= k;
      p.ci_hi *= k;
    }
  for (auto* t : {&curve.terms->quantization, &curve.terms->arw, &curve.terms->bias_instability,
                  &curve.terms->rrw, &curve.terms->rate_ramp}) {
    t->value *= k;
    t->lo *= k;
    t->hi *= k;
  }
  return curve;
}

}  // namespace gyroflip::report
