/// \file
/// \brief Compensate and summarise (compensate.hpp).
#include "gyroflip/workflow/compensate.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/digits.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/schema.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/cycle_print.hpp"
#include "gyroflip/method/runs.hpp"
#include "gyroflip/report/page.hpp"
#include "gyroflip/rigdata/recording_source.hpp"
#include "gyroflip/workflow/calibrate.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip::workflow {

namespace {

delta_n_source of_record(io::calibration_record rec, const std::string& name) {
  auto model = io::delta_n_model_of(rec);
  const auto p = rec.pairing;
  return delta_n_source{std::move(model), name, p, std::move(rec)};
}

double term_value(std::span<const method::delta_n_term> terms, std::string_view name) {
  for (const auto& t : terms)
    if (t.name == name) return t.value_dps;
  return 0.0;
}

// The rows of `inner` with the harmonic terms other than c1 removed at each row's position (the
// c1 part is the dN the blocks' c1 is compensated by: compensate_file).
class terms_removed final : public method::row_source {
 public:
  terms_removed(method::row_source& inner, std::span<const method::delta_n_term> terms)
      : inner_(inner) {
    const double s1 = term_value(terms, "s1"), c2 = term_value(terms, "c2"),
                 s2 = term_value(terms, "s2");
    const auto& table = inner.positions();
    for (int i = 0; i < static_cast<int>(table.size()); ++i) {
      const double a = table.angle_deg(i) * units::rad_per_deg;
      at_.push_back(s1 * std::sin(a) + c2 * std::cos(2.0 * a) + s2 * std::sin(2.0 * a));
    }
  }
  [[nodiscard]] result<std::size_t> read(std::span<method::row> out) override {
    auto n = inner_.read(out);
    if (!n) return n;
    for (std::size_t i = 0; i < *n; ++i) {
      auto& r = out[i];
      if (r.position >= 0 && static_cast<std::size_t>(r.position) < at_.size())
        r.rate_dps -= at_[static_cast<std::size_t>(r.position)];
    }
    return n;
  }
  [[nodiscard]] const std::string& name() const noexcept override { return inner_.name(); }
  [[nodiscard]] const position_table& positions() const noexcept override {
    return inner_.positions();
  }
  [[nodiscard]] bool has_temp() const noexcept override { return inner_.has_temp(); }
  [[nodiscard]] std::span<const metadata_entry> metadata() const noexcept override {
    return inner_.metadata();
  }
  [[nodiscard]] std::span<const std::string> warnings() const noexcept override {
    return inner_.warnings();
  }
  [[nodiscard]] std::uint64_t done() const noexcept override { return inner_.done(); }
  [[nodiscard]] std::uint64_t total() const noexcept override { return inner_.total(); }

 private:
  method::row_source& inner_;
  std::vector<double> at_;
};

// The mean temperature of the cycles that have one; NaN when none has.
double mean_temp_c(std::span<const method::cycle> cycles) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& c : cycles)
    if (std::isfinite(c.temp_c)) {
      sum += c.temp_c;
      ++n;
    }
  return n > 0 ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::optional<std::vector<method::delta_n_term>> harmonic_terms_of(
    const io::calibration_record& rec) {
  if (rec.pairing != method::pairing::harmonic) return std::nullopt;
  std::vector<method::delta_n_term> out;
  for (const auto& t : rec.terms)
    if (t.name == "c1" || t.name == "s1" || t.name == "c2" || t.name == "s2") out.push_back(t);
  const auto has = [&out](std::string_view n) {
    return std::any_of(out.begin(), out.end(), [n](const auto& t) { return t.name == n; });
  };
  if (!has("c1") || !has("s1")) return std::nullopt;
  return out;
}

method::delta_n_model pair_model_of(const method::delta_n_model& c1_model,
                                    std::span<const method::delta_n_term> terms, double plus_deg) {
  const double a = plus_deg * units::rad_per_deg;
  const double c = std::cos(a), s = std::sin(a);
  method::delta_n_model m = c1_model;
  for (double& k : m.coeffs_dps) k *= c;
  if (m.coeffs_dps.empty()) m.coeffs_dps.push_back(0.0);
  m.coeffs_dps.front() += term_value(terms, "s1") * s;
  for (double& v : m.cov) v *= c * c;
  double se_s1 = 0.0;
  for (const auto& t : terms)
    if (t.name == "s1") se_s1 = t.stderr_correlated_dps;
  if (!m.cov.empty()) m.cov.front() += se_s1 * se_s1 * s * s;
  const double scale = c * c;  // what a new power-up's spread of c1 carries along
  m.between_run_var_dps2 *= scale;
  m.new_run_var_dps2 *= scale;
  m.tau2_centre_dps2 *= scale;
  m.tau2_curvature_dps2_per_c2 *= scale;
  return m;
}

