/// \file
/// \brief `gyroflip report FILE... -o DIR`: calibrates (or, with --calibration, compensates) the
/// recordings, analyses them, draws the paper's figures and the Allan plot, and writes one page
/// a person would send (DIR/index.html), the figures with their gnuplot scripts
/// (DIR/figures/), DIR/summary.json and DIR/report.pdf (docs/REPORT.md).
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/compensation.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/method/dwells.hpp"
#include "gyroflip/report/figures.hpp"
#include "gyroflip/report/page.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "report_folder.hpp"

namespace gyroflip::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr std::array formats{report::image_format::png, report::image_format::svg,
                             report::image_format::pdf};

// One recording, read and analysed.
struct run_data {
  std::string file;
  std::vector<method::dwell> dwells;
  std::vector<method::cycle> cycles;         // with the chosen pairing
  std::vector<method::cycle> simple_cycles;  // with the paper's pairing, for the comparison
  std::vector<method::cycle> abba_cycles;
  method::calibration cal;  // of the chosen pairing's cycles
  std::vector<method::compensated_cycle> compensated;
  method::compensation_summary summary;
  std::optional<analysis::noise_analysis> raw_noise, comp_noise;
};

std::string g(double v, int digits = 4) {
  return fmt::format("{:.{}g}", v, digits);
}

// The mean spacing of a series' stamps (s).
double mean_step(const std::vector<double>& t) {
  return t.size() > 1 ? (t.back() - t.front()) / static_cast<double>(t.size() - 1) : 1.0;
}

// OADEV with bounds and the IEEE 952 fit of `y` spaced `tau0_s`, or nothing when the series is
// too short for it (the report then shows what it has).
std::optional<analysis::noise_analysis> noise_of(const std::vector<double>& y, double tau0_s,
                                                 double abba_cycle_s) {
  if (y.size() < 16 || !(tau0_s > 0.0)) return std::nullopt;
  const analysis::span_samples s(y);
  auto x = analysis::phase_source::make(s, analysis::input_kind::rate, tau0_s);
  if (!x) return std::nullopt;
  analysis::noise_series ns;
  ns.abba_cycle_s = abba_cycle_s;
  auto a = analysis::analyse_noise(*x, 0.683, {}, ns);
  if (a) return std::move(*a);
  // Too few points to fit: the curve alone.
  auto pts = analysis::deviation(analysis::dev_kind::oadev, *x, {});
  if (!pts) return std::nullopt;
  analysis::add_confidence(*pts, analysis::dev_kind::oadev, *x, 0.683);
  analysis::noise_analysis only;
  only.oadev = std::move(*pts);
  only.terms.chi2_per_dof = -1.0;  // marks "not fitted"
  return only;
}

bool fitted(const analysis::noise_analysis& a) {
  return a.terms.chi2_per_dof >= 0.0;
}

result<run_data> read_run(const std::string& file, method::pairing p) {
  auto rr = rigdata::read_recording_rows(file);
  if (!rr) return rr.err();
  for (const auto& w : rr->warnings) warn(w);
  run_data r;
  r.file = file;
  r.dwells = method::extract_dwells(rr->rows);
  auto cyc = [&](method::pairing q) -> result<std::vector<method::cycle>> {
    auto c = io::cycles_of_rows(file, rr->rows, q, rr->metadata);
    if (!c) return c.err();
    return std::move(c->cycles);
  };
  auto simple = cyc(method::pairing::simple);
  if (!simple) return simple.err();
  auto abba = cyc(method::pairing::abba);
  if (!abba) return abba.err();
  r.simple_cycles = std::move(*simple);
  r.abba_cycles = std::move(*abba);
  r.cycles = p == method::pairing::abba ? r.abba_cycles : r.simple_cycles;
  auto cal = method::calibrate(r.cycles);
  if (!cal) return input_error({file}, cal.err().message);
  r.cal = *cal;
  return r;
}

