/// \file
/// \brief `gyroflip heading`: north finding from indexed runs (workflow/heading.hpp).
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/workflow/heading.hpp"

namespace gyroflip::app {

int run_heading(const heading_options& o) {
  workflow::heading_request q;
  q.runs = o.runs;
  q.lat_deg = o.lat_deg;
  if (!o.table_axis.empty()) q.table_axis_up = o.table_axis == "up";
  q.base_turn_deg = o.base_turn_deg;
  q.sensor = o.sensor;
  q.harmonics = o.harmonics;
  auto h = workflow::find_heading(q);
  if (!h) return report(h.err());
  if (o.json) {
    if (auto s = print_json(workflow::heading_json(*h)); !s) return report(s.err());
    return 0;
  }
  std::string text = fmt::format(
      "heading {:.3f} deg +- {:.3f} deg (1 sigma, from the data's own noise)\n"
      "  azimuth of the sensitive axis at the table's 0 deg, from north, clockwise\n"
      "  scheme: {}\n",
      h->heading_deg, h->sigma_deg, h->scheme);
  if (h->ambiguous)
    text += fmt::format("  or its mirror {:.3f} deg (0/180 gives the heading up to {})\n",
                        h->mirror_deg, h->two_azimuths ? "a mirror image" : "its sign");
  if (h->limit_deg > 0.0)
    text += fmt::format(
        "  white-noise limit {:.3f} deg ({}, N = {:.3g} deg/s/sqrt(Hz) from the dwells): sigma is "
        "{:.2f} x the limit\n",
        h->limit_deg,
        h->ambiguous && h->two_azimuths
            ? "N sqrt(T (1/T1 + 1/T2)) / (2 |sin(turn/2)| W_E cos(lat) sqrt(1 - x^2) sqrt(T)): "
              "the difference of two 0/180 contrasts, k = 1"
        : h->ambiguous ? "N / (W_E cos(lat) |sin(psi - theta_0)| sqrt(T)): a 0/180 contrast, k = 1"
                       : "sqrt(2) N / (W_E cos(lat) sqrt(T))",
        h->arw_dps_rthz, h->ratio_to_limit);
  if (h->dead_time_bound_deg)
    text +=
        fmt::format("  dead-time bound (the sensor's N and B): {:.3f} deg: sigma is {:.2f} x it\n",
                    *h->dead_time_bound_deg, h->sigma_deg / *h->dead_time_bound_deg);
  text += fmt::format("  first harmonic {}{:.4e} deg/s against W_E cos(lat) {:.4e} deg/s\n",
                      h->ambiguous ? "(its projection, magnitude) " : "", h->amplitude_dps,
                      h->earth_horizontal_dps);
  if (!h->runs.empty() && h->runs[0].fit.names.size() == 5)
    text += fmt::format("  second harmonic {:.4e} +- {:.2e} deg/s\n", h->second_harmonic_dps,
                        h->second_harmonic_sigma_dps);
  if (h->two_azimuths)
    text += fmt::format(
        "  two base azimuths ({:g} deg apart): the table's term (tilt x g-sensitivity) removed: "
        "{:.3e} deg/s, {:+.2f} deg in the first run's own heading\n",
        h->base_turn_deg, h->table_term_dps, h->table_term_heading_deg);
  for (const auto& r : h->runs)
    text += fmt::format("  {}: {:.3f} +- {:.3f} deg, {} periods of {} dwells, {:.0f} s\n", r.path,
                        r.heading.heading_deg, r.heading.sigma_deg, r.fit.blocks, r.fit.period,
                        r.run_s);
  for (const auto& c : h->caveats) text += fmt::format("  caveat: {}\n", c);
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
