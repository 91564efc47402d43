/// \file
/// \brief `gyroflip noise`: IEEE 952 noise terms (Q, N, B, K, R) with intervals and units.
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "cmd_adev.hpp"
#include "finite_output.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/noise_report.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/report/figures.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

using nlohmann::json;

std::string show(const analysis::noise_term& t, double to_unit) {
  if (!t.resolved) return fmt::format("not resolved (< {:.4g})", t.hi * to_unit);
  return fmt::format("{:.4g}  [{:.4g}, {:.4g}]", t.value * to_unit, t.lo * to_unit, t.hi * to_unit);
}

// A term's value, or for an unresolved term its upper limit.
double value_or_limit(const analysis::noise_term& t) {
  return t.resolved ? t.value : t.hi;
}

// The term in another unit, for the text's "= ..." (the value, or its upper limit).
std::string also(const analysis::noise_term& t, double to_unit) {
  return fmt::format("{}{:.4g}", t.resolved ? "" : "< ", value_or_limit(t) * to_unit);
}

// Kalibr's IMU noise file (kalibr/wiki "IMU Noise Model"): the continuous-time gyroscope noise
// density (rad/s/sqrt(Hz), our N) and bias random walk (rad/s^2/sqrt(Hz), our K), as measured:
// no inflation factor is applied (docs/ANALYSIS.md says what the field's x10 habit means).
std::string kalibr_yaml(const std::string& file, const analysis::noise_terms& f, double to_rad,
                        double rate_hz) {
  const auto remark = [](const analysis::noise_term& t) {
    return t.resolved ? std::string() : std::string("  # an upper limit: not resolved by the data");
  };
  return fmt::format(
      "# IMU noise model for Kalibr, measured by gyroflip noise from {}\n"
      "# continuous-time densities, not inflated; accelerometer fields are not measured here\n"
      "gyroscope_noise_density: {:.6e}  # rad/s/sqrt(Hz) (ARW N){}\n"
      "gyroscope_random_walk: {:.6e}  # rad/s^2/sqrt(Hz) (RRW K){}\n"
      "update_rate: {:.9g}  # Hz\n",
      printable(file, 200), value_or_limit(f.arw) * to_rad, remark(f.arw),
      value_or_limit(f.rrw) * to_rad, remark(f.rrw), rate_hz);
}

// One column's OADEV, fitted terms and read-offs (in the samples' unit).
using column_noise = io::noise_report;

// `--fit-taus LO:HI` (s): the taus the model is fitted to (the library's rule).
result<analysis::tau_range> fit_range(const std::string& spec) {
  if (spec.empty()) return analysis::tau_range{};
  const auto v = text::to_doubles(spec, ':');
  if (!v || v->size() != 2)
    return usage_error("--fit-taus: LO:HI in seconds, 0 <= LO < HI; got " + spec);
  const analysis::tau_range r{(*v)[0], (*v)[1], false};  // a given range is fitted as given
  if (auto s = analysis::check_fit_range(r); !s) return s.err();
  return r;
}

result<column_noise> noise_of(const noise_options& o, const analysis::tau_range& range,
                              const analysis_input& in) {
  column_noise c;
  c.file = o.in.file;
  c.column = in.column;
  c.input = o.in.input;
  c.units = unit_name(o.in);
  c.deg_per_unit = deg_per_unit(o.in);
  c.tau0_s = in.phase.tau0_s();
  c.samples = in.series.samples().size();
  // The rate column of `gyroflip compensate`: a demodulator's estimates, whose white-noise shape
  // its scheme states (abba: correlated cycles).
  for (const auto& m : in.series.metadata())
    if (m.key == "pairing" && o.in.input == "rate")
      if (const auto p = method::parse_pairing(m.value))
        c.series = method::noise_series_of(*p, c.tau0_s);
  progress bar("noise of " + o.in.file, 1000);
  auto a = analysis::analyse_noise(in.phase, o.ci, range, c.series, per_mille(bar), o.long_taus);
  bar.finish();
  // Too few points for the fit is a property of this input (too short a series): name it.
  if (!a)
    return input_error({o.in.file}, a.err().message + (o.fit_taus.empty() ? "" : " in --fit-taus"));
  if (a->terms.chi2_per_dof > 4.0)
    warn(
        fmt::format("{}: column {}: the noise model fits the curve poorly (chi2/dof {:.3g}): "
                    "other noise (a sinusoid, a temperature swing) or a bad range; see the misfit "
                    "points, or fit a range with --fit-taus LO:HI",
                    o.in.file, printable(c.column, 60), a->terms.chi2_per_dof));
  c.result = std::move(*a);
  return c;
}