result<harmonic_cycles> read_harmonic_cycles(method::row_source& source,
                                             std::span<const method::delta_n_term> terms,
                                             const method::delta_n_model& c1_model,
                                             std::optional<method::pairing> asked,
                                             const progress_fn& on_progress) {
  harmonic_cycles out;
  out.pairing = asked.value_or(source.positions().size() < 3 ? method::pairing::abba
                                                             : method::pairing::harmonic);
  auto& app = out.applied;
  app.terms.assign(terms.begin(), terms.end());
  if (out.pairing == method::pairing::harmonic) {
    terms_removed wrapped(source, terms);
    auto rc = method::read_cycles(wrapped, out.pairing, on_progress);
    if (!rc) return rc.err();
    out.cycles = std::move(*rc);
    app.how = "at each position";
    app.model = c1_model;
    return out;
  }
  auto rc = method::read_cycles(source, out.pairing, on_progress);
  if (!rc) return rc.err();
  out.cycles = std::move(*rc);
  const double plus = out.cycles.positions.angle_deg(out.cycles.pair.plus);
  app.how = fmt::format("at the pair's first position ({:g} deg): c1 cos + s1 sin", plus);
  app.model = pair_model_of(c1_model, terms, plus);
  app.pair_plus_deg = plus;
  return out;
}

delta_n_errors pair_errors_of(const io::calibration_record& rec, double plus_deg,
                              const delta_n_errors& c1) {
  const std::size_t n = rec.terms.size();
  std::size_t i1 = n, i2 = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (rec.terms[i].name == "c1") i1 = i;
    if (rec.terms[i].name == "s1") i2 = i;
  }
  if (i1 == n || i2 == n || rec.terms_covariance.size() != n * n) return c1;
  const double v11 = rec.terms_covariance[i1 * n + i1], v22 = rec.terms_covariance[i2 * n + i2],
               v12 = rec.terms_covariance[i1 * n + i2];
  // At 0/180 the pair's dN is c1 itself: its errors as they are (no rounding through k).
  if (!(v11 > 0.0) || !std::isfinite(c1.delta_n_u_dps) || std::fmod(plus_deg, 180.0) == 0.0)
    return c1;
  const double a = plus_deg * units::rad_per_deg;
  const double c = std::cos(a), s = std::sin(a);
  const double u1_2 = c1.delta_n_u_dps * c1.delta_n_u_dps;
  const double var = u1_2 / v11 * std::max(c * c * v11 + s * s * v22 + 2.0 * s * c * v12, 0.0);
  delta_n_errors out = c1;
  out.delta_n_u_dps = std::sqrt(var);
  if (std::isfinite(c1.new_power_up_dps))
    out.new_power_up_dps =
        std::sqrt(var + std::max(c1.new_power_up_dps * c1.new_power_up_dps - u1_2, 0.0));
  return out;
}

delta_n_errors applied_errors_of(const delta_n_source& dn, std::span<const method::cycle> cycles,
                                 const delta_n_budget& budget,
                                 const harmonic_application* applied) {
  if (applied == nullptr) return delta_n_errors_of(dn, cycles, budget, dn.model);
  if (!std::isfinite(applied->pair_plus_deg) || !dn.record)
    return delta_n_errors_of(dn, cycles, budget, applied->model);
  return pair_errors_of(*dn.record, applied->pair_plus_deg,
                        delta_n_errors_of(dn, cycles, budget, dn.model));
}

status check_calibration_fits(const std::string& file, const delta_n_source& dn,
                              std::span<const io::csv_metadata> metadata,
                              std::span<const method::cycle> cycles,
                              std::vector<std::string>& warnings) {
  if (!dn.record) return ok();
  const auto& cal = *dn.record;
  const auto& name = dn.source;
  const auto here = io::sensor_of(metadata);
  if (!cal.sensor) {
    warnings.push_back(
        fmt::format("{}: the calibration names no sensor (a file from before gyroflip recorded "
                    "it): nothing checks that it belongs to this sensor",
                    name));
  } else if (cal.sensor->known() && here.known() && cal.sensor->sensor != here.sensor) {
    return input_error({file}, fmt::format("recorded with sensor '{}', but {} calibrates '{}': "
                                           "a calibration applies to its own sensor only",
                                           printable(here.sensor, 80), printable(name, 200),
                                           printable(cal.sensor->sensor, 80)));
  } else {
    if (!cal.sensor->known() || !here.known())
      warnings.push_back(
          fmt::format("{}: sensor unknown on one side ({} vs {}): nothing checks that the "
                      "calibration belongs to this sensor",
                      file, printable(here.sensor, 80), printable(cal.sensor->sensor, 80)));
    for (const auto& d : io::rig_differences(*cal.sensor, here))
      warnings.push_back(
          fmt::format("{}: rig setting differs from the calibration's: {}", file, d));
  }
  if (cal.model && cal.model->degree() > 0) return ok();  // dN(T) covers temperature
  const double mean_c = mean_temp_c(cycles);
  if (std::isfinite(mean_c) && std::isfinite(cal.pooled.temp_c) &&
      std::abs(mean_c - cal.pooled.temp_c) > far_from_calibration_c)
    warnings.push_back(fmt::format(
        "{}: mean temperature {:.1f} degC, but the calibration was made at {:.1f} degC: dN "
        "depends on temperature (calibrate at several temperatures for a dN(T) model)",
        file, mean_c, cal.pooled.temp_c));
  return ok();
}

