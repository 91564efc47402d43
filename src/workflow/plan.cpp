/// \file
/// \brief The planner's workflow (workflow/plan.hpp; docs/PLANNER.md).
#include "gyroflip/workflow/plan.hpp"

#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/io/schema.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/rig/rig_config.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::workflow {

method::plan_noise plan_noise_of(const sensor::sensor_params& p) noexcept {
  return {p.quantisation_deg, p.arw_dps_rthz, p.bias_instability_dps, p.rrw_dps_per_rts};
}

method::plan_noise plan_noise_of(const analysis::noise_terms& t, std::vector<std::string>& notes) {
  const auto take = [&](const analysis::noise_term& term, const char* name) {
    if (term.resolved) return term.value;
    if (term.hi > 0.0)
      notes.push_back(
          fmt::format("{} is not resolved by the record (< {:.3g}): left out of the "
                      "plan; a longer record would show whether it matters",
                      name, term.hi));
    return 0.0;
  };
  return {take(t.quantization, "Q"), take(t.arw, "N"), take(t.bias_instability, "B"),
          take(t.rrw, "K")};
}

result<method::plan_noise> plan_noise_of_record(const analysis::phase_source& x,
                                                double dps_per_unit, double min_dwell_s,
                                                std::vector<std::string>& notes) {
  auto a = analysis::analyse_noise(x, 0.683, analysis::tau_range{min_dwell_s});
  if (!a) return a.err();
  auto t = a->terms;
  for (auto* term : {&t.quantization, &t.arw, &t.bias_instability, &t.rrw})
    term->value *= dps_per_unit, term->lo *= dps_per_unit, term->hi *= dps_per_unit;
  return plan_noise_of(t, notes);
}

std::optional<double> gap_avar_of(std::span<const double> samples, std::size_t m,
                                  std::size_t spacing) {
  if (m == 0 || spacing < m || samples.size() < spacing + m + 1) return std::nullopt;
  // Prefix sums about the mean, in long double: a dwell mean is a difference of two of them.
  const long double mean = std::accumulate(samples.begin(), samples.end(), 0.0L) /
                           static_cast<long double>(samples.size());
  std::vector<long double> prefix(samples.size() + 1, 0.0L);
  for (std::size_t i = 0; i < samples.size(); ++i)
    prefix[i + 1] = prefix[i] + (static_cast<long double>(samples[i]) - mean);
  const std::size_t starts = samples.size() - spacing - m + 1;
  if (starts < 2) return std::nullopt;
  long double sum = 0.0L;
  const auto dm = static_cast<long double>(m);
  for (std::size_t t = 0; t < starts; ++t) {
    const long double a = (prefix[t + m] - prefix[t]) / dm;
    const long double b = (prefix[t + spacing + m] - prefix[t + spacing]) / dm;
    sum += (b - a) * (b - a);
  }
  return static_cast<double>(sum / (2.0L * static_cast<long double>(starts)));
}

