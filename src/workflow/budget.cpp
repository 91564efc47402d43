/// \file
/// \brief The uncertainty budget of dN (budget.hpp).
#include "gyroflip/workflow/budget.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/core/digits.hpp"
#include "gyroflip/method/runs.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip::workflow {

double turn_on_spread_dps(const sensor::sensor_params& p, double temp_c) noexcept {
  const double tc =
      std::isfinite(temp_c) ? p.g_sens_tc_turn_on_sigma_dps_per_g_c * (temp_c - p.temp_ref_c) : 0.0;
  return std::hypot(p.g_sens_turn_on_sigma_dps_per_g, tc);  // x 1 g, upside down
}

delta_n_budget budget_of(std::span<const io::calibration_entry> runs,
                         const std::optional<method::delta_n_model>& model,
                         const sensor::sensor_params* preset, const std::string& preset_name) {
  delta_n_budget b;
  b.runs = runs.size();
  if (runs.empty()) {
    constexpr double unknown = std::numeric_limits<double>::quiet_NaN();
    b.within_run_dps = b.single_run_dps = b.run_to_run_dps = b.calibration_dps =
        b.new_power_up_dps = unknown;
    b.temp_c = unknown;
    b.run_to_run_source = "unknown: the calibration lists no runs";
    b.model_note = "not known: the calibration lists no runs and states no error";
    b.valid = false;
    b.invalid_why = "not known: the calibration lists no runs and states no error";
    return b;
  }
  b.within_run_dps = method::pooled_correlated_stderr(calibrations_of(runs));
  {
    std::vector<double> own;
    for (const auto& r : runs) own.push_back(r.cal.stderr_correlated_dps);
    std::sort(own.begin(), own.end());
    const std::size_t h = own.size() / 2;
    b.single_run_dps = own.size() % 2 ? own[h] : 0.5 * (own[h - 1] + own[h]);
  }
  double t_sum = 0.0;
  std::size_t t_n = 0;
  for (const auto& r : runs)
    if (std::isfinite(r.cal.temp_c)) {
      t_sum += r.cal.temp_c;
      ++t_n;
    }
  b.temp_c = t_n > 0 ? t_sum / static_cast<double>(t_n) : std::numeric_limits<double>::quiet_NaN();
  // The runs show their repeatability when a model with degrees of freedom is fitted to them:
  // the scatter of their dN about it.
  std::size_t dof = 0;
  if (model && runs.size() > model->degree() + 1) dof = runs.size() - model->degree() - 1;
  if (model && dof > 0) {
    // At one temperature: the plain sample std of the runs' dN (what the label says; the
    // weighted mean would weight runs by within-run errors that their scatter dwarfs, review
    // R5). A dN(T) line: the runs' scatter about it, over its degrees of freedom.
    double plain_mean = 0.0;
    for (const auto& r : runs) plain_mean += r.cal.delta_n_dps / static_cast<double>(runs.size());
    double ss = 0.0, worst = 0.0;
    for (const auto& r : runs) {
      const double d =
          r.cal.delta_n_dps - (model->degree() == 0 ? plain_mean : model->eval(r.cal.temp_c));
      ss += d * d;
      worst = std::max(worst, model->interval_at(r.cal.temp_c));
    }
    b.run_to_run_dps = b.runs_std_dps = std::sqrt(ss / static_cast<double>(dof));
    b.run_to_run_measured = true;
    b.run_to_run_dof = dof;
    // A std below the runs' own noise does not resolve the power-up change (fourth review of
    // issue 31, F1: two runs 16 microdeg/s apart, each +-0.00037, read as "dN moves by about
    // 0.000011 deg/s"): the repeatability is then floored at what the runs can tell, their own
    // noise (the median of their errors), or the sensor preset's turn-on spread where larger.
    const double preset_spread = preset != nullptr ? turn_on_spread_dps(*preset, b.temp_c) : 0.0;
    b.run_to_run_floored = b.runs_std_dps < b.single_run_dps;
    if (b.run_to_run_floored)
      b.run_to_run_dps =
          std::max(b.single_run_dps, std::isfinite(preset_spread) ? preset_spread : 0.0);
    // A random-effects fit's intervals take Student's t for its degrees of freedom, and so does
    // a new power-up's (its repeatability is estimated from as few runs): measured coverage
    // 0.67-0.97 for 2-13 runs (docs/METHOD-NOTES.md, "Pooling runs").
    b.coverage_factor =
        model->random_effects ? analysis::t_one_sigma(static_cast<double>(dof)) : 1.0;
    b.between_run_dps = std::isfinite(model->between_run_var_dps2)
                            ? std::sqrt(model->between_run_var_dps2)
                            : std::numeric_limits<double>::quiet_NaN();
    const std::string rough =
        dof == 1 ? "; 1 degree of freedom: this std is itself uncertain by about 70 %" : "";
    b.run_to_run_source =
        model->degree() == 0
            ? fmt::format("measured: std of the {} runs' dN{}", runs.size(), rough)
            : fmt::format(
                  "measured: std of the {} runs' dN about the dN(T) line ({} degree{} of "
                  "freedom){}",
                  runs.size(), dof, dof == 1 ? "" : "s", rough);
    if (b.run_to_run_floored)
      b.run_to_run_source = fmt::format(
          "not resolved: the {} runs' dN scatter by {} °/s, less than their own noise {} °/s, so "
          "they cannot tell how far dN moves between power-ups; taken as {} °/s, {}",
          runs.size(), fixed_significant(b.runs_std_dps, 2), fixed_significant(b.single_run_dps, 2),
          fixed_significant(b.run_to_run_dps, 2),
          b.run_to_run_dps > b.single_run_dps
              ? fmt::format("the sensor preset {}'s turn-on spread (an assumption)", preset_name)
              : std::string("their own noise (the median of their errors)"));
    b.model_dps = worst;
    const std::string t_words =
        b.coverage_factor > 1.0
            ? fmt::format(", × {:.3g} (Student's t, {} degree{} of freedom) for a 68.3 % interval",
                          b.coverage_factor, dof, dof == 1 ? "" : "s")
            : "";
    b.model_note =
        !model->random_effects
            ? (model->degree() == 0
                   ? "the weighted mean's error (each run weighted by 1/(its within-run "
                     "error)²), scaled by the runs' scatter"
                   : "the dN(T) line's error at the runs' temperatures (largest)")
            : fmt::format(
                  "{} (random effects: each run weighted by 1/(its within-run error² + the "
                  "between-run variance), DerSimonian–Laird; modified Knapp–Hartung error, never "
                  "below the runs' own{})",
                  model->degree() == 0 ? "the runs' mean"
                                       : "the dN(T) line at the runs' "
                                         "temperatures (largest)",
                  t_words);
    b.calibration_dps = worst;
    b.new_power_up_dps = std::hypot(b.calibration_dps, b.coverage_factor * b.run_to_run_dps);
    // A between-run variance that grows away from the middle (tau^2(T)): a new power-up's error
    // is the band the ΔN(T) figure draws, largest at the runs' temperatures (third review of
    // issue 31, M2), not the constant repeatability's.
    if (std::isfinite(model->tau2_centre_dps2) && !model->fitted_runs.empty()) b.band_model = model;
    double band = 0.0, band_at_c = std::numeric_limits<double>::quiet_NaN();
    for (const auto& r : runs)
      if (const double w = new_power_up_at(b, r.cal.temp_c); w > band) {
        band = w;
        band_at_c = r.cal.temp_c;
      }
    if (std::isfinite(band_at_c) && band != b.new_power_up_dps) {
      b.new_power_up_dps = band;
      b.new_power_up_from_band = true;
      b.run_to_run_source += fmt::format(
          "; it grows away from {:.1f} °C (a between-run variance that changes with temperature, "
          "τ²(T)): a new power-up's ΔN is within ±{} °/s at {:.1f} °C, the band of the ΔN(T) "
          "figure",
          model->t_ref_c, fixed_significant(band, 2), band_at_c);
    }
    return b;
  } else {
    if (preset != nullptr) {
      b.run_to_run_dps = turn_on_spread_dps(*preset, b.temp_c);
      b.run_to_run_source = fmt::format(
          "not measured ({}): the turn-on spread of the sensor preset {} (an assumption fitted "
          "to the paper, not this sensor)",
          runs.size() == 1 ? "one run" : "the dN(T) fit has no degrees of freedom", preset_name);
    } else {
      b.run_to_run_dps = std::numeric_limits<double>::quiet_NaN();
      b.run_to_run_source =
          fmt::format("unknown: {} and no sensor preset to take it from",
                      runs.size() == 1 ? "one run" : "the dN(T) fit has no degrees of freedom");
    }
    if (model) {
      b.model_note = fmt::format(
          "not determined: the dN(T) line of degree {} passes through its {} runs exactly (0 "
          "degrees of freedom), so its own error says nothing",
          model->degree(), runs.size());
      b.calibration_dps = std::isfinite(b.run_to_run_dps)
                              ? std::hypot(b.within_run_dps, b.run_to_run_dps)
                              : std::numeric_limits<double>::quiet_NaN();
    } else {
      b.model_note = "none: one run";
      b.calibration_dps = b.within_run_dps;
      // The one run's dN is its own power-up's (mu + delta_A), a new power-up's is mu + delta_B:
      // they differ by two draws of the spread, sqrt(e^2 + 2 sigma^2), the random-effects
      // prediction interval tau^2 (1 + 1/k) + e^2 at k = 1 (Higgins, Thompson & Spiegelhalter
      // 2009, sec. 5; fifth review of issue 31, F17: hypot(e, sigma) covered 0.55-0.62). The
      // 0-dof line above already holds one sigma in calibration_dps.
      b.new_power_up_dps = std::hypot(b.calibration_dps, std::numbers::sqrt2 * b.run_to_run_dps);
      b.run_to_run_two_draws = true;
      return b;
    }
  }
  b.new_power_up_dps = std::hypot(b.calibration_dps, b.run_to_run_dps);
  return b;
}