namespace {

bool could_be_a_run_of(const std::string& file, const delta_n_source& dn) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) return true;  // not a regular file's size: let the hash decide
  for (const auto& e : dn.record->files)
    if (e.source && (e.source->size_bytes == 0 || e.source->size_bytes == size)) return true;
  return false;
}

// The ΔN's error a compensated rate carries after a new power-up: the calibration's budget as
// report reads it (calibration_budget: from its runs, checked to be theirs), at the run's
// temperature `at_c` where the runs give tau^2(T).
void quote_new_power_up(const delta_n_source& dn, double at_c, const delta_n_budget& b,
                        delta_n_errors& out) {
  const auto& rec = *dn.record;
  const bool no_dof =
      rec.model && rec.model->random_effects && rec.model->dof == 0 && rec.files.size() > 1;
  if (no_dof) {
    out.delta_n_u_dps = std::numeric_limits<double>::quiet_NaN();
    out.delta_n_u_note = fmt::format(
        "not determined (0 degrees of freedom: the dN(T) line of degree {} passes through its {} "
        "runs){}",
        rec.model->degree(), rec.files.size(),
        b.valid && std::isfinite(b.new_power_up_dps)
            ? fmt::format("; with the sensor preset's assumed run-to-run spread, ±{} deg/s for a "
                          "new power-up",
                          significant(b.new_power_up_dps, 2))
            : std::string());
    return;
  }
  if (!b.valid) {
    out.delta_n_u_note = "a new power-up's is " + b.invalid_why;
    return;
  }
  if (!std::isfinite(b.new_power_up_dps)) {
    out.delta_n_u_note = rec.uncertainty
                             ? "a new power-up's is not known: " + b.run_to_run_source
                             : "a new power-up's is not in the calibration file (written before "
                               "calibrate stated it) and no sensor specification gives the "
                               "repeatability: calibrate again to know it";
    return;
  }
  // The band of a between-run variance that changes with temperature is the budget's own refit
  // of the runs (calibration_budget: made once, and kept only when it is the model applied).
  out.new_power_up_dps = new_power_up_at(b, at_c);
}

}  // namespace

// compensate --strict takes only a calibration that vouches for its ΔN (fifth review of issue 31,
// F3/F4/F16): its ΔN and uncertainty are its runs' (budget valid), and its runs are listed and
// were checked for stationarity.
status refuse_unvouched(const delta_n_source& dn, const delta_n_budget& b, bool unchecked) {
  if (!b.valid) return input_error({dn.source}, b.invalid_why + "; refused (strict)");
  if (dn.record->files.empty())
    return input_error({dn.source},
                       "the calibration lists no runs, so none was checked for "
                       "stationarity; refused (strict)");
  if (unchecked)
    return input_error({dn.source}, "its runs were not checked for stationarity; refused (strict)");
  return ok();
}

namespace {
// A run the calibration was made of (its warning, "FILE: what"), refused under strict.
error refuse_copy(const std::string& file, const std::string& warning) {
  const std::string what =
      warning.starts_with(file + ": ") ? warning.substr(file.size() + 2) : warning;
  return input_error({file}, what + "; refused (strict)");
}
}  // namespace

delta_n_budget compensation_budget(const delta_n_source& dn,
                                   std::span<const io::csv_metadata> metadata,
                                   const std::string& file, std::vector<std::string>& warnings) {
  if (!dn.record) return {};
  // The sensor's specification as calibrate and report resolve it (the run's `# sensor.*`
  // header, else its built-in by name), for the repeatability of a calibration's one run.
  auto spec = resolve_sensor_spec(std::nullopt, metadata, file, false, warnings);
  const sensor::preset* preset = spec && *spec ? &**spec : nullptr;
  return calibration_budget(dn, preset, std::string(), warnings);
}