namespace {

// The flip plan (no positions, or two) or the indexed plan (three or more), and the heading's.
result<method::flip_plan> plan_of(const plan_request& r, std::vector<double>& positions,
                                  std::vector<double>& visits, std::string& order) {
  positions = r.positions_deg;
  order = r.order;
  if (order != "auto" && order != "sweep" && order != "cycle" && order != "there-and-back")
    return parameter_error("order", fmt::format("the visiting order is auto, sweep, cycle or "
                                                "there-and-back; got '{}'",
                                                printable(order, 40)));
  if (r.heading_lat_deg) {
    if (auto s = earth::check_latitude(*r.heading_lat_deg); !s) return s.err();
    if (std::abs(*r.heading_lat_deg) > 85.0)
      return usage_error(fmt::format(
          "at {:g} deg latitude the horizontal Earth rate is {:.2g} of its whole: north cannot "
          "be found by it",
          *r.heading_lat_deg, std::cos(*r.heading_lat_deg * units::rad_per_deg)));
    if (positions.empty()) positions = {0.0, 90.0, 180.0, 270.0};
    if (positions.size() < 3)
      return usage_error(
          "a heading plan needs at least three positions: 0/180 gives only the projection of "
          "the Earth rate on the axis (its heading up to +-psi, with the scale factor known)");
  }
  for (const double a : positions)
    if (!(std::isfinite(a) && a >= 0.0 && a < 360.0))
      return usage_error(fmt::format("a position must be an angle in [0, 360) deg; got {:g}", a));
  if (positions.size() == 1 || positions.size() > 8)
    return usage_error(fmt::format("a table has 2 to 8 positions; got {}", positions.size()));
  if (positions.size() < 3) {
    if (order != "auto" && order != "cycle")
      return parameter_error(
          "order", fmt::format("two positions are planned as the paper's A, B cycle (auto or "
                               "cycle); '{}' is for three or more",
                               order));
    positions.clear();
    order.clear();
    return method::plan_flip(r.noise, r.dead_s, r.duration_s, r.limits);
  }
  if (order == "auto") order = "sweep";
  if (order == "sweep") {
    visits = method::sweep_visits(positions);
  } else {
    auto v = rig::device_visits(
        positions, order == "cycle" ? rig::device_order::cycle : rig::device_order::there_and_back,
        false);
    if (!v) return v.err();
    visits = std::move(*v);
  }
  auto p = method::plan_indexed(r.noise, visits, r.dead_s, r.duration_s, r.limits);
  if (!p)
    return usage_error(fmt::format("the visiting order {} ({}): {}", order, fmt::join(visits, ", "),
                                   p.err().message));
  return p;
}

}  // namespace

result<plan_result> plan(const plan_request& r) {
  std::vector<double> positions, visits;
  std::string order;
  auto p = plan_of(r, positions, visits, order);
  if (!p) return p.err();
  plan_result out;
  out.positions_deg = std::move(positions);
  out.visits_deg = std::move(visits);
  out.order = std::move(order);
  out.plan = std::move(*p);
  out.noise = r.noise;
  out.noise_source = r.noise_source;
  out.notes = r.notes;
  out.reference_dwell_s = r.reference_dwell_s;
  if (r.reference_dwell_s > 0.0 && out.visits_deg.empty())
    out.reference_sigma_dps = std::sqrt(
        method::flip_mean_variance(r.noise, r.reference_dwell_s, r.dead_s,
                                   method::pairs_in(r.duration_s, r.reference_dwell_s, r.dead_s)));
  if (r.reference_dwell_s > 0.0 && !out.visits_deg.empty()) {
    if (auto q = method::indexed_period_of(out.visits_deg, r.reference_dwell_s, r.dead_s)) {
      const auto periods = static_cast<std::size_t>(std::floor(r.duration_s / q->period_s));
      out.reference_sigma_dps =
          std::sqrt(method::indexed_run_variance(r.noise, *q, periods).mean_var());
    }
  }
  if (r.heading_lat_deg) {
    heading_plan h;
    h.lat_deg = *r.heading_lat_deg;
    h.earth_horizontal_dps = earth::earth_rate_wgs84_dps * std::cos(h.lat_deg * units::rad_per_deg);
    const auto deg = [&](double sigma_dps) {
      return sigma_dps / h.earth_horizontal_dps / units::rad_per_deg;
    };
    h.sigma_deg = deg(out.plan.sigma_dps);
    h.sigma_deg_rth = h.sigma_deg * std::sqrt(r.duration_s / 3600.0);
    h.white_limit_deg =
        method::heading_white_limit_deg(r.noise.arw_dps_rthz, h.lat_deg, r.duration_s);
    for (const auto& q : out.plan.by_dwell) h.by_dwell_deg.push_back({q.x, deg(q.sigma_dps)});
    for (const auto& q : out.plan.by_duration) h.by_duration_deg.push_back({q.x, deg(q.sigma_dps)});
    out.heading = std::move(h);
  }
  if (r.conversion_s > 0.0)
    out.conversions_per_dwell =
        static_cast<std::size_t>(std::max(1.0, std::round(out.plan.dwell_s / r.conversion_s)));
  if (!r.static_samples.empty() && r.static_tau0_s > 0.0) {
    const auto m =
        static_cast<std::size_t>(std::max(1.0, std::round(out.plan.dwell_s / r.static_tau0_s)));
    const auto s = m + static_cast<std::size_t>(std::round(r.dead_s / r.static_tau0_s));
    if (const auto v = gap_avar_of(r.static_samples, m, s)) {
      const double tau = static_cast<double>(m) * r.static_tau0_s;
      const double model = method::gap_avar(r.noise, tau, static_cast<double>(s) * r.static_tau0_s);
      out.record_over_model = *v * r.static_dps_per_unit * r.static_dps_per_unit / model;
      if (std::abs(std::sqrt(*out.record_over_model) - 1.0) > 0.2)
        out.notes.push_back(fmt::format(
            "the record's own two-sample deviation at the planned dwell and gap is {:.2f} times "
            "the fitted model's: the record is not the five-term model there; try the plan on the "
            "rig before a long run",
            std::sqrt(*out.record_over_model)));
    } else {
      out.notes.push_back(
          "the record is too short to check the plan's dwell against its own "
          "two-sample variance");
    }
  }
  out.notes.push_back(
      "assumes the noise does not depend on the table's position and a warm "
      "sensor (a cold start's warm-up is a drift, not a noise)");
  if (!out.visits_deg.empty())
    out.notes.push_back(
        "an indexed run: the dead time is per turn (whatever its angle) and none between two "
        "dwells at the same angle; the error is of the first harmonic (c1, s1) that the "
        "per-period least squares with a bias and its slope gives (method/harmonic.hpp)");
  if (r.noise.bias_instability_dps == 0.0)
    out.notes.push_back("no flicker term: without it the shortest dwell is always best");
  return out;
}

