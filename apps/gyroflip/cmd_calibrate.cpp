/// \file
/// \brief `gyroflip calibrate`: dN from stationary recordings (paper eqns 8-11), its Earth and
/// g terms, and a dN(T) model when recordings at several temperatures are given.
#include <array>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "command_line.hpp"
#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/workflow/calibrate.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {
namespace {

void print_entry(std::string& out, const io::calibration_entry& e,
                 const std::optional<io::calibration_geometry>& g) {
  const auto& c = e.cal;
  fmt::format_to(std::back_inserter(out), "{}: {} cycles over {:.0f} s", e.file, c.cycles,
                 c.duration_s);
  if (!std::isnan(c.temp_c)) fmt::format_to(std::back_inserter(out), ", {:.2f} degC", c.temp_c);
  fmt::format_to(std::back_inserter(out),
                 "\n  dN = {:.6e} deg/s   std {:.3e}   stderr {:.3e} (naive) {:.3e} (correlated)\n",
                 c.delta_n_dps, c.std_dps, c.stderr_dps, c.stderr_correlated_dps);
  fmt::format_to(std::back_inserter(out), "  bias (half-sum) mean {:.6e} deg/s\n", c.bias_mean_dps);
  if (g) {
    const auto s = method::split_delta_n(c.delta_n_dps, g->lat_deg, g->axis);
    fmt::format_to(std::back_inserter(out), "  Earth term {:.6e} deg/s   g term {:.6e} deg/s\n",
                   s.earth_rate_dps, s.g_term_dps);
  }
}

std::string summary_text(const io::calibration_record& rec) {
  std::string out;
  fmt::format_to(std::back_inserter(out), "pairing: {}\n", method::to_string(rec.pairing));
  for (const auto& f : rec.files) print_entry(out, f, rec.geometry);
  if (rec.files.size() > 1) print_entry(out, {"all files", rec.pooled, std::nullopt}, rec.geometry);
  if (rec.model) {
    const auto& m = *rec.model;
    if (m.degree() == 0) {
      fmt::format_to(std::back_inserter(out),
                     "dN over {} runs (weighted mean) = {:.6e} +- {:.3e} deg/s, chi2/dof {:.3g}\n",
                     rec.files.size(), m.coeffs_dps[0], m.stderr_at(0.0), m.chi2_per_dof);
    } else {
      fmt::format_to(
          std::back_inserter(out),
          "dN(T) = sum c_k (T - {:.2f})^k, c = [{:.6e}], fitted over {:.1f}..{:.1f} degC, chi2/dof "
          "{:.3g}\n",
          m.t_ref_c, fmt::join(m.coeffs_dps, ", "), m.temp_min_c, m.temp_max_c, m.chi2_per_dof);
    }
  }
  return out;
}

}  // namespace

int run_calibrate(const calibrate_options& o) {
  const auto pairing = method::parse_pairing(o.pairing);
  if (!pairing) return report(usage_error("--pairing must be abba or simple"));
  auto geometry = geometry_option(o.lat_deg, o.axis);
  if (!geometry) return report(geometry.err());
  if (auto s = io::check_outputs(o.files, std::array{o.output}); !s) return report(s.err());
  workflow::calibrate_request req;
  req.files = o.files;
  req.pairing = *pairing;
  req.angle_tolerance_deg = o.angle_tolerance_deg;
  req.geometry = *geometry;
  if (o.degree_given) req.degree = o.degree;
  progress bar("calibrate", 1000);
  auto res = workflow::calibrate_runs(req, per_mille(bar));
  bar.finish();
  if (!res) return report(res.err());
  for (const auto& w : res->warnings) warn(w);
  const auto& rec = res->record;
  // Formatted and checked (every number finite) before anything is written.
  const auto text = io::to_json(rec);
  if (!text) return report(text.err());
  const std::string summary = o.json ? *text + "\n" : summary_text(rec);
  if (auto s = check_finite(summary, "<stdout>"); !s) return report(s.err());
  if (!o.output.empty())
    if (auto s = io::write_file_atomically(o.output, *text + "\n"); !s) return report(s.err());
  fmt::print("{}", summary);
  return 0;
}

}  // namespace gyroflip::app