delta_n_errors delta_n_errors_of(const delta_n_source& dn, std::span<const method::cycle> cycles,
                                 const delta_n_budget& budget, const method::delta_n_model& model) {
  delta_n_errors out;
  if (!dn.record) {
    out.delta_n_u_note = "not stated (a dN given as a number, not a calibration file)";
    return out;
  }
  // At the run's mean temperature (the model's reference without temperatures).
  const double mean_c = mean_temp_c(cycles);
  const double at_c = std::isfinite(mean_c) ? mean_c : model.t_ref_c;
  // A constant's own error from its runs, as the budget reads them (a file's stated stderr may be
  // edited: fifth review of issue 31, F6); a line's at the run's temperature (its covariance is
  // checked to be its runs' fit).
  const double u = model.degree() == 0 && budget.valid && !dn.record->files.empty()
                       ? budget.calibration_dps
                       : model.interval_at(at_c);
  if (std::isfinite(u) && u > 0.0) out.delta_n_u_dps = u;
  quote_new_power_up(dn, at_c, budget, out);
  return out;
}

std::vector<std::string> same_run_warnings(const std::string& file, const std::string& sha256,
                                           const delta_n_source& dn) {
  std::vector<std::string> out;
  if (!dn.record) return out;
  for (const auto& e : dn.record->files)
    if (e.source && e.source->sha256 == sha256)
      out.push_back(fmt::format(
          "{}: the same bytes as the calibration's run {} (SHA-256): its dN is part of the ΔN "
          "applied, so its compensated mean is not an independent test of the calibration",
          file, e.file));
  return out;
}

std::vector<std::string> same_cycles_warnings(const std::string& file,
                                              std::span<const method::cycle> cycles,
                                              std::span<const double> dwell_rates,
                                              const delta_n_source& dn) {
  std::vector<std::string> out;
  if (!dn.record || cycles.empty()) return out;
  const auto own = method::calibrate(cycles);
  if (!own) return out;
  for (const auto& e : dn.record->files) {
    // By content where the file holds the run's print (fifth review of issue 31, F5: a copy
    // rounded, shifted in time, trimmed, split or exported kept no signature).
    if (const auto hit = e.print ? method::find_in_print(dwell_rates, *e.print) : std::nullopt) {
      out.push_back(fmt::format(
          "{}: dwells {}–{} of its {} are the same as the calibration's run {}'s dwells {}–{} ({} "
          "in a row alike to a quarter of that run's scatter: a copy of it, rounded, shifted, "
          "trimmed, split or exported): its dN is part of the ΔN applied, so its compensated mean "
          "is not an independent test of the calibration",
          file, hit->first + 1, hit->first + hit->length, dwell_rates.size(), e.file,
          hit->first_print + 1, hit->first_print + hit->length, hit->length));
      continue;
    }
    if (e.cal.cycles == own->cycles && e.cal.delta_n_dps == own->delta_n_dps &&
        (e.cal.std_dps == 0.0 || e.cal.std_dps == own->std_dps))  // no std: a file before it
      out.push_back(fmt::format(
          "{}: the same {} cycles as the calibration's run {} (dN and std equal to the last "
          "digit) in other bytes (a copy, or an export of it): its dN is part of the ΔN applied, "
          "so its compensated mean is not an independent test of the calibration",
          file, own->cycles, e.file));
  }
  return out;
}

result<calibration_runs_check> check_calibration_runs(const delta_n_source& dn, bool strict) {
  calibration_runs_check out;
  if (!dn.record) return out;
  if (dn.record->files.empty()) {
    // A ΔN written with no runs (or a file whose runs were deleted: the one-line forgery of a
    // failed calibration, fifth review of issue 31, F4) vouches for nothing. Its warning is
    // calibration_budget's, one sentence with what its ± is (fifth review, leftover: two
    // warnings on one fact).
    out.unchecked = true;
    return out;
  }
  for (const auto& e : dn.record->files) {
    if (!e.stationarity) {
      out.unchecked = true;
      continue;
    }
    // The verdict judged again from the stored statistics (review of issue 31, L3): a file edited
    // to read "stationary" with "failures": [] is judged by its numbers, as its model is.
    // A stored "not checked" is only what calibrate writes for a run under the minimum of cycles
    // (fifth review of issue 31, F16 addendum: a failed run's test replaced by {"checked":
    // false} passed --strict without a word).
    if (!e.stationarity->checked && (e.stationarity->cycles >= method::min_stationarity_cycles ||
                                     e.stationarity->cycles != e.cal.cycles)) {
      const std::string what = fmt::format(
          "its run {} is stored as not tested for stationarity, but has {} cycles (its test "
          "says {}; the test runs from {}): the file was edited",
          e.file, e.cal.cycles, e.stationarity->cycles, method::min_stationarity_cycles);
      if (strict) return input_error({dn.source}, what + "; refused (strict)");
      out.warnings.push_back(fmt::format("{}: {}", dn.source, what));
    }
    auto st = e.stationarity->rejudged();
    if (e.stationarity->failed() && !st.failed()) st = *e.stationarity;  // a failure stands
    if (st.failed() && !e.stationarity->failed())
      out.warnings.push_back(fmt::format(
          "{}: its run {} is marked stationary, but its own statistics fail the test (the file "
          "was edited?): judged from the statistics",
          dn.source, e.file));
    // The one verdict on a run (judge_run, as calibrate's and report's): a failed run makes the
    // ΔN not the sensor's; a run whose g-term was not checked passed tests that a constant input
    // rate passes too (third review of issue 31, H2).
    auto standing = judge_run({e.file, dn.source, "compensation", {}}, st, strict, out.warnings);
    if (!standing) return standing.err();
    if (*standing == run_standing::failed) out.failed.push_back(e.file);
    if (*standing == run_standing::g_unchecked) out.g_unchecked.push_back(e.file);
    if (*standing == run_standing::untested) out.untested.push_back(e.file);
  }
  if (out.unchecked)
    out.warnings.push_back(fmt::format(
        "{}: its runs were not checked for stationarity (a calibration written before gyroflip "
        "tested it): recalibrate, or run `gyroflip calibrate` again on its runs, to know that "
        "its ΔN is the sensor's",
        dn.source));
  return out;
}

