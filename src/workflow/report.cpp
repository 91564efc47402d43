/// \file
/// \brief The report a lab sends (report.hpp).
#include "gyroflip/workflow/report.hpp"

#include <array>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/parallel.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/core/version.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/schema.hpp"
#include "gyroflip/report/figures.hpp"
#include "gyroflip/report/folder.hpp"
#include "gyroflip/report/page.hpp"
#include "gyroflip/workflow/analyse.hpp"
#include "gyroflip/workflow/compensate.hpp"

namespace gyroflip::workflow {

namespace {

using nlohmann::json;

constexpr std::array formats{report::image_format::png, report::image_format::svg,
                             report::image_format::pdf};

std::string g(double v, int digits = 4) {
  return fmt::format("{:.{}g}", v, digits);
}

std::string term(const analysis::noise_term& t, double to) {
  if (!t.resolved) return "< " + g(t.hi * to, 3);
  return fmt::format("{} [{}, {}]", g(t.value * to, 4), g(t.lo * to, 3), g(t.hi * to, 3));
}

report::table noise_table(const std::vector<run_analysis>& runs) {
  report::table t{
      "IEEE 952 noise terms of the compensated rate (68.3 % intervals; < : upper limit, "
      "not resolved)",
      {"file", "N (°/√h)", "B (°/h)", "K (°/h/√h)", "OADEV floor (°/h) at τ (s)"},
      {}};
  for (const auto& r : runs) {
    if (!r.comp_noise || !noise_fitted(*r.comp_noise)) {
      t.rows.push_back({r.run.file, "-", "-", "-", "series too short"});
      continue;
    }
    const auto& f = r.comp_noise->terms;
    t.rows.push_back({r.run.file, term(f.arw, units::deg_rth_per_deg_rts),
                      term(f.bias_instability, units::dph_per_dps),
                      term(f.rrw, units::dph_rth_per_dps_rts),
                      fmt::format("{} at {}", g(f.bias_floor_dev * units::dph_per_dps, 3),
                                  g(f.bias_floor_tau_s, 3))});
  }
  return t;
}

// The pairing comparison the reader would otherwise misread (docs/METHOD-NOTES.md).
report::section pairing_section(const std::vector<run_analysis>& runs) {
  report::section s;
  s.heading = "Simple and abba pairing";
  s.paragraphs.push_back(
      "The paper pairs each 0° dwell with the next 180° dwell (simple pairing). gyroflip's "
      "default, abba, averages each dwell with both neighbours, which cancels a linear drift "
      "of the bias exactly (the warm-up leak of simple pairing). Abba cycles share dwells, so "
      "neighbouring cycle values are correlated: their per-cycle std is lower than simple "
      "pairing's although the white-noise level at long averaging times is the same. Compare "
      "the paper's per-cycle std with the simple pairing's column; compare long-term stability "
      "with the OADEV at long τ, which is the same for both.");
  report::table t{"Per-cycle statistics of dN = (y₀ − y₁₈₀)/2 by pairing",
                  {"file", "pairing", "cycles", "dN (°/s)", "per-cycle std (°/s)",
                   "correlated stderr (°/s)", "OADEV at longest common τ (°/s)"},
                  {}};
  for (const auto& r : runs)
    for (const auto& p : r.pairings) {
      const auto& c = p.cal;
      const auto& at = p.oadev_at_common_tau;
      t.rows.push_back({r.run.file,
                        p.pairing == method::pairing::simple ? "simple (paper)" : "abba",
                        std::to_string(c.cycles), g(c.delta_n_dps, 6), g(c.std_dps, 3),
                        g(c.stderr_correlated_dps, 3),
                        at ? fmt::format("{} at {} s", g(at->dev, 3), g(at->tau_s, 3)) : "-"});
    }
  s.tables.push_back(std::move(t));
  return s;
}

// Renders `f` as figures/STEM.{png,svg,pdf} in `dir` and returns its reference.
result<report::figure_ref> draw(const report::figure& f, const std::string& dir,
                                const std::string& stem, const std::string& caption) {
  if (auto s = report::render(f, dir + "/figures", stem, formats); !s) return s.err();
  return report::figure_ref{f.title, "figures/" + stem + ".png", "figures/" + stem + ".pdf",
                            caption};
}

std::string stem_of(std::size_t k, const char* what) {
  return fmt::format("run{}_{}", k + 1, what);
}

json run_json(const run_analysis& r, const std::string& sum) {
  const auto& s = r.comp.summary;
  json j = {{"file", r.run.file},
            {"sha256", sum},
            {"cycles", r.cal.cycles},
            {"temp_c", std::isnan(r.cal.temp_c) ? json(nullptr) : json(r.cal.temp_c)},
            {"delta_n_dps", r.cal.delta_n_dps},
            {"std_dps", r.cal.std_dps},
            {"stderr_dps", r.cal.stderr_dps},
            {"stderr_correlated_dps", r.cal.stderr_correlated_dps},
            {"compensated",
             {{"mean_dps", s.mean_dps},
              {"std_dps", s.std_dps},
              {"stderr_correlated_dps", s.stderr_correlated_dps},
              {"drift_dps", s.drift_dps ? json(*s.drift_dps) : json(nullptr)},
              {"drift_window_s", s.drift_window_s}}}};
  if (r.comp_noise && noise_fitted(*r.comp_noise)) {
    const auto& f = r.comp_noise->terms;
    const auto v = [](const analysis::noise_term& t, double to) {
      return t.resolved ? json(t.value * to) : json(nullptr);
    };
    j["noise"] = {{"arw_deg_rth", v(f.arw, units::deg_rth_per_deg_rts)},
                  {"bias_instability_deg_h", v(f.bias_instability, units::dph_per_dps)},
                  {"rrw_deg_h_rth", v(f.rrw, units::dph_rth_per_dps_rts)}};
  }
  return j;
}

}  // namespace

result<report_result> make_report(const report_request& r, const progress_fn& on_progress) {
  if (r.files.empty()) return usage_error("no recording to report on");
  if (auto s = io::check_distinct_inputs(r.files); !s) return s.err();
  std::vector<std::string> inputs = r.files;
  if (!r.calibration.empty()) inputs.push_back(r.calibration);
  // The folder is checked (and its staging folder made) before any work.
  auto folder = report::report_folder::make(r.output, inputs);
  if (!folder) return folder.err();
  const std::string& staging = folder->path();  // removed with `folder` unless published
  report_result out;
  std::optional<delta_n_source> given;
  if (!r.calibration.empty()) {
    auto dn = delta_n_of_file(r.calibration);
    if (!dn) return dn.err();
    given = std::move(*dn);
  }

  std::vector<run_analysis> runs;
  for (std::size_t k = 0; k < r.files.size(); ++k) {
    auto run = read_run(r.files[k]);
    if (!run) return run.err();
    for (const auto& w : run->warnings) out.warnings.push_back(w);
    auto a = analyse_run(std::move(*run), r.pairing);
    if (!a) return a.err();
    runs.push_back(std::move(*a));
    if (on_progress) on_progress(k + 1, 2 * r.files.size() + 1);
  }
  // Calibration report: each run compensated with its own dN (residuals about zero), the runs'
  // dN and, over a temperature span, dN(T). With a calibration: its dN or dN(T).
  std::vector<io::calibration_entry> entries;
  entries.reserve(runs.size());
  for (const auto& a : runs) entries.push_back({a.run.file, a.cal});
  std::optional<method::delta_n_model> model;
  if (given) {
    model = given->model;
  } else if (auto m = io::fit_runs_model(entries); m && *m && (*m)->degree() > 0) {
    model = std::move(**m);  // calibrate's rule; runs at one temperature get no dN(T)
  }
  for (auto& a : runs)
    if (auto s = compensate_run(a, given ? *model : method::constant_model(a.cal.delta_n_dps)); !s)
      return s.err();

  report::page page;
  page.title = r.title.empty() ? (given ? "Compensated gyro runs" : "Calibration of dN") : r.title;
  page.version = std::string(version());
  page.command = r.command;
  std::vector<std::string> sums;
  for (const auto& f : inputs) {
    auto sum = report::sha256_file(f);
    if (!sum) return sum.err();
    page.inputs.emplace_back(f, *sum);
    sums.push_back(*sum);
  }

  // Summary tables.
  report::section summary;
  summary.heading = given ? "Compensation" : "dN and its parts";
  if (given) {
    summary.paragraphs.push_back(
        fmt::format("Compensated with {} (pairing {}): w = r − ΔN per cycle (paper eqn 12).",
                    r.calibration, method::to_string(r.pairing)));
  } else {
    summary.paragraphs.push_back(fmt::format(
        "dN = mean of r = (y₀ − y₁₈₀)/2 over the cycles of each stationary run (paper eqns "
        "8–11), pairing {}. The correlated standard error accounts for the cycles' correlation "
        "(the naive std/√n understates it when the noise is not white).",
        method::to_string(r.pairing)));
  }
  report::table runs_t{
      "Per run",
      {"file", "T (°C)", "cycles", "dN (°/s)", "stderr (°/s)", "correlated stderr (°/s)",
       "compensated mean (°/s)", "its correlated stderr (°/s)", "std (°/s)", "drift (°/s)"},
      {}};
  for (const auto& a : runs) {
    const auto& s = a.comp.summary;
    runs_t.rows.push_back({a.run.file, std::isnan(a.cal.temp_c) ? "-" : g(a.cal.temp_c, 3),
                           std::to_string(a.cal.cycles), g(a.cal.delta_n_dps, 6),
                           g(a.cal.stderr_dps, 3), g(a.cal.stderr_correlated_dps, 3),
                           g(s.mean_dps, 3), g(s.stderr_correlated_dps, 3), g(s.std_dps, 3),
                           s.drift_dps ? g(*s.drift_dps, 3) : "-"});
  }
  summary.tables.push_back(runs_t);
  if (r.geometry) {
    report::table split{
        fmt::format("dN split at {}° latitude (paper eqns 9–10)", r.geometry->lat_deg),
        {"file", "dN (°/s)", "Earth term (°/s)", "g-term (°/s)"},
        {}};
    for (const auto& a : runs) {
      const auto s =
          method::split_delta_n(a.cal.delta_n_dps, r.geometry->lat_deg, r.geometry->axis);
      split.rows.push_back(
          {a.run.file, g(a.cal.delta_n_dps, 6), g(s.earth_rate_dps, 6), g(s.g_term_dps, 6)});
    }
    summary.tables.push_back(split);
  }
  if (model && model->degree() > 0) {
    report::table m{fmt::format("ΔN(T) = Σ c_k (T − {:.2f} °C)^k, {:.1f}–{:.1f} °C", model->t_ref_c,
                                model->temp_min_c, model->temp_max_c),
                    {"k", "c_k (°/s per °C^k)", "standard error"},
                    {}};
    const std::size_t n = model->coeffs_dps.size();
    for (std::size_t k = 0; k < n; ++k)
      m.rows.push_back(
          {std::to_string(k), g(model->coeffs_dps[k], 6), g(std::sqrt(model->cov[k * n + k]), 3)});
    summary.tables.push_back(m);
  }
  summary.tables.push_back(noise_table(runs));
  if (!given && runs.size() > 1) {
    auto f = draw(report::delta_n_runs_figure(entries, "ΔN per run"), staging, "delta_n_runs",
                  "the paper's Tab. 3/4 as a figure");
    if (!f) return f.err();
    summary.figures.push_back(*f);
  }
  if (model && model->degree() > 0) {
    auto f = draw(report::delta_n_temperature_figure(entries, *model, "ΔN against temperature"),
                  staging, "delta_n_temperature", "");
    if (!f) return f.err();
    summary.figures.push_back(*f);
  }
  page.sections.push_back(std::move(summary));
  page.sections.push_back(pairing_section(runs));

  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& a = runs[k];
    report::section s;
    s.heading = a.run.file;
    const auto add = [&](const report::figure& fig, const char* what,
                         const std::string& caption) -> status {
      auto f = draw(fig, staging, stem_of(k, what), caption);
      if (!f) return f.err();
      s.figures.push_back(*f);
      return ok();
    };
    std::vector<report::allan_curve> curves;
    if (a.raw_noise) curves.push_back({"raw: dwell means at 0°", a.raw_noise->oadev, std::nullopt});
    if (a.comp_noise)
      curves.push_back(
          {"compensated (" + std::string(method::to_string(a.pairing)) + " cycles)",
           a.comp_noise->oadev,
           noise_fitted(*a.comp_noise) ? std::optional(a.comp_noise->terms) : std::nullopt});
    for (const auto& st :
         {add(report::dwell_figure(a.run.dwells, "Output at 0° and 180°"), "dwells",
              "the paper's Figs 3/5/7/9"),
          add(report::compensated_figure(a.comp.cycles, a.comp.summary, "Compensated output"),
              "compensated", "the paper's Figs 4/6/8/10"),
          add(report::bias_figure(a.run.cycles(a.pairing), "Bias estimate c(t)"), "bias", ""),
          curves.empty() ? ok()
                         : add(report::allan_figure(curves, "°/s", "Allan deviation"), "allan",
                               "68.3 % bounds; dashed: the fitted IEEE 952 terms")})
      if (!st) return st.err();
    page.sections.push_back(std::move(s));
    if (on_progress) on_progress(r.files.size() + k + 1, 2 * r.files.size() + 1);
  }
  for (const auto& s : page.sections) out.figures += s.figures.size();

