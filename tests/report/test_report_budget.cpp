// The dN uncertainty budget of the report (workflow/budget.hpp, issue 22): each component
// against its closed form on made-up runs whose numbers are known.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/core/digits.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/runs.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/budget.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip {
namespace {

io::calibration_entry run(double dn_dps, double err_dps, double temp_c) {
  io::calibration_entry e;
  e.file = "r.csv";
  e.cal.delta_n_dps = dn_dps;
  e.cal.stderr_correlated_dps = err_dps;
  e.cal.temp_c = temp_c;
  e.cal.cycles = 1000;
  return e;
}

// The one "v ± u" of the report, the budget and the calibrate text (the report's own copy, which
// printed "nan ± u", is gone; review of issue 31): u to two significant digits and v to the same
// decimals; without a usable u, v to 3 significant digits in fixed notation (issue 31: a slope
// of 0 degrees of freedom read "4.28589e-05"); a non-finite v is "–" whatever u is (a report
// never prints nan).
TEST(ValuePm, DigitsOfTheErrorAndNeverNan) {
  const double nan = std::nan("");
  EXPECT_EQ(workflow::value_pm(0.00326975, 0.000812), "0.00327 ± 0.00081");
  EXPECT_EQ(workflow::value_pm(0.500099, 1.2e-5), "0.500099 ± 0.000012");
  EXPECT_EQ(workflow::value_pm(123.456, 35.0), "123 ± 35");
  EXPECT_EQ(workflow::value_pm(0.00326975, 0.0), "0.00327");
  EXPECT_EQ(workflow::value_pm(0.00326975, nan), "0.00327");
  EXPECT_EQ(workflow::value_pm(-4.28589e-5, 0.0), "-0.0000429");
  EXPECT_EQ(workflow::value_pm(nan, 0.1), "–");
  EXPECT_EQ(workflow::value_pm(std::numeric_limits<double>::infinity(), 0.1), "–");
  EXPECT_EQ(workflow::value_pm(nan, nan), "–");
  EXPECT_EQ(workflow::value_pm_dph(1e-3, 2.5e-4), "3.60 ± 0.90 °/h");
  // Review of issue 31 (L2): an error of 100 or more was printed whole, with the value beside it
  // to the unit ("-1507 ± 3613 ppm"); both are rounded at the error's second digit.
  EXPECT_EQ(workflow::value_pm(-1507.0, 3613.0), "-1500 ± 3600");
  EXPECT_EQ(workflow::value_pm(123456.0, 355.0), "123460 ± 360");
  EXPECT_EQ(workflow::value_pm(-40.0, 3613.0), "0 ± 3600");
  EXPECT_EQ(workflow::value_pm(99.4, 99.96), "99 ± 100");
}

// `{:.2g}` dropped significant trailing zeros ("0.0002" for 0.00020; review of issue 31, L2).
TEST(ValuePm, TwoSignificantDigitsKeepTheirTrailingZeros) {
  EXPECT_EQ(significant(0.00020, 2), "0.00020");
  EXPECT_EQ(significant(0.000204, 2), "0.00020");
  EXPECT_EQ(significant(1.0, 2), "1.0");
  EXPECT_EQ(significant(12.0, 2), "12");
  EXPECT_EQ(significant(0.0012345, 2), "0.0012");
  EXPECT_EQ(significant(9.96, 2), "10");
  EXPECT_EQ(significant(0.000996, 2), "0.0010");
  EXPECT_EQ(significant(-0.00020, 2), "-0.00020");
}

TEST(DeltaNBudget, RunsAtOneTemperatureGiveTheirMeasuredScatter) {
  // Equal errors: the weighted mean is the plain mean, the scatter the sample std (0.01).
  const std::vector runs{run(0.40, 1e-4, 20.0), run(0.41, 1e-4, 20.0), run(0.42, 1e-4, 20.0)};
  const auto model = method::fit_runs_model(workflow::calibrations_of(runs));
  ASSERT_TRUE(model && model->has_value());
  const auto* hz1 = sensor::find_builtin("hz1-90-100a");
  ASSERT_NE(hz1, nullptr);
  const auto b = workflow::budget_of(runs, *model, &hz1->params, "hz1-90-100a");
  EXPECT_TRUE(b.run_to_run_measured);
  EXPECT_NEAR(b.run_to_run_dps, 0.01, 1e-9);
  // Random effects with equal errors: the plain mean, its error std / sqrt(n) (Knapp-Hartung),
  // and both intervals 68.3 %: Student's t for 2 degrees of freedom, 1.3213 (issue 31).
  ASSERT_TRUE(b.model_dps.has_value());
  const double t2 = 1.3212773729262555;  // (2p - 1)/sqrt(2p(1 - p)), p = Phi(1)
  EXPECT_NEAR(b.coverage_factor, t2, 1e-9);
  EXPECT_NEAR(*b.model_dps, t2 * 0.01 / std::sqrt(3.0), 1e-9);
  EXPECT_NEAR(b.calibration_dps, *b.model_dps, 1e-12);
  EXPECT_NEAR(b.new_power_up_dps, t2 * std::hypot(0.01 / std::sqrt(3.0), 0.01), 1e-9);
  // The between-run std beyond the runs' own noise: sqrt(0.01^2 - 1e-4^2).
  EXPECT_NEAR(b.between_run_dps, std::sqrt(1e-4 - 1e-8), 1e-12);
  EXPECT_NEAR(b.within_run_dps, method::pooled_correlated_stderr(workflow::calibrations_of(runs)),
              1e-15);
}

// Third review of issue 31, M2: runs whose scatter grows away from the middle (tau^2(T)
// estimated) had a "new power-up" error from the constant repeatability (±0.0029) while the ΔN(T)
// figure drew the band delta_n_model::new_run_interval_at (±0.0056 at 4 °C). The budget's number is
// now that band, the largest at the runs' temperatures, and new_power_up_at gives it at a run's.
TEST(DeltaNBudget, ANewPowerUpTakesTheBetweenRunVarianceAtItsTemperature) {
  const std::vector runs{run(3.8e-3, 2e-5, 4.0), run(3.3e-3, 2e-5, 12.0), run(3.1e-3, 2e-5, 20.0),
                         run(2.2e-3, 2e-5, 28.0), run(2.9e-3, 2e-5, 36.0)};
  const auto model = method::fit_runs_model(workflow::calibrations_of(runs));
  ASSERT_TRUE(model && model->has_value());
  const auto& m = **model;
  ASSERT_TRUE(std::isfinite(m.tau2_centre_dps2));  // the band changes with temperature
  const auto b = workflow::budget_of(runs, *model, nullptr, "");
  double widest = 0.0;
  for (const auto& r : runs) {
    const double band = m.new_run_interval_at(r.cal.temp_c);
    EXPECT_NEAR(workflow::new_power_up_at(b, r.cal.temp_c), band, 1e-15);
    widest = std::max(widest, band);
  }
  EXPECT_NEAR(b.new_power_up_dps, widest, 1e-15);
  EXPECT_TRUE(b.new_power_up_from_band);
  EXPECT_GT(m.new_run_interval_at(4.0), m.new_run_interval_at(20.0));
  EXPECT_NE(b.run_to_run_source.find("τ²(T)"), std::string::npos) << b.run_to_run_source;
  // Without such a model (a budget that holds no tau^2(T) fit), the budget's constant number.
  auto constant = b;
  constant.band_model.reset();
  EXPECT_EQ(workflow::new_power_up_at(constant, 4.0), b.new_power_up_dps);
}

// Review of issue 31 (M3): "a run like these gives ±X" printed the k runs' pooled error, sqrt(k)
// below what one run gives; it is the median of the runs' own errors.
TEST(DeltaNBudget, WhatOneRunLikeTheseGivesIsTheMedianOfTheirOwnErrors) {
  const std::vector runs{run(0.40, 1e-4, 20.0), run(0.41, 2.5e-4, 20.0), run(0.42, 4e-4, 20.0)};
  const auto model = method::fit_runs_model(workflow::calibrations_of(runs));
  ASSERT_TRUE(model && model->has_value());
  const auto* hz1 = sensor::find_builtin("hz1-90-100a");
  ASSERT_NE(hz1, nullptr);
  const auto b = workflow::budget_of(runs, *model, &hz1->params, "hz1-90-100a");
  const auto text = workflow::when_to_recalibrate(b, "20.0 °C");
  EXPECT_NE(text.find("one run like these gives ±0.00025 °/s"), std::string::npos) << text;
  EXPECT_GT(std::abs(b.within_run_dps - 2.5e-4), 2e-5);  // the pooled error is another number
  // Its trailing zero is significant (L2): 2.0e-4 was printed "0.0002".
  const std::vector two_e4{run(0.40, 1e-4, 20.0), run(0.41, 2.0e-4, 20.0), run(0.42, 4e-4, 20.0)};
  const auto m2 = method::fit_runs_model(workflow::calibrations_of(two_e4));
  ASSERT_TRUE(m2 && m2->has_value());
  const auto text2 = workflow::when_to_recalibrate(
      workflow::budget_of(two_e4, *m2, &hz1->params, "hz1-90-100a"), "20.0 °C");
  EXPECT_NE(text2.find("one run like these gives ±0.00020 °/s"), std::string::npos) << text2;
}

TEST(DeltaNBudget, OneRunTakesThePresetsTurnOnSpreadAndSaysSo) {
  const std::vector runs{run(0.40, 2e-4, 4.0)};
  const auto* hz1 = sensor::find_builtin("hz1-90-100a");
  ASSERT_NE(hz1, nullptr);
  const auto& p = hz1->params;
  const auto b = workflow::budget_of(runs, std::nullopt, &p, "hz1-90-100a");
  EXPECT_FALSE(b.run_to_run_measured);
  const double spread = std::hypot(p.g_sens_turn_on_sigma_dps_per_g,
                                   p.g_sens_tc_turn_on_sigma_dps_per_g_c * (4.0 - p.temp_ref_c));
  EXPECT_GT(spread, 0.0);
  EXPECT_NEAR(b.run_to_run_dps, spread, 1e-15);
  EXPECT_NE(b.run_to_run_source.find("not measured"), std::string::npos);
  EXPECT_NEAR(b.calibration_dps, 2e-4, 1e-15);
  // The calibrated run's power-up and a new one are two draws of the spread: a new power-up's
  // dN is sqrt(e^2 + 2 sigma^2) from the calibrated value (fifth review of issue 31, F17:
  // hypot(e, sigma) covered 0.55-0.62 of new power-ups), and dN moves by sqrt(2) sigma.
  EXPECT_NEAR(b.new_power_up_dps, std::sqrt(4e-8 + 2.0 * spread * spread), 1e-15);
  const auto text = workflow::when_to_recalibrate(b, "");
  EXPECT_NE(text.find("moves by about " + significant(std::sqrt(2.0) * spread, 2) + " °/s"),
            std::string::npos)
      << text;
  // Without a preset the repeatability is unknown, not zero.
  const auto none = workflow::budget_of(runs, std::nullopt, nullptr, "");
  EXPECT_TRUE(std::isnan(none.run_to_run_dps));
  EXPECT_TRUE(std::isnan(none.new_power_up_dps));
}

TEST(DeltaNBudget, ALineThroughTwoRunsIsFlaggedNotShownAsExact) {
  const std::vector runs{run(0.40, 1e-4, 4.0), run(0.42, 1e-4, 20.0)};
  const auto model = method::fit_runs_model(workflow::calibrations_of(runs));
  ASSERT_TRUE(model && model->has_value() && (*model)->degree() == 1);
  const auto* hz1 = sensor::find_builtin("hz1-90-100a");
  const auto b = workflow::budget_of(runs, *model, &hz1->params, "hz1-90-100a");
  EXPECT_FALSE(b.model_dps.has_value());
  EXPECT_NE(b.model_note.find("0 degrees of freedom"), std::string::npos);
  EXPECT_FALSE(b.run_to_run_measured);
  // The calibrated value's error is not the line's own (which would be ~1e-4): the preset's
  // repeatability is in it.
  EXPECT_NEAR(b.calibration_dps, std::hypot(b.within_run_dps, b.run_to_run_dps), 1e-15);
  EXPECT_GT(b.calibration_dps, 1e-4 * 2);
}

// Review R3: a constant dN applied 16 degC from its runs' temperature. HZ1: the preset's g-term
// coefficient 4.5e-5 and its power-up spread 8.75e-5 deg/s/degC (paper Tab. 3) combined, times
// 16 degC, added in quadrature; ADXRS150 (no coefficient): not valid, no number.
TEST(DeltaNBudget, ATemperatureTermFromThePresetOrNotValid) {
  const std::vector runs{run(0.0030, 1e-4, 20.0), run(0.0031, 1e-4, 20.0)};
  const auto model = method::fit_runs_model(workflow::calibrations_of(runs));
  ASSERT_TRUE(model && model->has_value());
  const auto* hz1 = sensor::find_builtin("hz1-90-100a");
  auto b = workflow::budget_of(runs, *model, &hz1->params, "hz1-90-100a");
  const double before = b.new_power_up_dps;
  workflow::add_temperature_term(b, 16.0, "20.0 °C", &hz1->params, "hz1-90-100a");
  const double term = std::hypot(4.5e-5, 8.75e-5) * 16.0;
  EXPECT_TRUE(b.valid);
  EXPECT_NEAR(b.temperature_dps, term, 1e-12);
  EXPECT_NEAR(b.new_power_up_dps, std::hypot(before, term), 1e-12);
  EXPECT_NE(b.temperature_note.find("(assumed, 1 σ)"), std::string::npos);
  // The mean coefficient's own shift over the distance, stated (4.5e-5 x 16 = 0.00072 deg/s:
  // the paper's 4 - 20 degC difference, Tab. 3) but not applied.
  EXPECT_NE(b.temperature_note.find("move ΔN by 0.00072 °/s"), std::string::npos)
      << b.temperature_note;
  const auto* adx = sensor::find_builtin("adxrs150");
  auto a = workflow::budget_of(runs, *model, &adx->params, "adxrs150");
  workflow::add_temperature_term(a, 16.0, "20.0 °C", &adx->params, "adxrs150");
  EXPECT_FALSE(a.valid);
  EXPECT_TRUE(std::isnan(a.new_power_up_dps));
  EXPECT_NE(a.temperature_note.find("not valid outside"), std::string::npos);
}

// Review R5/R5b: "std of the 3 runs' dN" was the rms about the weighted mean (0.0013434 for the
// review's runs, whose plain std is 0.0012544); a repeatability of 1 degree of freedom is flagged.
TEST(DeltaNBudget, TheRunsStdIsTheirPlainStdAndOneDegreeOfFreedomIsFlagged) {
  const std::vector runs{run(0.0026233, 1.403e-4, 20.0), run(0.0036824, 1.170e-4, 20.0),
                         run(0.0011830, 8.059e-5, 20.0)};
  const auto model = method::fit_runs_model(workflow::calibrations_of(runs));
  ASSERT_TRUE(model && model->has_value());
  const auto* hz1 = sensor::find_builtin("hz1-90-100a");
  const auto b = workflow::budget_of(runs, *model, &hz1->params, "hz1-90-100a");
  const double mean = (0.0026233 + 0.0036824 + 0.0011830) / 3.0;
  const double sd = std::sqrt((std::pow(0.0026233 - mean, 2) + std::pow(0.0036824 - mean, 2) +
                               std::pow(0.0011830 - mean, 2)) /
                              2.0);
  EXPECT_NEAR(sd, 0.0012544, 2e-7);  // the review's 5-digit inputs
  EXPECT_NEAR(b.run_to_run_dps, sd, 1e-12);
  EXPECT_EQ(b.run_to_run_dof, 2u);
  EXPECT_EQ(b.run_to_run_source.find("70 %"), std::string::npos);
  // Two runs (the review's ADXRS150 pair): |difference| / sqrt(2), 1 degree of freedom, flagged.
  const std::vector two{run(0.41494, 2e-4, 20.0), run(0.39844, 1e-4, 20.0)};
  const auto m2 = method::fit_runs_model(workflow::calibrations_of(two));
  ASSERT_TRUE(m2 && m2->has_value());
  const auto* adx = sensor::find_builtin("adxrs150");
  const auto b2 = workflow::budget_of(two, *m2, &adx->params, "adxrs150");
  EXPECT_NEAR(b2.run_to_run_dps, (0.41494 - 0.39844) / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(b2.run_to_run_dof, 1u);
  EXPECT_NE(b2.run_to_run_source.find("1 degree of freedom"), std::string::npos);
}

}  // namespace
}  // namespace gyroflip