void analyse(run_data& r, const method::delta_n_model& model, method::pairing p) {
  r.compensated.clear();
  for (const auto& c : r.cycles) r.compensated.push_back(method::compensate(c, model));
  r.summary = method::summarize(r.compensated);
  std::vector<double> t, y, t0, y0;
  for (const auto& c : r.compensated) {
    t.push_back(c.time_s);
    y.push_back(c.rate_dps);
  }
  // The raw sensor: its dwell means at 0 deg, one per cycle (what a fixed sensor would give).
  for (const auto& d : r.dwells)
    if (d.sign > 0) {
      t0.push_back(d.time_s);
      y0.push_back(d.rate_dps);
    }
  const double tc = mean_step(t);
  r.comp_noise = noise_of(y, tc, p == method::pairing::abba ? tc : 0.0);
  r.raw_noise = noise_of(y0, mean_step(t0), 0.0);
}

std::string term(const analysis::noise_term& t, double to) {
  if (!t.resolved) return "< " + g(t.hi * to, 3);
  return fmt::format("{} [{}, {}]", g(t.value * to, 4), g(t.lo * to, 3), g(t.hi * to, 3));
}

report::table noise_table(const std::vector<run_data>& runs) {
  report::table t{
      "IEEE 952 noise terms of the compensated rate (68.3 % intervals; < : upper limit, "
      "not resolved)",
      {"file", "N (°/√h)", "B (°/h)", "K (°/h/√h)", "OADEV floor (°/h) at τ (s)"},
      {}};
  for (const auto& r : runs) {
    if (!r.comp_noise || !fitted(*r.comp_noise)) {
      t.rows.push_back({r.file, "-", "-", "-", "series too short"});
      continue;
    }
    const auto& f = r.comp_noise->terms;
    t.rows.push_back({r.file, term(f.arw, units::deg_rth_per_deg_rts),
                      term(f.bias_instability, units::dph_per_dps),
                      term(f.rrw, units::dph_rth_per_dps_rts),
                      fmt::format("{} at {}", g(f.bias_floor_dev * units::dph_per_dps, 3),
                                  g(f.bias_floor_tau_s, 3))});
  }
  return t;
}

