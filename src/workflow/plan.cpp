/// \file
/// \brief The planner's workflow (workflow/plan.hpp; docs/PLANNER.md).
#include "gyroflip/workflow/plan.hpp"

#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/io/schema.hpp"

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

result<plan_result> plan(const plan_request& r) {
  auto p = method::plan_flip(r.noise, r.dead_s, r.duration_s, r.limits);
  if (!p) return p.err();
  plan_result out;
  out.plan = std::move(*p);
  out.noise = r.noise;
  out.noise_source = r.noise_source;
  out.notes = r.notes;
  out.reference_dwell_s = r.reference_dwell_s;
  if (r.reference_dwell_s > 0.0)
    out.reference_sigma_dps = std::sqrt(
        method::flip_mean_variance(r.noise, r.reference_dwell_s, r.dead_s,
                                   method::pairs_in(r.duration_s, r.reference_dwell_s, r.dead_s)));
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
  if (r.noise.bias_instability_dps == 0.0)
    out.notes.push_back("no flicker term: without it the shortest dwell is always best");
  return out;
}

namespace {

nlohmann::json curve_json(const std::vector<method::plan_point>& c, const char* x) {
  auto a = nlohmann::json::array();
  for (const auto& p : c) a.push_back({{x, p.x}, {"sigma_dps", p.sigma_dps}});
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
  j["notes"] = r.notes;
  return j;
}

}  // namespace gyroflip::workflow