// The budget of a calibration file's ΔN. Its runs give it, once the file's ΔN is checked to be
// theirs: a model that is not their fit (edited by hand, review D4) is warned about, as the
// budget then describes other numbers than those applied. A file that lists no runs (a ΔN
// written by hand) gets its own stated error as one run's, with the preset's repeatability, or
// no ± at all (review D1: it got ±0).
delta_n_budget calibration_budget(const delta_n_source& given, const sensor::preset* spec,
                                  const std::string& named_preset,
                                  std::vector<std::string>& warnings) {
  const auto& rec = *given.record;
  // The sensor's specification as the runs' g-term check takes it (--sensor, a TOML header, a
  // built-in by name; fourth review of issue 31, F3: only a built-in was used here).
  const auto* preset = spec != nullptr ? &spec->params : nullptr;
  const std::string preset_name = spec != nullptr ? spec->name : named_preset;
  if (rec.files.empty()) {
    // Its own stated error: the model's (the ΔN applied; the largest over its temperatures for a
    // line), else the top-level correlated error of a constant.
    double own_dps = rec.pooled.stderr_correlated_dps;
    if (rec.model && !rec.model->cov.empty()) {
      const auto& m = *rec.model;
      own_dps = m.degree() == 0 || !std::isfinite(m.temp_min_c)
                    ? std::sqrt(m.cov.front())
                    : std::max(m.interval_at(m.temp_min_c), m.interval_at(m.temp_max_c));
    }
    const bool own = std::isfinite(own_dps) && own_dps > 0.0;
    // One sentence for the one fact (check_calibration_runs says nothing more of it).
    warnings.push_back(
        own ? fmt::format(
                  "{}: the calibration lists no runs, so nothing shows that its ΔN was measured "
                  "on a stationary table; it carries its own stated error ±{} °/s and, for a "
                  "new power-up, the run-to-run repeatability of the budget below",
                  given.source, significant(own_dps, 2))
            : fmt::format("{}: the calibration lists no runs and states no error: nothing shows "
                          "that its ΔN was measured on a stationary table, and it has no known "
                          "uncertainty",
                          given.source));
    if (!own) return budget_of({}, std::nullopt, preset, preset_name);
    std::vector<io::calibration_entry> one{
        {"the calibration's stated ΔN", rec.pooled, std::nullopt, std::nullopt}};
    one.front().cal.stderr_correlated_dps = own_dps;
    one.front().cal.cycles = std::max<std::size_t>(one.front().cal.cycles, 1);  // one weight
    auto b = budget_of(one, std::nullopt, preset, preset_name);
    b.within_run_note = "the calibration's own stated error (it lists no runs)";
    b.model_note = "none: the calibration lists no runs";
    return b;
  }
  // Runs listed twice (the same bytes, or the same cycles in other bytes) are one run counted
  // twice: the runs' scatter, and so the ±, is understated (review N3).
  bool twice = false;
  for (std::size_t k = 1; k < rec.files.size(); ++k)
    for (std::size_t i = 0; i < k; ++i) {
      const auto &a = rec.files[i], &b = rec.files[k];
      const auto rep = repeat_of(a, b);
      if (rep == repeat::none) continue;
      twice = true;
      warnings.push_back(fmt::format(
          "{}: its runs {} and {} are {}: one recording counted as two runs, so the runs' "
          "scatter understates the repeatability; the ΔN applied has no known uncertainty",
          given.source, a.file, b.file,
          rep == repeat::same_bytes ? "the same bytes (SHA-256)"
                                    : "the same cycles (dN, std and count)"));
    }
  const auto differs = [](double a, double b) {
    return std::abs(a - b) > 1e-9 * std::max(std::abs(a), std::abs(b)) + 1e-15;
  };
  bool edited = false;  // the ΔN applied is not what its runs give: no ± from them
  std::optional<method::delta_n_model> refit_model;
  if (rec.model) {
    const auto refit = method::fit_runs_model(calibrations_of(rec.files), rec.model->degree());
    const bool theirs_coeffs = refit && *refit && same_line(*rec.model, **refit);
    const bool theirs_cov =
        refit && *refit && rec.model->cov.size() == (*refit)->cov.size() &&
        std::equal(rec.model->cov.begin(), rec.model->cov.end(), (*refit)->cov.begin(),
                   [&](double a, double b) { return !differs(a, b); });
    // A file written before the modified Knapp-Hartung scale (schema 3-4) holds the
    // untruncated one: its covariance is the refit's times q <= 1 where the runs agreed closely.
    const bool older_scale =
        refit && *refit && rec.model->random_effects && !theirs_cov &&
        rec.model->cov.size() == (*refit)->cov.size() && !rec.model->cov.empty() &&
        (*refit)->cov.front() > 0.0 && (*refit)->dof > 0 && [&] {
          // The untruncated q = sum w* r^2 / dof of the refit (its weights 1/(v + tau^2)).
          const auto& m = **refit;
          const double tau2 = std::isfinite(m.between_run_var_dps2) ? m.between_run_var_dps2 : 0.0;
          double q = 0.0;
          for (const auto& e : rec.files) {
            const double r = e.cal.delta_n_dps - m.eval(e.cal.temp_c);
            const double v = e.cal.stderr_correlated_dps * e.cal.stderr_correlated_dps + tau2;
            if (!(v > 0.0)) return false;
            q += r * r / v / static_cast<double>(m.dof);
          }
          return q < 1.0 &&
                 std::equal(rec.model->cov.begin(), rec.model->cov.end(), m.cov.begin(),
                            [&](double a, double b2) {
                              return std::abs(a - q * b2) <= 1e-6 * std::abs(q * b2) + 1e-30;
                            });
        }();
    const bool theirs = theirs_coeffs && (theirs_cov || older_scale);
    if (theirs && refit && *refit) refit_model = **refit;
    if (!theirs) {
      edited = true;
      const double se = refit && *refit ? std::sqrt((*refit)->cov.front()) : method::no_value;
      warnings.push_back(fmt::format(
          "{}: its ΔN model is not the fit of the {} runs it lists (c₀ {} °/s applied, {} °/s "
          "from its runs{}; or its t_ref_c or covariance differs): edited by hand or made by "
          "other software; the ΔN applied has no known uncertainty",
          given.source, rec.files.size(), fmt::format("{:.6g}", rec.model->coeffs_dps.front()),
          refit && *refit ? fmt::format("{:.6g}", (*refit)->coeffs_dps.front())
                          : std::string("none"),
          std::isfinite(se) && se > 0.0
              ? fmt::format(
                    ", {:.1f} σ apart",
                    std::abs(rec.model->coeffs_dps.front() - (*refit)->coeffs_dps.front()) / se)
              : std::string()));
    }
  } else if (rec.files.size() > 1) {
    edited = true;  // calibrate writes a model for several runs
    warnings.push_back(fmt::format(
        "{}: it lists {} runs but no ΔN model (calibrate writes one): edited by hand or made "
        "by other software; the ΔN applied has no known uncertainty",
        given.source, rec.files.size()));
  } else if (differs(rec.pooled.delta_n_dps, rec.files[0].cal.delta_n_dps) ||
             differs(rec.pooled.stderr_correlated_dps, rec.files[0].cal.stderr_correlated_dps)) {
    edited = true;
    warnings.push_back(fmt::format(
        "{}: its ΔN {} °/s is not its one run's {} °/s: edited by hand or made by other "
        "software; the ΔN applied has no known uncertainty",
        given.source, value_pm(rec.pooled.delta_n_dps, rec.pooled.stderr_correlated_dps),
        value_pm(rec.files[0].cal.delta_n_dps, rec.files[0].cal.stderr_correlated_dps)));
  }
  // The budget from the runs' fit as this version makes it (a file written before the modified
  // Knapp-Hartung scale keeps a covariance that may be below the runs' own errors; its
  // coefficients are the same).
  auto b = budget_of(rec.files, refit_model ? refit_model : rec.model, preset, preset_name);
  // A calibration whose runs cannot give the repeatability (one run, no degrees of freedom) and
  // no specification here: the one calibrate stated, from the specification it had (F3).
  // Its stated parts checked against each other and its runs (fifth review of issue 31, F6: a
  // new-power-up error of 1e-9 was quoted): never below the runs' own error, nor below the
  // calibrated error and the repeatability combined.
  if (!std::isfinite(b.new_power_up_dps) && !edited && !twice && rec.uncertainty &&
      std::isfinite(rec.uncertainty->new_power_up_dps) &&
      std::isfinite(rec.uncertainty->repeatability_dps)) {
    const auto& u = *rec.uncertainty;
    const double cal = std::isfinite(u.calibrated_dps) ? u.calibrated_dps : b.calibration_dps;
    const double least = std::hypot(std::max(cal, b.within_run_dps), u.repeatability_dps);
    constexpr double rounding = 1.0 - 1e-6;
    if (u.new_power_up_dps < rounding * least || cal < rounding * b.within_run_dps) {
      edited = true;
      warnings.push_back(fmt::format(
          "{}: its stated uncertainty is below its own parts (new power-up ±{} °/s, calibrated "
          "±{} °/s, repeatability ±{} °/s, its runs' own error ±{} °/s): edited by hand or made "
          "by other software; the ΔN applied has no known uncertainty",
          given.source, fmt::format("{:.3g}", u.new_power_up_dps), fmt::format("{:.3g}", cal),
          fmt::format("{:.3g}", u.repeatability_dps), fmt::format("{:.3g}", b.within_run_dps)));
    }
  }
  if (!std::isfinite(b.new_power_up_dps) && !edited && !twice && rec.uncertainty &&
      std::isfinite(rec.uncertainty->new_power_up_dps) &&
      std::isfinite(rec.uncertainty->repeatability_dps)) {
    b.run_to_run_dps = rec.uncertainty->repeatability_dps;
    b.run_to_run_source =
        "as the calibration file states it: " + rec.uncertainty->repeatability_source;
    if (std::isfinite(rec.uncertainty->calibrated_dps))
      b.calibration_dps = rec.uncertainty->calibrated_dps;
    b.new_power_up_dps = rec.uncertainty->new_power_up_dps;
  }
  if (edited || twice) {
    b.valid = false;
    b.new_power_up_dps = std::numeric_limits<double>::quiet_NaN();
    b.invalid_why = edited ? "not known: the calibration's ΔN is not what its runs give"
                           : "not known: the calibration counts one recording as two runs";
  }
  return b;
}

