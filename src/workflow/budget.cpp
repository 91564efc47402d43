/// \file
/// \brief The uncertainty budget of dN (budget.hpp).
#include "gyroflip/workflow/budget.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

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
    b.within_run_dps = b.run_to_run_dps = b.calibration_dps = b.new_power_up_dps = unknown;
    b.temp_c = unknown;
    b.run_to_run_source = "unknown: the calibration lists no runs";
    b.model_note = "not known: the calibration lists no runs and states no error";
    b.valid = false;
    b.invalid_why = "not known: the calibration lists no runs and states no error";
    return b;
  }
  b.within_run_dps = io::pooled_correlated_stderr(runs);
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
      worst = std::max(worst, model->stderr_at(r.cal.temp_c));
    }
    b.run_to_run_dps = std::sqrt(ss / static_cast<double>(dof));
    b.run_to_run_measured = true;
    b.run_to_run_dof = dof;
    const std::string rough =
        dof == 1 ? "; 1 degree of freedom: this std is itself uncertain by about 70 %" : "";
    b.run_to_run_source =
        model->degree() == 0
            ? fmt::format("measured: std of the {} runs' dN{}", runs.size(), rough)
            : fmt::format(
                  "measured: std of the {} runs' dN about the dN(T) line ({} degree{} of "
                  "freedom){}",
                  runs.size(), dof, dof == 1 ? "" : "s", rough);
    b.model_dps = worst;
    b.model_note = model->degree() == 0
                       ? "the weighted mean's error (each run weighted by 1/(its within-run "
                         "error)²), scaled by the runs' scatter"
                       : "the dN(T) line's error at the runs' temperatures (largest)";
    b.calibration_dps = worst;
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
    }
  }
  b.new_power_up_dps = std::hypot(b.calibration_dps, b.run_to_run_dps);
  return b;
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
      outside_c, span, fmt::format("{:.3g}", tc),
      fmt::format("{:.3g}", std::abs(preset->g_sens_tc_z_dps_per_g_c)),
      fmt::format("{:.3g}", preset->g_sens_tc_turn_on_sigma_dps_per_g_c), preset_name, outside_c,
      fmt::format("{:.2g}", std::abs(preset->g_sens_tc_z_dps_per_g_c) * outside_c));
  b.new_power_up_dps = std::hypot(b.new_power_up_dps, b.temperature_dps);
}

std::optional<g_spec> g_sensitivity_spec(const std::string& preset_name) {
  // The specifications' own numbers (FACTS §4.1, §4.2).
  if (preset_name == "adxrs150")
    return g_spec{0.2, "ADXRS150 datasheet, 0.2 °/s/g typical (FACTS §4.1, not verified)"};
  if (preset_name == "hz1-90-100a")
    return g_spec{0.06, "HZ1-90-100A specification, < 0.06 °/s/g (paper Tab. 2, FACTS §4.2)"};
  return std::nullopt;
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

}  // namespace gyroflip::workflow