void append_text(std::string& text, const noise_options& o, const column_noise& c) {
  const auto& f = c.result.terms;
  const double k = deg_per_unit(o.in);
  const double k_rad = k * units::rad_per_deg;
  const auto out = std::back_inserter(text);
  fmt::format_to(out,
                 "{}: column {}, {} samples at {:g} Hz in {}, IEEE 952 terms from OADEV ({:g} % "
                 "intervals)\n",
                 o.in.file, printable(c.column, 60), c.samples, 1.0 / c.tau0_s, unit_name(o.in),
                 100.0 * f.level);
  fmt::format_to(out,
                 "  angle random walk N    {} deg/sqrt(h)   = {} deg/s/sqrt(Hz) = {} rad/s/sqrt(Hz)"
                 " (two-sided density; one-sided sqrt(2) N = {} deg/s/sqrt(Hz))\n",
                 show(f.arw, k * units::deg_rth_per_deg_rts), also(f.arw, k), also(f.arw, k_rad),
                 also(analysis::noise_term{f.arw.resolved, std::numbers::sqrt2 * f.arw.value, 0.0,
                                           std::numbers::sqrt2 * f.arw.hi},
                      k));
  if (std::isfinite(c.result.adev_1s))
    fmt::format_to(
        out,
        "                         ADEV(1 s) {:.4g} deg/sqrt(h) (ADEV at tau {:g} s x "
        "sqrt(tau): the datasheet reading), {:.4g} less the other fitted terms there\n",
        c.result.adev_1s * std::sqrt(c.result.adev_1s_tau_s) * k * units::deg_rth_per_deg_rts,
        c.result.adev_1s_tau_s, c.result.adev_1s_arw * k * units::deg_rth_per_deg_rts);
  const double floor_dph = f.bias_floor_dev * k * units::dph_per_dps;
  fmt::format_to(out,
                 "  bias instability  B    {} deg/h (IEEE 952 fit)   = {} rad/s;  floor/0.664 "
                 "{:.4g} deg/h;  datasheet \"bias stability\" (raw floor) {:.4g} deg/h at tau {:g} "
                 "s{}\n",
                 show(f.bias_instability, k * units::dph_per_dps), also(f.bias_instability, k_rad),
                 floor_dph / 0.6643, floor_dph, f.bias_floor_tau_s,
                 f.bias_floor_reached ? "" : " (no floor: OADEV still falls)");
  fmt::format_to(out, "  rate random walk  K    {} deg/h/sqrt(h)   = {} rad/s^2/sqrt(Hz)\n",
                 show(f.rrw, k * units::dph_rth_per_dps_rts), also(f.rrw, k_rad));
  fmt::format_to(out, "  quantization      Q    {} deg\n", show(f.quantization, k));
  fmt::format_to(out, "  rate ramp         R    {} deg/h^2\n",
                 show(f.rate_ramp, k * units::dph2_per_dps2));
  fmt::format_to(out,
                 "  fit over tau {:g} to {:g} s{}, chi2/dof {:.3g}; intervals include the spread "
                 "over {} fit ranges\n",
                 f.fit_tau_lo_s, f.fit_tau_hi_s, o.fit_taus.empty() ? "" : " (--fit-taus)",
                 f.chi2_per_dof, f.fit_ranges);
  const auto& r = c.result.readoffs;
  const auto line = [](const std::optional<double>& v, double to, double tau, const char* slope) {
    return v ? fmt::format("{:.4g} (slope {} at tau {:.3g} s)", *v * to, slope, tau)
             : fmt::format("- (no slope {} on the curve)", slope);
  };
  fmt::format_to(out,
                 "  read off the curve: N {} deg/sqrt(h), K {} deg/h/sqrt(h), B = floor/0.664 "
                 "{:.4g} deg/h (floor {:.4g} deg/h at tau {:.3g} s, {})\n",
                 line(r.arw, k * units::deg_rth_per_deg_rts, r.arw_from_tau_s, "-1/2"),
                 line(r.rrw, k * units::dph_rth_per_dps_rts, r.rrw_from_tau_s, "+1/2"),
                 r.bias_instability * k * units::dph_per_dps, r.floor_dev * k * units::dph_per_dps,
                 r.floor_tau_s, r.floor_is_minimum ? "a minimum" : "the curve still falls there");
  for (const auto& n : f.notes)
    if (n.find("not resolved by the data") == std::string::npos)
      fmt::format_to(out, "  note: {}\n", n);
}