result<delta_n_source> delta_n_of_value(double delta_n_dps) {
  if (auto s = method::check_delta_n(delta_n_dps); !s) return s.err();
  return delta_n_source{method::constant_model(delta_n_dps), {}, std::nullopt, std::nullopt};
}

result<delta_n_source> delta_n_of_file(const std::string& path) {
  auto rec = io::read_calibration_file(path);
  if (!rec) return rec.err();
  return of_record(std::move(*rec), path);
}

result<delta_n_source> delta_n_of_json(std::string_view text, const std::string& name) {
  auto rec = io::parse_calibration(text, name);
  if (!rec) return rec.err();
  return of_record(std::move(*rec), name);
}

std::string outside_model_warning(std::string_view file, const compensation& c,
                                  const method::delta_n_model& model) {
  const std::size_t n = c.cycles.size();
  return fmt::format(
      "{}: {} cycles lie outside the dN(T) model's {:.1f}–{:.1f} °C: ΔN was "
      "extrapolated",
      file,
      c.outside_model == n ? fmt::format("all {}", n) : fmt::format("{} of {}", c.outside_model, n),
      model.temp_min_c, model.temp_max_c);
}

result<compensation> compensate_cycles(std::span<const method::cycle> cycles,
                                       const method::delta_n_model& model, double drift_window_s,
                                       std::string_view what) {
  if (auto s = method::check_drift_window(drift_window_s); !s) return s.err();
  compensation out;
  out.cycles.reserve(cycles.size());
  for (const auto& c : cycles) {
    out.cycles.push_back(method::compensate(c, model));
    if (model.degree() > 0 &&
        (c.temp_c < model.temp_min_c - 1.0 || c.temp_c > model.temp_max_c + 1.0))
      ++out.outside_model;
  }
  out.summary = method::summarize(out.cycles, drift_window_s);
  if (auto s = io::check_finite(out.cycles, out.summary, what); !s) return s.err();
  return out;
}

