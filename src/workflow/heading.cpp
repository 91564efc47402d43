/// \file
/// \brief North finding from indexed runs (heading.hpp).
#include "gyroflip/workflow/heading.hpp"

#include <cmath>
#include <cstdlib>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/io/schema.hpp"
#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/rigdata/recording_source.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::workflow {
namespace {

const std::string* meta(const std::vector<io::csv_metadata>& m, std::string_view key) {
  for (const auto& e : m)
    if (e.key == key) return &e.value;
  return nullptr;
}

std::optional<double> meta_number(const std::vector<io::csv_metadata>& m, std::string_view key) {
  const std::string* v = meta(m, key);
  if (!v || v->empty()) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(v->c_str(), &end);
  if (end == v->c_str() || !std::isfinite(x)) return std::nullopt;
  return x;
}

// One conversion's time (s): the recording's own figure, else its AD7739 settings.
std::optional<double> conversion_time_of(const std::vector<io::csv_metadata>& m) {
  if (auto t = meta_number(m, "conversion_time_s")) return t;
  const auto fw = meta_number(m, "filter_word");
  const std::string* chop = meta(m, "chop");
  if (!fw || !chop) return std::nullopt;
  rig::ad7739_config c;
  c.filter_word = static_cast<int>(*fw);
  c.chop = *chop == "on";
  return rig::conversion_time_s(c);
}

struct read_run {
  heading_run run;
  std::optional<bool> axis_up;  // from `# table_axis:`
  std::optional<double> azimuth_deg;
  double table_angle0_deg = 0.0;         // the table's first position (a projection's direction)
  bool axis_named_not_vertical = false;  // `# table_axis:` names another axis than up/down
  std::string axis_name;
};

result<read_run> fit_run(const std::string& path, bool axis_up_default, int harmonics,
                         double earth_horizontal_dps) {
  auto rec = rigdata::read_recording_rows(path);
  if (!rec) return rec.err();
  read_run out;
  if (const std::string* a = meta(rec->metadata, "table_axis")) {
    if (*a == "up") out.axis_up = true;
    if (*a == "down") out.axis_up = false;
    out.axis_named_not_vertical = *a != "up" && *a != "down";
    out.axis_name = *a;
  }
  out.azimuth_deg = meta_number(rec->metadata, "azimuth_deg");
  const auto dwells = method::indexed_dwells(rec->rows);
  method::harmonic_options options;
  options.harmonics = harmonics;
  options.projection_of_two = true;
  if (harmonics == 2 && rec->positions.size() == 2)
    return usage_error(
        fmt::format("{}: a second harmonic needs at least 5 positions; the run has {}", path,
                    rec->positions.describe()));
  auto fit = method::fit_harmonics(dwells, rec->positions, options);
  // Data that cannot give a heading (too few positions, no visiting period) is bad input.
  if (!fit) return usage_error(fmt::format("{}: {}", path, fit.err().message));
  heading_run& r = out.run;
  r.path = path;
  r.fit = std::move(*fit);
  r.positions = rec->positions.describe();
  r.n_positions = rec->positions.size();
  const auto& f = r.fit;
  if (f.names[1] == "p1") {
    const auto p = method::heading_of_projection(f.value[1], f.var(1), earth_horizontal_dps,
                                                 rec->positions.angle_deg(0),
                                                 out.axis_up.value_or(axis_up_default));
    r.projection = p;
    out.table_angle0_deg = rec->positions.angle_deg(0);
    r.heading = {p.heading_deg, p.sigma_deg, std::abs(f.value[1])};
  } else {
    r.heading = method::heading_of(f.value[1], f.value[2], f.var(1), f.var(2), f.cov(1, 2),
                                   out.axis_up.value_or(axis_up_default));
  }
  if (harmonics == 2) {
    if (auto one = method::fit_harmonics(dwells, rec->positions))
      r.sigma_one_harmonic_deg =
          method::heading_of(one->value[1], one->value[2], one->var(1), one->var(2), one->cov(1, 2),
                             out.axis_up.value_or(axis_up_default))
              .sigma_deg;
  }
  r.run_s = static_cast<double>(f.blocks) * f.block_s;
  if (const auto t_conv = conversion_time_of(rec->metadata)) {
    double w = 0.0;
    for (const auto& d : dwells) w += d.weight;
    r.dwell_s = w / static_cast<double>(dwells.size()) * *t_conv;
    r.dead_per_dwell_s = std::max(0.0, f.block_s / static_cast<double>(f.period) - r.dwell_s);
    r.arw_dps_rthz = f.dwell_sigma_dps * std::sqrt(r.dwell_s);
  }
  return out;
}

// The turn of the rig's base from the first run to the second: given, else the recordings'
// `# azimuth_deg:` difference.
result<double> base_turn_of(const heading_request& q, std::optional<double> az1,
                            std::optional<double> az2) {
  if (q.base_turn_deg) return *q.base_turn_deg;
  if (az1 && az2) return *az2 - *az1;
  return parameter_error(
      "base_turn_deg",
      fmt::format(
          "two runs: the turn of the rig's base between them is not known (the azimuth "
          "is not recorded in {}: a recording states it when told the rig's azimuth): give it",
          az1 ? q.runs[1] : q.runs[0]));
}

}  // namespace