std::optional<std::string> runs_disagree_warning(
    const std::optional<method::delta_n_model>& runs_model) {
  if (!runs_model || !(runs_model->chi2_per_dof > max_runs_chi2_per_dof)) return std::nullopt;
  return fmt::format(
      "the runs' dN disagree by {:.0f} times their own errors (χ²/dof {:.3g}; the paper's own "
      "runs scatter 14–30 times theirs): they were not made under the same stationary "
      "conditions, and the pooled dN means little",
      std::sqrt(runs_model->chi2_per_dof), runs_model->chi2_per_dof);
}

std::optional<std::string> runs_too_alike_warning(
    const std::optional<method::delta_n_model>& runs_model) {
  if (!runs_model || runs_model->dof == 0 || !std::isfinite(runs_model->chi2_per_dof))
    return std::nullopt;
  const auto dof = static_cast<double>(runs_model->dof);
  const double p = analysis::chi2_cdf(runs_model->chi2_per_dof * dof, dof);
  if (!(p < min_runs_chi2_lower_tail)) return std::nullopt;
  return fmt::format(
      "the runs' dN agree far better than their own errors allow (χ²/dof {:.3g} over {} degrees "
      "of freedom: P(χ² ≤ this) = {:.2g}, below {:g}): the same data twice (a copy of a run, "
      "rounded or trimmed), not independent power-ups; the pooled dN's error is not to be trusted",
      runs_model->chi2_per_dof, runs_model->dof, p, min_runs_chi2_lower_tail);
}