  json sj = io::schema_object("report", 1);
  sj.update(json{{"command", page.command},
                 {"mode", given ? "compensation" : "calibration"},
                 {"pairing", method::to_string(r.pairing)},
                 {"runs", json::array()}});
  for (std::size_t k = 0; k < runs.size(); ++k) sj["runs"].push_back(run_json(runs[k], sums[k]));
  if (model)
    sj["delta_n_model"] = {{"coeffs_dps", model->coeffs_dps},
                           {"t_ref_c", model->t_ref_c},
                           {"degree", model->degree()}};
  auto summary_text = io::finite_dump(sj, r.output + "/summary.json");
  if (!summary_text) return summary_text.err();
  auto page_text = report::html(page, staging);
  if (!page_text) return page_text.err();
  for (const auto& [name, text] :
       {std::pair{"summary.json", *summary_text + "\n"}, std::pair{"index.html", *page_text}})
    if (auto s = io::write_file_atomically(staging + "/" + name, text); !s) return s.err();
  if (auto s = report::print_pdf(page, staging); !s) return s.err();
  if (auto s = folder->publish(fmt::format("{} {}", r.made_by, version())); !s) return s.err();
  out.summary_json = *summary_text;
  if (on_progress) on_progress(2 * r.files.size() + 1, 2 * r.files.size() + 1);
  return out;
}

}  // namespace gyroflip::workflow