namespace {

nlohmann::json curve_json(const std::vector<method::plan_point>& c, const char* x,
                          const char* y = "sigma_dps") {
  auto a = nlohmann::json::array();
  for (const auto& p : c) a.push_back({{x, p.x}, {y, p.sigma_dps}});
  return a;
}

}  // namespace

nlohmann::json plan_json(const plan_result& r) {
  const auto& p = r.plan;
  auto j = io::schema_object("plan", 1);
  j["noise_source"] = r.noise_source;
  j["noise"] = {{"quantization_deg", r.noise.quantization_deg},
                {"arw_dps_rthz", r.noise.arw_dps_rthz},
                {"bias_instability_dps", r.noise.bias_instability_dps},
                {"rrw_dps_per_rts", r.noise.rrw_dps_per_rts}};
  j["dead_time_s"] = p.dead_s;
  j["duration_s"] = p.duration_s;
  j["dwell_s"] = p.dwell_s;
  j["period_s"] = p.period_s;
  j["predicted_sigma_dps"] = p.sigma_dps;
  j["sigma_without_dead_time_dps"] = p.sigma_no_dead_dps;
  j["conversions_per_dwell"] = r.conversions_per_dwell;
  j["closed_form"] = {{"corner_tau_s", p.closed_form.corner_tau_s},
                      {"dwell_s", p.closed_form.dwell_s},
                      {"sigma_dps", p.closed_form.sigma_dps}};
  j["reference_dwell"] = {{"dwell_s", r.reference_dwell_s}, {"sigma_dps", r.reference_sigma_dps}};
  j["by_dwell"] = curve_json(p.by_dwell, "dwell_s");
  j["by_duration"] = curve_json(p.by_duration, "duration_s");
  if (r.record_over_model) j["record_over_model_avar"] = *r.record_over_model;
  if (!r.visits_deg.empty()) {
    j["positions_deg"] = r.positions_deg;
    j["visiting_order_deg"] = r.visits_deg;
    j["order"] = r.order;
  }
  if (r.heading) {
    const auto& h = *r.heading;
    j["heading"] = {{"latitude_deg", h.lat_deg},
                    {"earth_horizontal_dps", h.earth_horizontal_dps},
                    {"predicted_sigma_deg", h.sigma_deg},
                    {"sigma_deg_rth", h.sigma_deg_rth},
                    {"white_limit_deg", h.white_limit_deg},
                    {"by_dwell", curve_json(h.by_dwell_deg, "dwell_s", "sigma_deg")},
                    {"by_duration", curve_json(h.by_duration_deg, "duration_s", "sigma_deg")}};
  }
  j["notes"] = r.notes;
  return j;
}

