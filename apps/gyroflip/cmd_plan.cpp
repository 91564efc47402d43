/// \file
/// \brief `gyroflip plan`: the dwell and flip period that minimise a run's error for a dead time
/// (workflow/plan.hpp, docs/PLANNER.md).
#include "cmd_plan.hpp"

#include <array>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "finite_output.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/report/figure.hpp"
#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/plan.hpp"

namespace gyroflip::app {
namespace {

std::string plan_text(const workflow::plan_result& r) {
  const auto& p = r.plan;
  std::string t;
  auto out = std::back_inserter(t);
  const auto dph = [](double v) { return v * units::dph_per_dps; };
  fmt::format_to(out,
                 "plan for {} (N {:.4g} deg/s/rtHz, B {:.4g} deg/s, K {:.4g} deg/s/rts, Q {:.4g} "
                 "deg), dead time {:g} s per turn, run {:g} s\n",
                 r.noise_source, r.noise.arw_dps_rthz, r.noise.bias_instability_dps,
                 r.noise.rrw_dps_per_rts, r.noise.quantization_deg, p.dead_s, p.duration_s);
  if (!r.visits_deg.empty()) {
    std::string order;
    for (const double a : r.visits_deg)
      order += fmt::format("{}{:g}", order.empty() ? "" : ", ", a);
    fmt::format_to(out,
                   "  scheme         {} positions, visited in {} {} (a turn of the dead time "
                   "between dwells at different angles); the error is the first harmonic's per "
                   "component (c1, s1)\n",
                   r.positions_deg.size(),
                   r.order == "sweep"   ? "the drift-cancelling sweep"
                   : r.order == "cycle" ? "the table's order (cycle)"
                                        : "there and back",
                   order);
  }
  fmt::format_to(out, "  dwell          {:.3g} s", p.dwell_s);
  if (r.conversions_per_dwell > 0)
    fmt::format_to(out,
                   "  (about {} gyro conversions at the AD7739's default filter word: --n-avg {})",
                   r.conversions_per_dwell, r.conversions_per_dwell);
  if (r.visits_deg.empty())
    fmt::format_to(out, "\n  cycle period   {:.3g} s  (dwell, turn, dwell, turn)\n", p.period_s);
  else
    fmt::format_to(out, "\n  cycle period   {:.3g} s  ({} dwells and their turns)\n", p.period_s,
                   r.visits_deg.size());
  fmt::format_to(out, "  predicted 1-sigma error of the run's {}: {:.3g} deg/s ({:.3g} deg/h)\n",
                 r.visits_deg.empty() ? "compensated rate" : "first harmonic", p.sigma_dps,
                 dph(p.sigma_dps));
  if (r.heading)
    fmt::format_to(out,
                   "  predicted 1-sigma error of the heading at {:g} deg latitude: {:.3g} deg "
                   "({:.3g} deg x sqrt(h / T)); white-noise limit sqrt(2) N / (W_H sqrt(T)) "
                   "{:.3g} deg\n",
                   r.heading->lat_deg, r.heading->sigma_deg, r.heading->sigma_deg_rth,
                   r.heading->white_limit_deg);
  fmt::format_to(out, "  without dead time at this dwell: {:.3g} deg/s: the turns cost {:.1f} %\n",
                 p.sigma_no_dead_dps, 100.0 * (p.sigma_dps / p.sigma_no_dead_dps - 1.0));
  if (p.closed_form.dwell_s > 0.0)
    fmt::format_to(
        out,
        "  closed form (white + flicker, independent pairs): dwell sqrt(d tau_c) = "
        "{:.3g} s (tau_c {:.3g} s), error (N + 0.664 B sqrt(d))/sqrt(T) = {:.3g} deg/s\n",
        p.closed_form.dwell_s, p.closed_form.corner_tau_s, p.closed_form.sigma_dps);
  if (r.reference_sigma_dps > 0.0)
    fmt::format_to(out,
                   "  at the paper's dwell {:g} s: {:.3g} deg/s ({:+.1f} % against the plan)\n",
                   r.reference_dwell_s, r.reference_sigma_dps,
                   100.0 * (r.reference_sigma_dps / p.sigma_dps - 1.0));
  if (r.record_over_model)
    fmt::format_to(out,
                   "  the record's own two-sample deviation at this dwell and gap: {:.3f} x the "
                   "model's\n",
                   std::sqrt(*r.record_over_model));
  fmt::format_to(out,
                 "  error against run length at this dwell:\n    run (s)      sigma (deg/s)\n");
  if (r.heading) {
    fmt::format_to(out, "    (heading, deg: ");
    for (std::size_t i = 0; i < r.heading->by_duration_deg.size(); i += 6)
      fmt::format_to(out, "{}{:g} s {:.3g}", i ? ", " : "", r.heading->by_duration_deg[i].x,
                     r.heading->by_duration_deg[i].sigma_dps);
    fmt::format_to(out, ")\n");
  }
  for (const auto& q : p.by_duration)
    fmt::format_to(out, "    {:<12.4g} {:.3g}\n", q.x, q.sigma_dps);
  for (const auto& n : r.notes) fmt::format_to(out, "  note: {}\n", n);
  return t;
}

}  // namespace

int run_plan(const plan_options& o) {
  if (o.sensor.empty() == o.in.file.empty())
    return report(usage_error("plan: give either --sensor NAME|FILE.toml or --static FILE"));
  if (o.heading != std::isfinite(o.lat_deg))
    return report(usage_error("plan: --heading and --latitude DEG go together"));
  const auto plot = plot_target(o.plot);
  if (!plot) return report(plot.err());
  if (*plot) {
    const std::array format{(*plot)->format};
    if (auto s = io::check_outputs(std::array{o.in.file},
                                   report::rendered_files((*plot)->dir, (*plot)->stem, 1, format));
        !s)
      return report(s.err());
    if (auto s = report::check_rendered_files((*plot)->dir, (*plot)->stem, 1); !s)
      return report(s.err());
  }
  workflow::plan_request req;
  if (!o.positions.empty()) {
    const auto pos = text::to_doubles(o.positions, ',');
    if (!pos)
      return report(
          usage_error(fmt::format("--positions '{}': expected table positions in degrees, A,B,...",
                                  printable(o.positions, 60))));
    req.positions_deg = *pos;
  }
  if (o.heading) req.heading_lat_deg = o.lat_deg;
  req.order = o.order;
  req.dead_s = o.dead_s;
  req.duration_s = o.duration_s;
  req.limits.min_dwell_s = o.min_dwell_s;
  req.limits.max_dwell_s = o.max_dwell_s;
  req.conversion_s = rig::conversion_time_s(rig::ad7739_config{});
  std::vector<analysis_input> inputs;
  if (!o.sensor.empty()) {
    auto p = sensor::load_preset(o.sensor);
    if (!p) return report(p.err());
    req.noise = workflow::plan_noise_of(p->params);
    req.noise_source = "sensor " + p->name;
  } else {
    auto in = load_series(o.in);
    if (!in) return report(in.err());
    inputs = std::move(*in);
    auto t = workflow::plan_noise_of_record(inputs.front().phase, deg_per_unit(o.in), o.min_dwell_s,
                                            req.notes);
    if (!t) return report(input_error({o.in.file}, t.err().message));
    req.noise = *t;
    req.noise_source = "the noise fit of " + printable(o.in.file, 200);
    req.static_samples = inputs.front().series.values();
    req.static_tau0_s = inputs.front().phase.tau0_s();
    req.static_dps_per_unit = deg_per_unit(o.in);
  }
  auto r = workflow::plan(req);
  if (!r) return report(r.err());
  if (*plot) {
    const std::array formats{(*plot)->format};
    if (auto s = report::render(workflow::plan_figure(*r), (*plot)->dir, (*plot)->stem, formats);
        !s)
      return report(s.err());
  }
  const auto s =
      o.json ? print_json(workflow::plan_json(*r)) : print_checked(plan_text(*r), "<stdout>");
  if (!s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