result<heading_result> find_heading(const heading_request& q) {
  if (q.runs.empty() || q.runs.size() > 2)
    return usage_error(fmt::format(
        "a heading takes one run, or two at different base azimuths; got {}", q.runs.size()));
  if (auto s = earth::check_latitude(q.lat_deg); !s) return s.err();
  if (std::abs(q.lat_deg) > 85.0)
    return usage_error(
        fmt::format("at {:g} deg latitude the horizontal Earth rate is {:.2g} of "
                    "its whole: north cannot be found by it",
                    q.lat_deg, std::cos(q.lat_deg * units::rad_per_deg)));
  std::optional<sensor::preset> preset;
  if (!q.sensor.empty()) {
    auto p = sensor::load_preset(q.sensor);
    if (!p) return p.err();
    preset = std::move(*p);
  }
  if (q.harmonics != 1 && q.harmonics != 2)
    return usage_error(fmt::format("one or two harmonics are fitted; got {}", q.harmonics));
  heading_result out;
  out.earth_horizontal_dps = earth::earth_rate_wgs84_dps * std::cos(q.lat_deg * units::rad_per_deg);
  std::vector<read_run> runs;
  for (const auto& path : q.runs) {
    auto r = fit_run(path, q.table_axis_up.value_or(true), q.harmonics, out.earth_horizontal_dps);
    if (!r) return r.err();
    if (r->axis_named_not_vertical && !q.table_axis_up)
      return usage_error(fmt::format(
          "{}: the recording's table axis is '{}', not vertical (up or down): north finding "
          "needs the table to turn about the vertical (give the axis if the recording misnames "
          "it)",
          path, printable(r->axis_name, 40)));
    if (q.table_axis_up) r->axis_up = q.table_axis_up;
    if (!q.table_axis_up && r->axis_name.empty())
      out.caveats.push_back(fmt::format(
          "{}: the table axis is not recorded (a recording not told it, or made before gyroflip "
          "stored it): taken as up; give the table axis if it was down",
          path));
    runs.push_back(std::move(*r));
  }
  if (runs.empty()) return usage_error("no run");
  const bool up = runs.front().axis_up.value_or(true);
  const bool projection = runs.front().run.projection.has_value();
  if (runs.size() == 2 && projection != runs[1].run.projection.has_value())
    return usage_error(
        "a 0/180 run and a run of three or more positions are not combined: give two 0/180 runs "
        "(at the same table angles) or two of three or more positions (docs/NORTH.md)");
  const bool two_projections = runs.size() == 2 && projection;
  if (two_projections &&
      std::abs(std::remainder(runs[0].table_angle0_deg - runs[1].table_angle0_deg, 360.0)) > 0.01)
    return usage_error(fmt::format(
        "two 0/180 runs at different table angles ({:g} and {:g} deg): the table's term cancels "
        "only between runs at the same angles",
        runs[0].table_angle0_deg, runs[1].table_angle0_deg));
  double total_s = 0.0, arw_w = 0.0, arw_sum = 0.0, dead_sum = 0.0;
  for (const auto& r : runs) {
    total_s += r.run.run_s;
    if (r.run.arw_dps_rthz > 0.0) {
      arw_sum += r.run.arw_dps_rthz * r.run.run_s;
      dead_sum += r.run.dead_per_dwell_s * r.run.run_s;
      arw_w += r.run.run_s;
    }
    out.runs.push_back(r.run);
  }
  const auto& f0 = runs[0].run.fit;
  out.scheme = fmt::format("{} positions ({} deg), visiting period {} dwells",
                           runs[0].run.n_positions, runs[0].run.positions, f0.period);
  if (projection && !two_projections) {
    const auto& p = *runs[0].run.projection;
    out.ambiguous = true;
    out.mirror_deg = p.mirror_deg;
    out.scheme = fmt::format(
        "2 positions ({} deg), visiting period {} dwells: the projection of the Earth rate on "
        "the axis at the table's {:g} deg, with the scale factor known",
        runs[0].run.positions, f0.period, runs[0].table_angle0_deg);
    out.caveats.push_back(fmt::format(
        "0/180 measures only W_H cos(psi - {0:g}): the heading is {1:.3f} or its mirror {2:.3f} "
        "deg, which one this run cannot tell (a third position, or the rig's base turned by 90 "
        "deg, can)",
        runs[0].table_angle0_deg, p.heading_deg, p.mirror_deg));
    out.caveats.push_back(
        "the scale factor is taken as known (the recording's deg/s as true): an error e of it "
        "shifts the heading by about e x cot(psi - theta_0) rad, and a bias of the projection "
        "from the table's tilt x g-sensitivity the same as for more positions");
    if (p.at_edge)
      out.caveats.push_back(fmt::format(
          "the projection is {:.3f} of W_H, within one sigma of +-1: the axis points near the "
          "table's 0 deg direction or its opposite, where cos is flat; the sigma is the angle "
          "acos(1 - sigma_p / W_H), not the delta method's",
          p.cos_value));
  }
  std::optional<double> two_projection_cos;
  if (two_projections) {
    auto turn = base_turn_of(q, runs[0].azimuth_deg, runs[1].azimuth_deg);
    if (!turn) return turn.err();
    if (runs[1].axis_up.value_or(up) != up)
      return usage_error("the two runs name different table axes (up and down)");
    const auto& a = runs[0].run.fit;
    const auto& b = runs[1].run.fit;
    auto h = method::heading_of_two_projections(a.value[1], a.var(1), b.value[1], b.var(1),
                                                out.earth_horizontal_dps, runs[0].table_angle0_deg,
                                                *turn, up);
    if (!h) return h.err();
    const auto& p = h->heading;
    out.two_azimuths = true;
    out.base_turn_deg = *turn;
    out.ambiguous = true;
    out.heading_deg = p.heading_deg;
    out.mirror_deg = p.mirror_deg;
    out.sigma_deg = p.sigma_deg;
    out.amplitude_dps = std::abs(a.value[1]);
    out.table_term_dps = h->table_term_dps;
    {  // the shift of the first run's own solution nearest to this heading
      const auto& one = *runs[0].run.projection;
      const double d1 = std::remainder(one.heading_deg - out.heading_deg, 360.0);
      const double d2 = std::remainder(one.mirror_deg - out.heading_deg, 360.0);
      out.table_term_heading_deg = std::abs(d1) <= std::abs(d2) ? d1 : d2;
    }
    two_projection_cos = p.cos_value;
    out.scheme = fmt::format(
        "two 0/180 runs ({} deg), visiting period {} dwells, at base azimuths {:g} deg apart: "
        "the difference of their projections of the Earth rate, with the scale factor known "
        "(the table's term removed)",
        runs[0].run.positions, f0.period, *turn);
    out.caveats.push_back(fmt::format(
        "two 0/180 runs give sin(psi - {0:g} + {1:g}) only: the heading is {2:.3f} or its mirror "
        "{3:.3f} deg, which one they cannot tell (a third position in either run can; the "
        "table's term is {4:.3g} deg/s for the first, {5:.3g} for the mirror)",
        runs[0].table_angle0_deg, 0.5 * *turn, p.heading_deg, p.mirror_deg, h->table_term_dps,
        h->table_term_mirror_dps));
    out.caveats.push_back(
        "the scale factor is taken as known (the recordings' deg/s as true): an error of it "
        "shifts the heading as for one 0/180 run");
    if (p.at_edge)
      out.caveats.push_back(fmt::format(
          "the difference is {:.3f} of its largest, within one sigma of +-1: the sigma is the "
          "angle acos(1 - sigma_x), not the delta method's",
          p.cos_value));
  } else if (runs.size() == 1) {
    out.heading_deg = runs[0].run.heading.heading_deg;
    out.sigma_deg = runs[0].run.heading.sigma_deg;
    out.amplitude_dps = runs[0].run.heading.amplitude_dps;
    std::string per_mrad;
    if (preset && !projection) {
      const double g =
          std::hypot(preset->params.g_sens_z_dps_per_g, preset->params.g_sens_x_dps_per_g);
      per_mrad = fmt::format(" ({} : {:.2g} deg per mrad of tilt)", preset->name,
                             std::atan(g * 1e-3 / out.earth_horizontal_dps) / units::rad_per_deg);
    }
    if (!projection)
      out.caveats.push_back(fmt::format(
          "the table's tilt x the gyro's g-sensitivity reads exactly as Earth rate{}: it shifts "
          "this heading by atan(g x tilt / W_H) and no statistic of one run shows it; a second run "
          "with the rig's base turned (180 deg is best) removes it",
          per_mrad));
  } else {
    out.two_azimuths = true;
    auto turn_of = base_turn_of(q, runs[0].azimuth_deg, runs[1].azimuth_deg);
    if (!turn_of) return turn_of.err();
    const double turn = *turn_of;
    out.base_turn_deg = turn;
    const auto& a = runs[0].run.fit;
    const auto& b = runs[1].run.fit;
    if (runs[1].axis_up.value_or(up) != up)
      return usage_error("the two runs name different table axes (up and down)");
    auto h = method::heading_two_azimuths(
        {a.value[1], a.value[2]}, {a.var(1), a.cov(1, 2), a.cov(1, 2), a.var(2)},
        {b.value[1], b.value[2]}, {b.var(1), b.cov(1, 2), b.cov(1, 2), b.var(2)}, turn, up);
    if (!h) return h.err();
    out.heading_deg = h->first.heading_deg;
    out.sigma_deg = h->first.sigma_deg;
    out.amplitude_dps = h->first.amplitude_dps;
    out.table_term_dps = h->table_term_dps;
    out.table_term_heading_deg =
        std::remainder(runs[0].run.heading.heading_deg - out.heading_deg, 360.0);
    out.scheme += fmt::format("; two base azimuths {:g} deg apart", turn);
  }
  if (arw_w > 0.0) {
    out.arw_dps_rthz = arw_sum / arw_w;
    out.limit_deg = method::heading_white_limit_deg(out.arw_dps_rthz, q.lat_deg, total_s,
                                                    projection ? 1.0 : std::sqrt(2.0));
    if (two_projection_cos) {
      // sigma_x^2 = N^2 (1/T1 + 1/T2) / (2 W_H sin(turn/2))^2 over 1 - x^2; the k = 1 limit of
      // the total T is N / (W_H sqrt(T)): the ratio of the two.
      const double t1 = runs[0].run.run_s, t2 = runs[1].run.run_s;
      out.limit_deg *=
          std::sqrt((1.0 / t1 + 1.0 / t2) * total_s) /
          (2.0 * std::abs(std::sin(0.5 * out.base_turn_deg * units::rad_per_deg))) /
          std::max(std::sqrt(std::max(0.0, 1.0 - *two_projection_cos * *two_projection_cos)), 1e-6);
    } else if (projection) {  // k = 1 (a known-bias pair's contrast), at this heading's |sin|
      out.limit_deg /= std::max(
          std::sqrt(std::max(0.0, 1.0 - std::pow(runs[0].run.projection->cos_value, 2))), 1e-6);
    }
    out.ratio_to_limit = out.sigma_deg / out.limit_deg;
  } else {
    out.caveats.push_back(
        "the dwell's length is not known (no conversion time or AD7739 settings in the "
        "recording): no white-noise limit");
  }
  if (preset && arw_w > 0.0) {
    out.dead_time_bound_deg = method::heading_dead_time_limit_deg(
        preset->params.arw_dps_rthz, preset->params.bias_instability_dps, dead_sum / arw_w,
        q.lat_deg, total_s);
    if (projection)
      *out.dead_time_bound_deg *=
          out.limit_deg / method::heading_white_limit_deg(out.arw_dps_rthz, q.lat_deg, total_s);
  }
  if (q.harmonics == 2) {
    const auto& f = runs[0].run.fit;
    const double c2 = f.value[3], s2 = f.value[4];
    const double a2 = std::hypot(c2, s2);
    out.second_harmonic_dps = a2;
    out.second_harmonic_sigma_dps =
        a2 > 0.0
            ? std::sqrt(std::max(
                  0.0, (c2 * c2 * f.var(3) + s2 * s2 * f.var(4) + 2.0 * c2 * s2 * f.cov(3, 4)) /
                           (a2 * a2)))
            : std::sqrt(0.5 * (f.var(3) + f.var(4)));
    const double z = a2 / std::max(out.second_harmonic_sigma_dps, 1e-300);
    const std::string one =
        runs[0].run.sigma_one_harmonic_deg
            ? fmt::format(" (one harmonic: +- {:.3f} deg against +- {:.3f} deg with two)",
                          *runs[0].run.sigma_one_harmonic_deg, runs[0].run.heading.sigma_deg)
            : std::string();
    out.caveats.push_back(
        z < 3.0 ? fmt::format("the second harmonic {:.3g} +- {:.3g} deg/s is not significant "
                              "({:.1f} sigma): one harmonic suffices{}",
                              a2, out.second_harmonic_sigma_dps, z, one)
                : fmt::format("the second harmonic {:.3g} +- {:.3g} deg/s is significant ({:.1f} "
                              "sigma): a term at twice the table angle (a wobble of the table, a "
                              "mounting or anisoelastic term); fitting it keeps it out of the "
                              "heading where the positions are not equally spaced{}",
                              a2, out.second_harmonic_sigma_dps, z, one));
  }
  if (!f0.correlated)
    out.caveats.push_back(fmt::format(
        "{} visiting periods: the sigma assumes independent periods (32 are needed to read "
        "their correlation)",
        f0.blocks));
  const double rel = out.amplitude_dps / out.earth_horizontal_dps - 1.0;
  if (!projection && std::abs(rel) > 0.05)
    out.caveats.push_back(fmt::format(
        "the first harmonic is {:+.1f} % off the horizontal Earth rate at {:g} deg: a scale-factor "
        "error, a table term (tilt x g-sensitivity) or a wrong latitude",
        100.0 * rel, q.lat_deg));
  return out;
}

