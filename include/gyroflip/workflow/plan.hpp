/// \file
/// \brief The flip-period planner as `gyroflip plan` and `gyroflip.plan` run it: the noise terms
/// from a sensor preset or a static record's fit, the plan (method/plan.hpp), the dwell as the
/// rig's conversions per dwell, and for a static record its own gap two-sample variance at the
/// plan beside the model's. docs/PLANNER.md.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/plan.hpp"
#include "gyroflip/report/figure.hpp"
#include "gyroflip/sensor/params.hpp"

namespace gyroflip::workflow {

/// The planner's noise from a preset's parameters (its IEEE 952 coefficients as they are).
[[nodiscard]] method::plan_noise plan_noise_of(const sensor::sensor_params& p) noexcept;

/// The planner's noise from fitted terms: resolved terms at their value, unresolved ones left out
/// (`notes` names each with its upper limit). An upper limit taken as a value would plan against
/// noise the record only failed to exclude: a short record's K limit alone can halve the dwell.
[[nodiscard]] method::plan_noise plan_noise_of(const analysis::noise_terms& t,
                                               std::vector<std::string>& notes);

/// The planner's noise from a static record: the IEEE 952 fit of its OADEV (analyse_noise) over
/// the taus from `min_dwell_s` on (the dwells a plan considers; below, an anti-alias filter
/// shapes the curve), in deg/s with `dps_per_unit` per unit of the samples, then as above.
/// Errors: those of analyse_noise (too short a record).
[[nodiscard]] result<method::plan_noise> plan_noise_of_record(const analysis::phase_source& x,
                                                              double dps_per_unit,
                                                              double min_dwell_s,
                                                              std::vector<std::string>& notes);

/// The two-sample variance of dwell means of m samples whose starts are `spacing` samples apart
/// (spacing >= m), estimated from `samples` (rate, every start overlapping; SP1065's overlapping
/// estimator with a gap): what a flip run with that dwell and dead time would see of the bias.
/// Empty when the record holds fewer than 2 such pairs.
[[nodiscard]] std::optional<double> gap_avar_of(std::span<const double> samples, std::size_t m,
                                                std::size_t spacing);

struct plan_request {
  method::plan_noise noise;
  std::string noise_source;  ///< where the terms come from ("preset adxrs150", "fit of FILE")
  /// What the noise source noted (plan_noise_of_record's unresolved terms): first in the result's.
  std::vector<std::string> notes;
  double dead_s = 0.0;  ///< turn + settle per turn (s)
  double duration_s = 3600.0;
  method::plan_limits limits;
  /// The rig's conversion time (s) for the dwell as a whole count of conversions; 0: not asked.
  double conversion_s = 0.0;
  /// A static record's rate samples and their spacing: its own gap variance at the plan.
  std::span<const double> static_samples;
  double static_tau0_s = 0.0;
  double static_dps_per_unit = 1.0;  ///< deg/s per unit of the static samples
  /// A dwell to compare with (s; 0: none): the paper's 256 conversions, 0.512 s, by default.
  double reference_dwell_s = 0.512;
  /// The table's positions (deg; empty: the paper's 0/180 flip). Two: the flip plan (the paper's
  /// A, B cycle). Three or more: an indexed run visiting them in the drift-cancelling sweep
  /// (method::sweep_visits), planned for the first harmonic's error (method::plan_indexed).
  std::vector<double> positions_deg;
  /// The visiting order planned for, as `simulate --order` and `record --order` visit the
  /// positions (issue 33): "auto" (two positions: the paper's A, B cycle; more: the sweep),
  /// "sweep" (method::sweep_visits), "cycle" (the table's order, as the device runs an angle
  /// table) or "there-and-back" (0, 1, ..., N-1, ..., 1: rig::device_visits, record's default
  /// for three to five positions). With two positions only "auto" and "cycle" (both A, B).
  std::string order = "auto";
  /// Plan for north finding at this latitude (deg): the dwell that minimises the heading's
  /// error (the first harmonic's over the horizontal Earth rate); positions default to 0, 90,
  /// 180, 270. Unset: plan for the compensated rate.
  std::optional<double> heading_lat_deg;
};

/// What a heading plan adds: the heading's predicted 1 sigma at the planned dwell.
struct heading_plan {
  double lat_deg = 0.0;
  double earth_horizontal_dps = 0.0;  ///< W_E cos(lat)
  double sigma_deg = 0.0;             ///< predicted 1 sigma of the heading for the run
  double sigma_deg_rth = 0.0;         ///< the same for one hour: sigma x sqrt(T / 1 h)
  /// The white-noise limit sqrt(2) N / (W_H sqrt(T)) for the run (no dead time, no flicker).
  double white_limit_deg = 0.0;
  std::vector<method::plan_point> by_dwell_deg;     ///< sigma (deg) against the dwell
  std::vector<method::plan_point> by_duration_deg;  ///< sigma (deg) against the run length
};

struct plan_result {
  method::flip_plan plan;
  method::plan_noise noise;
  std::string noise_source;
  std::size_t conversions_per_dwell = 0;  ///< round(dwell / conversion time); 0: not asked
  /// The record's gap two-sample variance at (dwell, dwell + dead) over the model's (static
  /// record only, when it is long enough).
  std::optional<double> record_over_model;
  /// The predicted error at plan_request::reference_dwell_s (deg/s; 0 when none was given).
  double reference_dwell_s = 0.0;
  double reference_sigma_dps = 0.0;
  std::vector<std::string> notes;  ///< assumptions and cautions, for the reader
  /// Three or more positions: the angles (deg) and one visiting period's order.
  std::vector<double> positions_deg, visits_deg;
  std::string order;  ///< the visiting order's name (plan_request::order; "auto" resolved)
  std::optional<heading_plan> heading;
};

/// Plans the dwell (method::plan_flip) and adds what the rig and the record say. Errors: those of
/// plan_flip.
[[nodiscard]] result<plan_result> plan(const plan_request& r);

/// The plan as `gyroflip plan --json` prints it and `gyroflip.plan` returns it (schema
/// gyroflip.plan/1): dwell_s, period_s, predicted_sigma_dps, the closed form, the paper's dwell,
/// the curves by_dwell and by_duration, notes.
[[nodiscard]] nlohmann::json plan_json(const plan_result& r);

/// What a sensor's noise terms imply for flipping and north finding (`gyroflip sensors`), from
/// the closed forms (docs/PLANNER.md, docs/NORTH.md): the corner time tau_c = N^2/(0.4413 B^2),
/// the best dwell sqrt(d tau_c) for a dead time d per turn, and the heading's limits at a
/// latitude per sqrt(hour) of run: white sqrt(2) N / W_H, with the dead time
/// sqrt(2) (N + 0.664 B sqrt(d)) / W_H (k = sqrt 2: one gyro, unknown bias, >= 3 positions).
struct sensor_implications {
  double dead_s = 0.0, lat_deg = 0.0;  ///< what they were computed for
  double corner_tau_s = 0.0;           ///< tau_c (s); 0 without a flicker term
  double dwell_s = 0.0;                ///< tau* = sqrt(d tau_c) (s); 0 without a flicker term
  double sigma_dps_rth = 0.0;  ///< the flip run's error (N + 0.664 B sqrt d) x sqrt(1 h / T)
  double heading_white_deg_rth = 0.0;      ///< deg x sqrt(h / T)
  double heading_dead_time_deg_rth = 0.0;  ///< deg x sqrt(h / T)
};
[[nodiscard]] sensor_implications implications_of(const sensor::sensor_params& p, double dead_s,
                                                  double lat_deg);

/// The object `gyroflip sensors --json` prints (schema gyroflip.sensors/1) and Python's
/// `gyroflip.sensors` returns: every built-in preset with each parameter (value, unit, what,
/// source, allowed range; an unbounded side null) and what it implies for `dead_s` per turn at
/// `lat_deg` (implications_of).
[[nodiscard]] nlohmann::json sensors_json(double dead_s, double lat_deg);

/// The figure of the plan: the predicted error against the dwell (log-log; the heading's in deg
/// for a heading plan), the planned dwell and the paper's dwell marked.
[[nodiscard]] report::figure plan_figure(const plan_result& r);

}  // namespace gyroflip::workflow