result<compensate_result> compensate_file(const compensate_request& r,
                                          const progress_fn& on_progress) {
  compensate_result out;
  const auto& dn = r.delta_n;
  out.pairing = r.pairing.value_or(dn.pairing.value_or(method::pairing::abba));
  if (auto s = method::check_drift_window(r.drift_window_s); !s) return s.err();
  const auto terms = dn.record ? harmonic_terms_of(*dn.record) : std::nullopt;
  result<method::recording_cycles> rc = usage_error("not read");
  if (terms) {
    // A harmonic calibration (issue 33): its terms at each position (harmonic_application).
    auto source = rigdata::open_recording(r.file, r.angle_tolerance_deg);
    if (!source) return source.err();
    auto hc = read_harmonic_cycles(**source, *terms, dn.model, r.pairing, on_progress);
    if (!hc) return hc.err();
    out.pairing = hc->pairing;
    out.applied = std::move(hc->applied);
    rc = std::move(hc->cycles);
  } else {
    if (dn.pairing && *dn.pairing != out.pairing)
      out.warnings.push_back(fmt::format("calibration used pairing '{}', compensating with '{}'",
                                         method::to_string(*dn.pairing),
                                         method::to_string(out.pairing)));
    rc = read_cycles(r.file, out.pairing, on_progress, r.angle_tolerance_deg);
    if (!rc) return rc.err();
  }
  const method::delta_n_model& model = out.applied ? out.applied->model : dn.model;
  for (auto& w : rc->warnings) out.warnings.push_back(std::move(w));
  if (auto s = check_calibration_fits(r.file, dn, rc->metadata, rc->cycles, out.warnings); !s)
    return s.err();
  auto runs = check_calibration_runs(dn, r.strict);
  if (!runs) return runs.err();
  for (auto& w : runs->warnings) out.warnings.push_back(std::move(w));
  const auto budget = compensation_budget(dn, rc->metadata, r.file, out.warnings);
  if (dn.record && r.strict)
    if (auto s = refuse_unvouched(dn, budget, runs->unchecked); !s) return s.err();
  if (model.degree() > 0 && !rc->has_temp)
    return input_error({r.file},
                       "no temp_c column, but the calibration's dN(T) model needs temperatures");
  auto comp = compensate_cycles(rc->cycles, model, r.drift_window_s, r.file);
  if (!comp) return comp.err();
  out.comp = std::move(*comp);
  if (dn.record) {
    // The SHA-256 of a 300 MB recording costs a third of the compensation (issue 33 (f)): only a
    // file the size of one of the calibration's runs (or of a run whose size is not on record)
    // can be one of them.
    bool same_bytes = false;
    if (could_be_a_run_of(r.file, dn)) {
      auto id = report::identify_file(r.file);
      if (!id) return id.err();
      for (auto& w : same_run_warnings(r.file, id->sha256, dn)) {
        out.warnings.push_back(std::move(w));
        same_bytes = true;
      }
    }
    // Other bytes with the same cycles (a copy with one more newline, a .gfr's CSV export): the
    // cycle signature calibrate compares runs by (fourth review of issue 31, F6).
    std::vector<std::string> copies;
    if (!same_bytes) copies = same_cycles_warnings(r.file, rc->cycles, rc->dwell_rates, dn);
    // No independent test at all: strict refuses it (fifth review of issue 31, F5).
    if (r.strict && (same_bytes || !copies.empty()))
      return refuse_copy(r.file, same_bytes ? out.warnings.back() : copies.front());
    for (auto& w : copies) out.warnings.push_back(std::move(w));
  }
  static_cast<delta_n_errors&>(out) =
      applied_errors_of(dn, rc->cycles, budget, out.applied ? &*out.applied : nullptr);
  if (out.comp.outside_model > 0)
    out.warnings.push_back(outside_model_warning(r.file, out.comp, model));
  return out;
}