nlohmann::json heading_json(const heading_result& h) {
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& r : h.runs) {
    nlohmann::json terms = nlohmann::json::object();
    for (std::size_t i = 0; i < r.fit.names.size(); ++i)
      terms[r.fit.names[i]] = {{"value_dps", r.fit.value[i]},
                               {"sigma_dps", std::sqrt(r.fit.var(i))}};
    runs.push_back({{"file", r.path},
                    {"positions_deg", r.positions},
                    {"period_dwells", r.fit.period},
                    {"blocks", r.fit.blocks},
                    {"skipped_dwells", r.fit.skipped_dwells},
                    {"run_s", r.run_s},
                    {"dwell_s", r.dwell_s},
                    {"dead_time_per_dwell_s", r.dead_per_dwell_s},
                    {"arw_dps_rthz", r.arw_dps_rthz},
                    {"terms", terms},
                    {"heading_deg", r.heading.heading_deg},
                    {"sigma_deg", r.heading.sigma_deg}});
  }
  nlohmann::json j = io::schema_object("heading", 1);
  j.update(nlohmann::json{{"heading_deg", h.heading_deg},
                          {"sigma_deg", h.sigma_deg},
                          {"limit_deg", h.limit_deg},
                          {"ratio_to_limit", h.ratio_to_limit},
                          {"arw_dps_rthz", h.arw_dps_rthz},
                          {"scheme", h.scheme},
                          {"two_azimuths", h.two_azimuths},
                          {"earth_horizontal_dps", h.earth_horizontal_dps},
                          {"first_harmonic_dps", h.amplitude_dps},
                          {"runs", runs},
                          {"caveats", h.caveats}});
  if (h.ambiguous) {
    j["ambiguous"] = true;
    j["heading_mirror_deg"] = h.mirror_deg;
  }
  if (!h.runs.empty() && h.runs[0].fit.names.size() == 5) {
    j["second_harmonic_dps"] = h.second_harmonic_dps;
    j["second_harmonic_sigma_dps"] = h.second_harmonic_sigma_dps;
    if (h.runs[0].sigma_one_harmonic_deg)
      j["sigma_one_harmonic_deg"] = *h.runs[0].sigma_one_harmonic_deg;
  }
  j["dead_time_bound_deg"] =
      h.dead_time_bound_deg ? nlohmann::json(*h.dead_time_bound_deg) : nlohmann::json();
  if (h.two_azimuths) {
    j["base_turn_deg"] = h.base_turn_deg;
    j["table_term_dps"] = h.table_term_dps;
    j["table_term_heading_deg"] = h.table_term_heading_deg;
  }
  return j;
}

}  // namespace gyroflip::workflow
