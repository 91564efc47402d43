/// \file
/// \brief `gyroflip compensate`: paper eqn 12 per cycle, w_in = r - dN(T).
#include <array>
#include <cmath>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/digits.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/recording_writer.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/workflow/compensate.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

std::string format_value(double v) {
  return std::isnan(v) ? std::string() : fmt::format("{}", v);
}

status write_csv(const std::string& path, const std::vector<method::compensated_cycle>& out,
                 const compensate_options& o, method::pairing p) {
  auto f = io::atomic_file::create(path);
  if (!f) return f.err();
  // The header first (scripts read line 1), then what made the series as metadata: `gyroflip
  // noise` reads `pairing` to model the abba pairing's correlated cycles.
  std::string head = "time_s,rate_dps,bias_dps,temp_c,delta_n_dps\n";
  io::append_metadata(head, std::vector<io::csv_metadata>{
                                {"gyroflip compensate", "one row per cycle (paper eqn 12)"},
                                {"version", GYROFLIP_VERSION},
                                {"source", o.file},
                                {"pairing", std::string(method::to_string(p))},
                                {"delta_n", o.calibration.empty() ? fmt::format("{}", o.delta_n_dps)
                                                                  : o.calibration}});
  f->write(head);
  fmt::memory_buffer buf;
  for (const auto& c : out) {
    fmt::format_to(std::back_inserter(buf), "{},{},{},{},{}\n", c.time_s, c.rate_dps, c.bias_dps,
                   format_value(c.temp_c), c.delta_n_dps);
    if (buf.size() > (1u << 16)) {
      if (auto s = check_finite({buf.data(), buf.size()}, path); !s) return s;
      f->write({buf.data(), buf.size()});
      buf.clear();
    }
  }
  if (auto s = check_finite({buf.data(), buf.size()}, path); !s) return s;
  f->write({buf.data(), buf.size()});
  return f->commit();
}

}  // namespace

int run_compensate(const compensate_options& o) {
  if (auto s = io::check_outputs(std::array{o.file, o.calibration}, std::array{o.output}); !s)
    return report(s.err());
  if (o.json)
    if (auto s = check_name_for_json(o.file); !s) return report(s.err());
  auto dn = o.calibration.empty() ? workflow::delta_n_of_value(o.delta_n_dps)
                                  : workflow::delta_n_of_file(o.calibration);
  if (!dn) return report(dn.err());
  if (o.calibration.empty()) dn->source = "--delta-n";
  workflow::compensate_request req{
      o.file, std::move(*dn), std::nullopt, o.angle_tolerance_deg, o.drift_window_s, o.strict};
  if (!o.pairing.empty()) {
    req.pairing = method::parse_pairing(o.pairing);
    if (!req.pairing)
      return report(usage_error("--pairing must be " + method::scheme_names_joined(" or ")));
  }
  progress bar("reading " + o.file, 1000);
  auto res = workflow::compensate_file(req, per_mille(bar));
  bar.finish();
  if (!res) return report(res.err());
  for (const auto& w : res->warnings) warn(w);
  const auto& comp = res->comp;
  const auto& summary = comp.summary;

  // Every number is checked before anything is written (the workflow checked the rows and the
  // summary; the text below is checked too), so stdout gets no partial table.
  std::string summary_text;
  // A harmonic calibration (issue 33): the dN its terms give for this run (the pair's) is the
  // one subtracted and stated.
  auto applied = req.delta_n;
  if (res->applied) {
    applied.model = res->applied->model;
    std::string terms;
    for (const auto& t : res->applied->terms)
      terms += fmt::format(" {} {}", t.name, significant(t.value_dps, 4));
    note(fmt::format("{}: the calibration's harmonic terms ({} deg/s) applied {}", o.calibration,
                     terms.substr(1), res->applied->how));
  }
  if (o.json) {
    auto t = finite_dump(workflow::compensation_json(comp, o.file, applied, res->pairing, *res),
                         "<stdout>");
    if (!t) return report(t.err());
    summary_text = *t + "\n";
  } else if (!o.output.empty()) {
    summary_text = fmt::format(
        "{}: {} cycles, mean {} deg/s, std {}, stderr {} (correlated), drift {} over "
        "{} s\n",
        // The mean with the digits its error supports (third review of issue 31, M4:
        // "4.999999e-01"); full digits in --json and the CSV.
        o.file, summary.cycles, to_digits_of(summary.mean_dps, summary.stderr_correlated_dps, 4),
        significant(summary.std_dps, 3), significant(summary.stderr_correlated_dps, 2),
        summary.drift_dps ? fmt::format("{} deg/s", significant(*summary.drift_dps, 3))
                          : std::string("n/a"),
        summary.drift_window_s);
    // Both errors of the mean: the within-run one above, and the ΔN's, common to every cycle
    // (third review of issue 31, M5), as calibrate says to quote it: a new power-up's (fourth
    // review, F2), the calibrated value's beside it. The ratio only where the stderr is not 0 (a
    // run without noise: no ratio to give).
    const auto times_stderr = [&](double u) {
      const double ratio = u / summary.stderr_correlated_dps;
      return std::isfinite(ratio) ? fmt::format(", {} times the stderr", significant(ratio, 2))
                                  : std::string();
    };
    if (std::isfinite(res->new_power_up_dps)) {
      summary_text += fmt::format(
          "  the ΔN subtracted carries ±{} deg/s for a new power-up (68.3 %, the calibration's "
          "quote: its value's own error{} and the run-to-run repeatability){}: the same in every "
          "cycle, so averaging does not reduce it; quote both\n",
          significant(res->new_power_up_dps, 2),
          std::isfinite(res->delta_n_u_dps)
              ? fmt::format(" ±{}", significant(res->delta_n_u_dps, 2))
              : std::string(),
          times_stderr(res->new_power_up_dps));
    } else if (std::isfinite(res->delta_n_u_dps)) {
      summary_text += fmt::format(
          "  the ΔN subtracted has its own error ±{} deg/s (the calibrated value's, 68.3 %){}: the "
          "same in every cycle, so averaging does not reduce it; quote both; {}\n",
          significant(res->delta_n_u_dps, 2), times_stderr(res->delta_n_u_dps),
          res->delta_n_u_note.empty() ? std::string("a new power-up adds its repeatability")
                                      : res->delta_n_u_note);
    } else if (!res->delta_n_u_note.empty()) {
      summary_text += fmt::format("  the ΔN subtracted: its error is {}\n", res->delta_n_u_note);
    }
    if (auto s = check_finite(summary_text, "<stdout>"); !s) return report(s.err());
  }
  if (!o.output.empty() || !o.json)
    if (auto s = write_csv(o.output.empty() ? "-" : o.output, comp.cycles, o, res->pairing); !s)
      return report(s.err());
  fmt::print("{}", summary_text);
  return 0;
}

}  // namespace gyroflip::app