nlohmann::json compensation_json(const compensation& c, const std::string& file,
                                 const delta_n_source& dn, method::pairing p,
                                 const delta_n_errors& errors) {
  using nlohmann::json;
  const auto& m = dn.model;
  const auto& s = c.summary;
  // The dN that was subtracted: a constant, or the dN(T) polynomial about t_ref_c.
  json d = {{"source", dn.source.empty() ? json(nullptr) : json(dn.source)},
            {"degree", m.degree()},
            {"coeffs_dps", m.coeffs_dps},
            {"t_ref_c", m.degree() > 0 ? json(m.t_ref_c) : json(nullptr)}};
  if (m.degree() == 0) d["delta_n_dps"] = m.coeffs_dps.front();
  if (dn.record)
    if (const auto terms = harmonic_terms_of(*dn.record)) {
      json t = json::object();
      for (const auto& x : *terms) t[x.name] = x.value_dps;
      d["terms_dps"] = std::move(t);
    }
  // Its errors as the text quotes them, null when not known and then the reason (issue 31: the
  // new-power-up error was in the text only).
  const auto or_null = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  d["error_dps"] = or_null(errors.delta_n_u_dps);
  d["new_power_up_dps"] = or_null(errors.new_power_up_dps);
  d["error_note"] = errors.delta_n_u_note.empty() ? json(nullptr) : json(errors.delta_n_u_note);
  json j = io::schema_object("compensate", 2);
  j.update(json{{"file", file},
                {"delta_n", std::move(d)},
                {"pairing", method::to_string(p)},
                {"cycles", s.cycles},
                {"duration_s", s.duration_s},
                {"mean_dps", s.mean_dps},
                {"std_dps", s.std_dps},
                {"stderr_dps", s.stderr_dps},
                {"stderr_correlated_dps", s.stderr_correlated_dps},
                {"drift_dps", s.drift_dps ? json(*s.drift_dps) : json(nullptr)},
                {"drift_window_s", s.drift_window_s}});
  return j;
}

}  // namespace gyroflip::workflow