// `noise -o FILE.csv`: one row per column and term, in the field's units, with the interval (or
// the upper limit of an unresolved term) and the read-off beside the fit.
std::string terms_csv(const noise_options& o, const std::vector<column_noise>& all) {
  std::string t = "column,term,unit,value,lo,hi,resolved,read_off\n";
  const double k = deg_per_unit(o.in);
  for (const auto& c : all) {
    const auto& f = c.result.terms;
    const auto& r = c.result.readoffs;
    const auto row = [&](const char* term, const char* unit, const analysis::noise_term& x,
                         double to, std::optional<double> read_off) {
      const std::string ro = read_off ? fmt::format("{}", *read_off * to) : "";
      if (x.resolved)
        t += fmt::format("{},{},{},{},{},{},1,{}\n", c.column, term, unit, x.value * to, x.lo * to,
                         x.hi * to, ro);
      else
        t += fmt::format("{},{},{},,,{},0,{}\n", c.column, term, unit, x.hi * to, ro);
    };
    row("arw", "deg/sqrt(h)", f.arw, k * units::deg_rth_per_deg_rts, r.arw);
    row("bias_instability", "deg/h", f.bias_instability, k * units::dph_per_dps,
        r.bias_instability);
    row("rrw", "deg/h/sqrt(h)", f.rrw, k * units::dph_rth_per_dps_rts, r.rrw);
    row("quantization", "deg", f.quantization, k, std::nullopt);
    row("rate_ramp", "deg/h^2", f.rate_ramp, k * units::dph2_per_dps2, std::nullopt);
  }
  return t;
}

// Kalibr takes one value for all axes: the largest of the columns (the conservative choice).
status write_kalibr(const noise_options& o, const std::vector<column_noise>& all) {
  const column_noise* worst_n = &all.front();
  const column_noise* worst_k = &all.front();
  for (const auto& c : all) {
    if (value_or_limit(c.result.terms.arw) > value_or_limit(worst_n->result.terms.arw))
      worst_n = &c;
    if (value_or_limit(c.result.terms.rrw) > value_or_limit(worst_k->result.terms.rrw))
      worst_k = &c;
  }
  analysis::noise_terms f;
  f.arw = worst_n->result.terms.arw;
  f.rrw = worst_k->result.terms.rrw;
  if (!f.arw.resolved || !f.rrw.resolved)
    warn(fmt::format("{}: {} not resolved: the Kalibr file holds its upper limit", o.kalibr,
                     !f.arw.resolved ? "ARW" : "RRW"));
  std::string source = o.in.file;
  if (all.size() > 1)
    source += fmt::format(
        " (largest of columns {}: N from {}, K from {})",
        [&] {
          std::string names;
          for (const auto& c : all) names += (names.empty() ? "" : ",") + c.column;
          return names;
        }(),
        worst_n->column, worst_k->column);
  return io::write_file_atomically(
      o.kalibr,
      kalibr_yaml(source, f, deg_per_unit(o.in) * units::rad_per_deg, 1.0 / all.front().tau0_s));
}

}  // namespace