bool same_line(const method::delta_n_model& applied, const method::delta_n_model& refit) {
  const auto equal = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)) + 1e-15;
  };
  return equal(applied.t_ref_c, refit.t_ref_c) &&
         applied.coeffs_dps.size() == refit.coeffs_dps.size() &&
         std::equal(applied.coeffs_dps.begin(), applied.coeffs_dps.end(), refit.coeffs_dps.begin(),
                    equal);
}

double new_power_up_at(const delta_n_budget& b, double temp_c) {
  if (!b.valid) return std::numeric_limits<double>::quiet_NaN();
  if (b.band_model && std::isfinite(temp_c))
    if (const double band = b.band_model->new_run_interval_at(temp_c); std::isfinite(band))
      return std::hypot(band, std::isfinite(b.temperature_dps) ? b.temperature_dps : 0.0);
  return b.new_power_up_dps;
}

double delta_n_tc_dps_per_c(const sensor::sensor_params& p) noexcept {
  return std::hypot(p.g_sens_tc_z_dps_per_g_c, p.g_sens_tc_turn_on_sigma_dps_per_g_c);  // x 1 g
}

void add_temperature_term(delta_n_budget& b, double outside_c, std::string_view span,
                          const sensor::sensor_params* preset, const std::string& preset_name) {
  b.outside_c = outside_c;
  const double tc = preset != nullptr ? delta_n_tc_dps_per_c(*preset) : 0.0;
  if (!(tc > 0.0)) {
    b.valid = false;
    b.temperature_dps = std::numeric_limits<double>::quiet_NaN();
    b.temperature_note = fmt::format(
        "not known: the run lies {:.1f} °C outside the calibration's {} and {} no temperature "
        "coefficient of ΔN; the uncertainty is not valid outside the calibration's temperatures",
        outside_c, span,
        preset != nullptr ? "the sensor preset " + preset_name + " states"
                          : "no sensor preset gives");
    b.new_power_up_dps = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  b.temperature_dps = tc * outside_c;
  // The preset's mean coefficient is not applied as a correction: it is the paper's unit's
  // (an assumption about this one), and its sign depends on how the sensor is mounted; it
  // enters the 1-sigma term as if it were a spread of its own size (review N5).
  b.temperature_note = fmt::format(
      "from the preset's temperature coefficient (assumed, 1 σ): the run lies {:.1f} °C outside "
      "the calibration's {}; {} °/s per °C (the g-term's coefficient {} and its spread {} from "
      "one power-up to the next, sensor preset {}, combined) × {:.1f} °C. The coefficient's "
      "mean alone would move ΔN by {} °/s over this distance (its sign set by the mounting): "
      "not applied as a correction, counted in the ±",
      outside_c, span, fixed_significant(tc, 3),
      fixed_significant(std::abs(preset->g_sens_tc_z_dps_per_g_c), 3),
      fixed_significant(preset->g_sens_tc_turn_on_sigma_dps_per_g_c, 3), preset_name, outside_c,
      fixed_significant(std::abs(preset->g_sens_tc_z_dps_per_g_c) * outside_c, 2));
  b.new_power_up_dps = std::hypot(b.new_power_up_dps, b.temperature_dps);
}

std::optional<method::g_term_spec> g_term_spec_of(const sensor::preset& p) {
  const auto& q = p.params;
  if (q.g_sens_spec_max_dps_per_g > 0.0)
    return method::g_term_spec{
        q.g_sens_spec_max_dps_per_g, 0.0,
        fmt::format("{}: maximum {} °/s/g; {}", p.name, q.g_sens_spec_max_dps_per_g,
                    p.source_of("g_sens_spec_max_dps_per_g"))};
  if (q.g_sens_spec_typ_dps_per_g > 0.0)
    return method::g_term_spec{
        0.0, q.g_sens_spec_typ_dps_per_g,
        fmt::format("{}: {:g} × typical {} °/s/g; {}", p.name, method::g_term_spec::typical_factor,
                    q.g_sens_spec_typ_dps_per_g, p.source_of("g_sens_spec_typ_dps_per_g"))};
  return std::nullopt;
}

std::optional<method::g_term_spec> g_sensitivity_spec(const std::string& preset_name) {
  const auto* p = sensor::find_builtin(preset_name);
  return p != nullptr ? g_term_spec_of(*p) : std::nullopt;
}

std::optional<scale_factor_spec> scale_factor_tolerance(const std::string& preset_name) {
  // The specifications' own numbers (FACTS §4.1, §4.2).
  if (preset_name == "adxrs150")
    return scale_factor_spec{
        0.10, "ADXRS150 datasheet's scale-factor tolerance ±10 % (FACTS §4.1, not verified)"};
  if (preset_name == "hz1-90-100a")
    return scale_factor_spec{
        0.02, "HZ1-90-100A specification's scale-factor tolerance ±2 % (paper Tab. 2, FACTS §4.2)"};
  return std::nullopt;
}

std::string value_pm(double v, double u) {
  if (!std::isfinite(v)) return "–";
  // No error to take the digits of: three significant digits, in the fixed notation of the
  // rest (issue 31: a slope of 0 degrees of freedom read "4.28589e-05" on the page).
  if (!(std::isfinite(u) && u > 0.0)) return fixed_significant(v, 3);
  const auto [vs, us] = digits_of_error(v, u);
  return vs + " ± " + us;
}

std::string value_pm_dph(double v_dps, double u_dps) {
  return value_pm(v_dps * 3600.0, u_dps * 3600.0) + " °/h";
}

std::string delta_n_meaning() {
  return "ΔN is the part of the flipped half-difference r = (y₀ − y₁₈₀)/2 that is not the "
         "input rate: the Earth's rate along the sensitive axis plus the g-sensitivity term, "
         "which reverse with the flip as a rate does (paper eqns 7–11). A rate measured by "
         "flipping is r − ΔN (eqn 12); an error in ΔN stays in every cycle of it.";
}

std::string when_to_recalibrate(const delta_n_budget& b, const std::string& temps) {
  std::string out;
  if (std::isfinite(b.run_to_run_dps) && std::isfinite(b.new_power_up_dps)) {
    out = fmt::format(
        "Recalibrate: ΔN moves by about {} °/s (1 σ, {}) from one power-up to the next, so a "
        "rate compensated with this calibration after a new power-up carries ±{} °/s (68.3 %; "
        "the calibrated value's own error is ±{} °/s). ",
        fixed_significant((b.run_to_run_two_draws ? std::numbers::sqrt2 : 1.0) * b.run_to_run_dps,
                          2),
        b.run_to_run_floored ? "not resolved by these runs, which scatter less than their own noise"
        : b.run_to_run_measured ? "measured on these runs"
                                : "the sensor preset's, not measured",
        fixed_significant(b.new_power_up_dps, 2), fixed_significant(b.calibration_dps, 2));
    if (b.run_to_run_dps > 2.0 * b.single_run_dps)
      out += fmt::format(
          "To do better, calibrate again after each power-up (one run like these gives ±{} °/s, "
          "the median of their own errors). ",
          fixed_significant(b.single_run_dps, 2));
  } else {
    out =
        "Recalibrate: how far ΔN moves from one power-up to the next is unknown (one run, no "
        "sensor preset): calibrate over several power-ups before relying on it. ";
  }
  if (!temps.empty())
    out += fmt::format(
        "Outside {} (by more than {:g} °C) calibrate again, or at several "
        "temperatures for ΔN(T).",
        temps, outside_calibration_c);
  return out;
}

}  // namespace gyroflip::workflow