// The pairing comparison the reader would otherwise misread (docs/METHOD-NOTES.md).
report::section pairing_section(const std::vector<run_data>& runs) {
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
  for (const auto& r : runs) {
    std::vector<std::pair<const char*, const std::vector<method::cycle>*>> both{
        {"simple (paper)", &r.simple_cycles}, {"abba", &r.abba_cycles}};
    std::vector<std::vector<analysis::deviation_point>> curves;
    double tau = 1e300;
    for (const auto& [name, cycles] : both) {
      std::vector<double> y, stamps;
      for (const auto& c : *cycles) {
        y.push_back(c.rate_dps);
        stamps.push_back(c.time_s);
      }
      auto pts = analysis::deviation(analysis::dev_kind::oadev, y, analysis::input_kind::rate,
                                     mean_step(stamps), {});
      // The longest tau both pairings reach.
      tau = std::min(tau, pts && !pts->empty() ? pts->back().tau_s : 0.0);
      curves.push_back(pts ? *pts : std::vector<analysis::deviation_point>{});
    }
    for (std::size_t k = 0; k < both.size(); ++k) {
      auto cal = method::calibrate(*both[k].second);
      if (!cal) continue;
      std::string at = "-";
      for (const auto& p : curves[k])
        if (p.tau_s <= tau * 1.5) at = fmt::format("{} at {} s", g(p.dev, 3), g(p.tau_s, 3));
      t.rows.push_back({r.file, both[k].first, std::to_string(cal->cycles), g(cal->delta_n_dps, 6),
                        g(cal->std_dps, 3), g(cal->stderr_correlated_dps, 3), at});
    }
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

json run_json(const run_data& r, const std::string& sum) {
  json j = {{"file", r.file},
            {"sha256", sum},
            {"cycles", r.cal.cycles},
            {"temp_c", std::isnan(r.cal.temp_c) ? json(nullptr) : json(r.cal.temp_c)},
            {"delta_n_dps", r.cal.delta_n_dps},
            {"std_dps", r.cal.std_dps},
            {"stderr_dps", r.cal.stderr_dps},
            {"stderr_correlated_dps", r.cal.stderr_correlated_dps},
            {"compensated",
             {{"mean_dps", r.summary.mean_dps},
              {"std_dps", r.summary.std_dps},
              {"stderr_correlated_dps", r.summary.stderr_correlated_dps},
              {"drift_dps", r.summary.drift_dps ? json(*r.summary.drift_dps) : json(nullptr)},
              {"drift_window_s", r.summary.drift_window_s}}}};
  if (r.comp_noise && fitted(*r.comp_noise)) {
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

int run_report(const report_options& o) {
  const auto pairing = method::parse_pairing(o.pairing);
  if (!pairing) return report(usage_error("--pairing must be abba or simple"));
  if (std::isnan(o.lat_deg) != o.axis.empty())
    return report(usage_error("--latitude and --axis go together"));
  std::optional<earth::ned_vector> axis;
  if (!o.axis.empty()) {
    if (auto s = earth::check_latitude(o.lat_deg); !s) return report(s.err());
    auto a = earth::parse_axis(o.axis);
    if (!a) return report(a.err());
    axis = *a;
  }
  if (auto s = io::check_distinct_inputs(o.files); !s) return report(s.err());
  std::vector<std::string> inputs = o.files;
  if (!o.calibration.empty()) inputs.push_back(o.calibration);
  if (auto s = io::check_outputs(inputs, std::array{o.output}); !s) return report(s.err());
  // The folder is checked (and its staging folder made) before any work.
  auto folder = report_folder::make(o.output, inputs);
  if (!folder) return report(folder.err());
  const std::string& staging = folder->path();  // removed with `folder` unless published
  std::optional<io::calibration_record> given;
  if (!o.calibration.empty()) {
    auto rec = io::read_calibration_file(o.calibration);
    if (!rec) return report(rec.err());
    given = std::move(*rec);
  }

  std::vector<run_data> runs;
  for (const auto& f : o.files) {
    auto r = read_run(f, *pairing);
    if (!r) return report(r.err());
    runs.push_back(std::move(*r));
  }
  // Calibration report: each run compensated with its own dN (residuals about zero), the runs'
  // dN and, over a temperature span, dN(T). With a calibration: its dN or dN(T).
  std::vector<io::calibration_entry> entries;
  entries.reserve(runs.size());
  for (const auto& r : runs) entries.push_back({r.file, r.cal});
  std::optional<method::delta_n_model> model;
  if (given) {
    model = io::delta_n_model_of(*given);
  } else if (auto m = io::fit_runs_model(entries); m && *m && (*m)->degree() > 0) {
    model = std::move(**m);  // calibrate's rule; runs at one temperature get no dN(T)
  }
  for (auto& r : runs)
    analyse(r, given ? *model : method::constant_model(r.cal.delta_n_dps), *pairing);

  const auto fail = [&](const error& e) { return report(e); };

  report::page page;
  page.title = o.title.empty() ? (given ? "Compensated gyro runs" : "Calibration of dN") : o.title;
  page.version = GYROFLIP_VERSION;
  for (const auto& a : o.command_line) page.command += (page.command.empty() ? "" : " ") + a;
  std::vector<std::string> sums;
  for (const auto& f : inputs) {
    auto sum = report::sha256_file(f);
    if (!sum) return fail(sum.err());
    page.inputs.emplace_back(f, *sum);
    sums.push_back(*sum);
  }

  // Summary tables.
  report::section summary;
  summary.heading = given ? "Compensation" : "dN and its parts";
  if (given) {
    summary.paragraphs.push_back(
        fmt::format("Compensated with {} (pairing {}): w = r − ΔN per cycle (paper eqn 12).",
                    o.calibration, method::to_string(*pairing)));
  } else {
    summary.paragraphs.push_back(fmt::format(
        "dN = mean of r = (y₀ − y₁₈₀)/2 over the cycles of each stationary run (paper eqns "
        "8–11), pairing {}. The correlated standard error accounts for the cycles' correlation "
        "(the naive std/√n understates it when the noise is not white).",
        method::to_string(*pairing)));
  }
  report::table runs_t{
      "Per run",
      {"file", "T (°C)", "cycles", "dN (°/s)", "stderr (°/s)", "correlated stderr (°/s)",
       "compensated mean (°/s)", "its correlated stderr (°/s)", "std (°/s)", "drift (°/s)"},
      {}};
  for (const auto& r : runs)
    runs_t.rows.push_back(
        {r.file, std::isnan(r.cal.temp_c) ? "-" : g(r.cal.temp_c, 3), std::to_string(r.cal.cycles),
         g(r.cal.delta_n_dps, 6), g(r.cal.stderr_dps, 3), g(r.cal.stderr_correlated_dps, 3),
         g(r.summary.mean_dps, 3), g(r.summary.stderr_correlated_dps, 3), g(r.summary.std_dps, 3),
         r.summary.drift_dps ? g(*r.summary.drift_dps, 3) : "-"});
  summary.tables.push_back(runs_t);
  if (axis) {
    report::table split{fmt::format("dN split at {}° latitude (paper eqns 9–10)", o.lat_deg),
                        {"file", "dN (°/s)", "Earth term (°/s)", "g-term (°/s)"},
                        {}};
    for (const auto& r : runs) {
      const auto s = method::split_delta_n(r.cal.delta_n_dps, o.lat_deg, *axis);
      split.rows.push_back(
          {r.file, g(r.cal.delta_n_dps, 6), g(s.earth_rate_dps, 6), g(s.g_term_dps, 6)});
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
    if (!f) return fail(f.err());
    summary.figures.push_back(*f);
  }
  if (model && model->degree() > 0) {
    auto f = draw(report::delta_n_temperature_figure(entries, *model, "ΔN against temperature"),
                  staging, "delta_n_temperature", "");
    if (!f) return fail(f.err());
    summary.figures.push_back(*f);
  }
  page.sections.push_back(std::move(summary));
  page.sections.push_back(pairing_section(runs));

  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& r = runs[k];
    report::section s;
    s.heading = r.file;
    const auto add = [&](const report::figure& fig, const char* what,
                         const std::string& caption) -> status {
      auto f = draw(fig, staging, stem_of(k, what), caption);
      if (!f) return f.err();
      s.figures.push_back(*f);
      return ok();
    };
    std::vector<report::allan_curve> curves;
    if (r.raw_noise) curves.push_back({"raw: dwell means at 0°", r.raw_noise->oadev, std::nullopt});
    if (r.comp_noise)
      curves.push_back({"compensated (" + std::string(method::to_string(*pairing)) + " cycles)",
                        r.comp_noise->oadev,
                        fitted(*r.comp_noise) ? std::optional(r.comp_noise->terms) : std::nullopt});
    for (const auto& st :
         {add(report::dwell_figure(r.dwells, "Output at 0° and 180°"), "dwells",
              "the paper's Figs 3/5/7/9"),
          add(report::compensated_figure(r.compensated, r.summary, "Compensated output"),
              "compensated", "the paper's Figs 4/6/8/10"),
          add(report::bias_figure(r.cycles, "Bias estimate c(t)"), "bias", ""),
          curves.empty() ? ok()
                         : add(report::allan_figure(curves, "°/s", "Allan deviation"), "allan",
                               "68.3 % bounds; dashed: the fitted IEEE 952 terms")})
      if (!st) return fail(st.err());
    page.sections.push_back(std::move(s));
  }

  json sj = {{"schema", "gyroflip.report/1"},
             {"version", GYROFLIP_VERSION},
             {"command", page.command},
             {"mode", given ? "compensation" : "calibration"},
             {"pairing", method::to_string(*pairing)},
             {"runs", json::array()}};
  for (std::size_t k = 0; k < runs.size(); ++k) sj["runs"].push_back(run_json(runs[k], sums[k]));
  if (model)
    sj["delta_n_model"] = {{"coeffs_dps", model->coeffs_dps},
                           {"t_ref_c", model->t_ref_c},
                           {"degree", model->degree()}};
  auto summary_text = finite_dump(sj, o.output + "/summary.json");
  if (!summary_text) return fail(summary_text.err());
  auto page_text = report::html(page, staging);
  if (!page_text) return fail(page_text.err());
  for (const auto& [name, text] :
       {std::pair{"summary.json", *summary_text + "\n"}, std::pair{"index.html", *page_text}})
    if (auto s = io::write_file_atomically(staging + "/" + name, text); !s) return fail(s.err());
  if (auto s = report::print_pdf(page, staging); !s) return fail(s.err());
  if (auto s = folder->publish("gyroflip report " GYROFLIP_VERSION); !s) return fail(s.err());
  fmt::print(
      "{}: index.html, report.pdf, summary.json and {} figures (PNG, SVG, PDF with their "
      "gnuplot scripts in figures/)\n",
      o.output, 4 * runs.size());
  return 0;
}

}  // namespace gyroflip::app