int run_noise(const noise_options& o) {
  if (o.json)
    if (auto s = check_name_for_json(o.in.file); !s) return report(s.err());
  if (auto s = io::check_outputs(std::array{o.in.file}, std::array{o.kalibr, o.output}); !s)
    return report(s.err());
  // Checked before the files are read.
  const auto range = fit_range(o.fit_taus);
  if (!range) return report(range.err());
  const auto plot = plot_target(o.plot);
  if (!plot) return report(plot.err());
  if (*plot) {
    if (o.plot_units != "deg/h" && o.plot_units != "deg/s" && o.plot_units != "rad/s")
      return report(usage_error("--plot-units must be deg/h, deg/s or rad/s; got " +
                                printable(o.plot_units, 40)));
    // The script and one data file per series (curve, its lines, its long taus) beside the
    // image: none may be an input, nor a file the user changed.
    auto names = column_names(o.in);
    if (!names) return report(names.err());
    const std::size_t series = 7 * names->size();
    const std::array format{(*plot)->format};
    if (auto s =
            io::check_outputs(std::array{o.in.file},
                              report::rendered_files((*plot)->dir, (*plot)->stem, series, format));
        !s)
      return report(s.err());
    if (auto s = report::check_rendered_files((*plot)->dir, (*plot)->stem, series); !s)
      return report(s.err());
  }
  auto inputs = load_series(o.in);
  if (!inputs) return report(inputs.err());
  std::vector<column_noise> all;
  for (const auto& in : *inputs) {
    auto c = noise_of(o, *range, in);
    if (!c) return report(c.err());
    all.push_back(std::move(*c));
  }
  json j;
  if (all.size() == 1) {
    j = io::noise_json(all.front());
  } else {
    j = with_schema("noise_columns", 1, {{"file", o.in.file}, {"columns", json::array()}});
    for (const auto& c : all) j["columns"].push_back(io::noise_json(c));
  }
  // Every output is formatted and checked before the first is written.
  std::string file_text;
  if (!o.output.empty()) {
    auto t = o.output.ends_with(".json") ? finite_dump(j, o.output)
                                         : result<std::string>(terms_csv(o, all));
    if (!t) return report(t.err());
    if (auto s = check_finite(*t, o.output); !s) return report(s.err());
    file_text = o.output.ends_with(".json") ? *t + "\n" : *t;
  }
  if (!o.kalibr.empty())
    if (auto s = write_kalibr(o, all); !s) return report(s.err());
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, file_text); !s) return report(s.err());
  if (*plot) {
    // One curve per column, in deg/s (the figure converts to --plot-units).
    std::vector<report::allan_curve> curves;
    for (const auto& c : all) {
      report::allan_curve curve{c.column, c.result.oadev, c.result.terms, c.result.long_oadev};
      for (auto* v : {&curve.points, &curve.beyond})
        for (auto& p : *v) {
          p.dev *= c.deg_per_unit;
          p.ci_lo *= c.deg_per_unit;
          p.ci_hi *= c.deg_per_unit;
        }
      for (auto* t : {&curve.terms->quantization, &curve.terms->arw, &curve.terms->bias_instability,
                      &curve.terms->rrw, &curve.terms->rate_ramp}) {
        t->value *= c.deg_per_unit;
        t->lo *= c.deg_per_unit;
        t->hi *= c.deg_per_unit;
      }
      curves.push_back(std::move(curve));
    }
    const auto title =
        o.title.empty() ? fmt::format("Allan deviation of {}", printable(o.in.file, 120)) : o.title;
    auto fig = report::noise_figure(curves, o.plot_units, title);
    if (!fig) return report(fig.err());
    const std::array formats{(*plot)->format};
    if (auto s = report::render(*fig, (*plot)->dir, (*plot)->stem, formats); !s)
      return report(s.err());
  }
  if (o.json) {
    if (auto s = print_json(j); !s) return report(s.err());
    return 0;
  }
  std::string text;
  for (const auto& c : all) append_text(text, o, c);
  if (auto s = print_checked(text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