sensor_implications implications_of(const sensor::sensor_params& p, double dead_s, double lat_deg) {
  sensor_implications s;
  s.dead_s = dead_s;
  s.lat_deg = lat_deg;
  const auto c = method::plan_flip_closed_form(plan_noise_of(p), dead_s, 3600.0);
  s.corner_tau_s = c.corner_tau_s;
  s.dwell_s = c.dwell_s;
  s.sigma_dps_rth = c.sigma_dps;
  s.heading_white_deg_rth = method::heading_white_limit_deg(p.arw_dps_rthz, lat_deg, 3600.0);
  s.heading_dead_time_deg_rth = method::heading_dead_time_limit_deg(
      p.arw_dps_rthz, p.bias_instability_dps, dead_s, lat_deg, 3600.0);
  return s;
}

report::figure plan_figure(const plan_result& r) {
  report::figure f;
  const bool heading = r.heading.has_value();
  const auto& curve = heading ? r.heading->by_dwell_deg : r.plan.by_dwell;
  const double to_y = heading ? r.heading->sigma_deg / r.plan.sigma_dps : 1.0;
  f.title = heading ? fmt::format("heading error against the dwell ({} s per turn, run {:g} s)",
                                  r.plan.dead_s, r.plan.duration_s)
                    : fmt::format(
                          "compensated rate's error against the dwell ({} s per turn, run "
                          "{:g} s)",
                          r.plan.dead_s, r.plan.duration_s);
  f.caption = r.noise_source;
  f.x = {"dwell (s)", true};
  f.y = {heading ? "predicted 1 sigma of the heading (deg)" : "predicted 1 sigma (deg/s)", true};
  report::series s;
  s.title =
      r.visits_deg.empty() ? "0/180 flip" : fmt::format("{} positions", r.positions_deg.size());
  s.how = report::series::style::lines;
  for (const auto& q : curve) s.x.push_back(q.x), s.y.push_back(q.sigma_dps);
  f.data.push_back(std::move(s));
  f.notes.push_back({r.plan.dwell_s, r.plan.sigma_dps * to_y,
                     fmt::format("planned {:.3g} s", r.plan.dwell_s), false, 1});
  if (r.reference_sigma_dps > 0.0)
    f.notes.push_back({r.reference_dwell_s, r.reference_sigma_dps * to_y,
                       fmt::format("paper's {:g} s", r.reference_dwell_s), true, 2});
  return f;
}

nlohmann::json sensors_json(double dead_s, double lat_deg) {
  const auto bound = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  nlohmann::json list = nlohmann::json::array();
  for (const auto& p : sensor::builtin_presets()) {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& f : sensor::fields()) {
      params[std::string(f.key)] = {{"value", p.params.*f.member},
                                    {"unit", f.unit},
                                    {"what", f.what},
                                    {"source", p.source_of(f.key)},
                                    {"min", bound(f.min_value)},
                                    {"max", bound(f.max_value)}};
    }
    const auto im = implications_of(p.params, dead_s, lat_deg);
    const nlohmann::json implied = {
        {"dead_time_s", im.dead_s},
        {"latitude_deg", im.lat_deg},
        {"corner_tau_s", im.corner_tau_s},
        {"dwell_s", im.dwell_s},
        {"flip_sigma_dps_rth", im.sigma_dps_rth},
        {"heading_white_limit_deg_rth", im.heading_white_deg_rth},
        {"heading_dead_time_limit_deg_rth", im.heading_dead_time_deg_rth}};
    list.push_back({{"name", p.name},
                    {"description", p.description},
                    {"params", params},
                    {"implied", implied}});
  }
  auto out = io::schema_object("sensors", 1);
  out["sensors"] = std::move(list);
  return out;
}

}  // namespace gyroflip::workflow
