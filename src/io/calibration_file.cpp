/// \file
/// \brief Calibration JSON writer and reader (see calibration_file.hpp).
#include "gyroflip/io/calibration_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "gyroflip/io/mapped_file.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/io/schema.hpp"
#include "gyroflip/method/demodulator.hpp"

namespace gyroflip::io {
namespace {

using nlohmann::json;

json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

json calibration_fields(const method::calibration& c,
                        const std::optional<calibration_geometry>& g) {
  json j = {{"delta_n_dps", c.delta_n_dps},
            {"std_dps", c.std_dps},
            {"stderr_dps", c.stderr_dps},
            {"stderr_correlated_dps", c.stderr_correlated_dps},
            {"correlated_m_cycles", c.correlated_m},
            {"cycles", c.cycles},
            {"temp_c", number_or_null(c.temp_c)},
            {"duration_s", c.duration_s},
            {"bias_mean_dps", c.bias_mean_dps},
            {"earth_rate_dps", nullptr},
            {"g_term_dps", nullptr}};
  if (g) {
    const auto s = method::split_delta_n(c.delta_n_dps, g->lat_deg, g->axis);
    j["earth_rate_dps"] = s.earth_rate_dps;
    j["g_term_dps"] = s.g_term_dps;
  }
  return j;
}

// The DOM parser with exceptions off, keeping where parsing stopped: nlohmann's own exceptions
// carry a byte offset at best and a number overflow (1e400, error 406) none at all.
class located_parser : public nlohmann::detail::json_sax_dom_parser<json> {
 public:
  explicit located_parser(json& j) : json_sax_dom_parser(j, false) {}
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& /*last_token*/, const Exception& ex) {
    position_ = position;
    what_ = ex.what();
    return false;
  }
  [[nodiscard]] std::size_t position() const noexcept { return position_; }
  [[nodiscard]] const std::string& what() const noexcept { return what_; }

 private:
  std::size_t position_ = 0;
  std::string what_;
};

// Strips nlohmann's "[json.exception.parse_error.101] parse error at line 1, column 5: " prefix.
std::string_view reason(std::string_view what) {
  const auto colon = what.rfind(": ");
  if (what.substr(0, 16) == "[json.exception." && colon != std::string_view::npos)
    return what.substr(colon + 2);
  const auto bracket = what.find("] ");
  return bracket != std::string_view::npos ? what.substr(bracket + 2) : what;
}

result<json> parse_json(const std::string& path, std::string_view text) {
  json j;
  located_parser sax(j);
  if (json::sax_parse(text.begin(), text.end(), &sax)) return j;
  // Byte offset -> 1-based line and column (the offset counts the byte that failed).
  const std::size_t at = std::min(sax.position(), text.size());
  const std::size_t at0 = at > 0 ? at - 1 : 0;
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(
                                   text.begin(), text.begin() + static_cast<long>(at0), '\n'));
  const auto nl = text.rfind('\n', at0 == 0 ? 0 : at0 - 1);
  const std::size_t col = at0 == 0 || nl == std::string_view::npos ? at0 + 1 : at0 - nl;
  return input_error({path, line, col},
                     fmt::format("not valid JSON: {}", printable(reason(sax.what()), 200)));
}

// The largest magnitude of a number in a calibration (as for recordings, csv_reader): within it
// compensation's arithmetic cannot overflow.
constexpr double max_magnitude = csv_reader::max_magnitude;

status check_magnitude(const std::string& path, std::string_view key, double v) {
  if (std::isfinite(v) && std::abs(v) <= max_magnitude) return ok();
  return input_error({path}, fmt::format("'{}' = {:g} is not a finite number within +-{:g}", key, v,
                                         max_magnitude));
}

// A dN(T) model must give finite, sane values over every temperature a recording may hold:
// ordered range within the recording limits, coefficients within the magnitude limit, and dN(T)
// within it at both ends of the recording temperature range (a polynomial of degree <= 6 with
// bounded coefficients is then bounded in between).
status check_model(const std::string& path, const method::delta_n_model& m) {
  for (double c : m.coeffs_dps)
    if (auto s = check_magnitude(path, "coeffs_dps", c); !s) return s;
  if (m.coeffs_dps.size() > method::max_model_degree + 1)
    return input_error({path}, fmt::format("model of degree {} is above the maximum {}",
                                           m.coeffs_dps.size() - 1, method::max_model_degree));
  const double lo = recording_reader::min_temp_c;
  const double hi = recording_reader::max_temp_c;
  if (std::isfinite(m.t_ref_c) && (m.t_ref_c < lo || m.t_ref_c > hi))
    return input_error(
        {path}, fmt::format("'t_ref_c' = {:g} is outside [{:g}, {:g}] degC", m.t_ref_c, lo, hi));
  const bool has_range = std::isfinite(m.temp_min_c) || std::isfinite(m.temp_max_c);
  if (has_range && !(m.temp_min_c >= lo && m.temp_min_c <= m.temp_max_c && m.temp_max_c <= hi))
    return input_error({path}, fmt::format("'temp_range_c' [{:g}, {:g}] must be ordered and "
                                           "within [{:g}, {:g}] degC",
                                           m.temp_min_c, m.temp_max_c, lo, hi));
  for (const double t : {lo, hi})
    if (m.coeffs_dps.size() > 1 && !(std::abs(m.eval(t)) <= max_magnitude))
      return input_error({path}, fmt::format("the dN(T) model gives {:g} deg/s at {:g} degC: its "
                                             "coefficients are not a calibration",
                                             m.eval(t), t));
  for (double c : m.cov)
    if (!std::isfinite(c)) return input_error({path}, "model 'cov' has a non-finite value");
  return ok();
}

// A run's origin in words as the file keeps it: one line (printable(): controls as \xNN, the
// direction controls that would reorder a page's text around them as \uNNNN, at most 1000 bytes).
std::string plain_line(std::string_view text) {
  return printable(text, 1000);
}

// A run's source (schema 2): all four keys or none (a file without one of them is not what
// calibrate wrote: review D3), a SHA-256 of 64 lowercase hex digits, a known origin, a size a
// JSON number holds exactly, and a detail of printable text. `at` names the run ("files[2]").
status read_source(const std::string& path, const std::string& at, const json& f,
                   calibration_entry& e) {
  constexpr const char* keys[] = {"sha256", "size_bytes", "origin", "origin_detail"};
  const auto present =
      std::count_if(std::begin(keys), std::end(keys), [&](const char* k) { return f.contains(k); });
  if (present == 0) return ok();
  const auto bad = [&](std::string_view what) {
    return input_error({path}, fmt::format("{}: {}", at, what));
  };
  if (present != 4)
    return bad(
        "a run's source needs all of 'sha256', 'size_bytes', 'origin' and "
        "'origin_detail' (or none)");
  for (const char* k : {"sha256", "origin", "origin_detail"})
    if (!f[k].is_string()) return bad(fmt::format("'{}' must be a string", k));
  run_source src;
  src.sha256 = f["sha256"].get<std::string>();
  src.origin = f["origin"].get<std::string>();
  src.origin_detail = f["origin_detail"].get<std::string>();
  if (src.sha256.size() != 64 ||
      src.sha256.find_first_not_of("0123456789abcdef") != std::string::npos)
    return bad("'sha256' must be 64 lowercase hex digits");
  if (src.origin != "simulated" && src.origin != "emulated" && src.origin != "rig" &&
      src.origin != "unknown")
    return bad("'origin' must be \"simulated\", \"emulated\", \"rig\" or \"unknown\"");
  // calibrate writes it as printable ASCII (printable()): anything else was not written by it
  // and could carry control or bidi characters onto a page.
  if (src.origin_detail.size() > 1000 || plain_line(src.origin_detail) != src.origin_detail)
    return bad(
        "'origin_detail' must be one line of plain text (no control characters), at "
        "most 1000 bytes");
  const auto& size = f["size_bytes"];
  constexpr std::uint64_t max_size = std::uint64_t{1} << 53;  // exact in a JSON double
  if (!size.is_number_unsigned() || size.get<std::uint64_t>() > max_size)
    return bad("'size_bytes' must be a whole number of bytes up to 2^53");
  src.size_bytes = size.get<std::uint64_t>();
  e.source = std::move(src);
  return ok();
}

json g_term_json(const method::stationarity& st) {
  if (!st.g_checked) return nullptr;
  return {{"g_term_dps", st.g_term_dps},       {"exact", st.g_exact},
          {"limit_dps", st.g_limit_dps},       {"margin_dps", st.g_margin_dps},
          {"source", plain_line(st.g_source)}, {"failed", st.g_failed}};
}

json stationarity_json(const method::stationarity& st) {
  // A run too short for the scatter and drift tests still has its g-term and temperature judged,
  // and is not vouched for (fifth review of issue 31, F16).
  if (!st.checked)
    return {{"checked", false},
            {"why_not", st.why_not},
            {"vouched", false},
            {"stationary", !st.failed()},
            {"cycles", st.cycles},
            {"temp_span_c", st.temp_span_c},
            {"temp_failed", st.temp_failed},
            {"g_term", g_term_json(st)},
            {"failures", st.failures()}};
  json j = {{"checked", true},
            {"vouched", st.vouched()},
            {"stationary", !st.failed()},
            {"scatter_ratio", st.scatter_ratio},
            {"scatter_limit", st.scatter_limit},
            {"scatter_low_limit", st.scatter_low_limit},
            {"cycles", st.cycles},
            {"temp_span_c", st.temp_span_c},
            {"drift_statistic", st.drift_statistic},
            {"drift_limit", st.drift_limit_value},
            {"step_dps", st.step_dps},
            {"step_time_s", st.step_time_s},
            {"step_limit_dps", st.step_limit_dps},
            {"step_statistic", st.step_statistic},
            {"step_statistic_limit", st.step_statistic_limit_value},
            {"trim_cycles", st.trim_cycles},
            {"slope_statistic", st.slope_statistic},
            {"slope_limit", st.slope_limit},
            {"ramp_dps", st.ramp_dps},
            {"long_run_std_dps", st.long_run_std_dps},
            {"step_hidden_dps", st.step_hidden_dps},
            {"step_hidden_end_dps", st.step_hidden_end_dps},
            {"ramp_hidden_dps", st.ramp_hidden_dps},
            {"scatter_failed", st.scatter_failed},
            {"drift_failed", st.drift_failed},
            {"temp_failed", st.temp_failed},
            {"temp_checked", st.has_temp},
            {"outlier_z", st.outlier_z},
            {"outlier_limit", st.outlier_limit},
            {"outlier_cycle", st.outlier_cycle},
            {"outlier_time_s", st.outlier_time_s},
            {"outlier_failed", st.outlier_failed},
            {"noise", nullptr},
            {"g_term", g_term_json(st)},
            {"failures", st.failures()}};
  if (st.noise_checked)
    j["noise"] = {{"ratio", st.noise_ratio},
                  {"limit", st.noise_limit},
                  {"source", plain_line(st.noise_source)},
                  {"failed", st.noise_failed}};
  return j;
}

// A stored test's g-term (null or absent: not checked).
template <class Flag, class Bad>
status read_g_term(const json& j, method::stationarity& st, const Flag& flag, const Bad& bad) {
  if (!j.contains("g_term") || j["g_term"].is_null()) return ok();
  const json& g = j["g_term"];
  if (!g.is_object() || !g.contains("g_term_dps") || !g["g_term_dps"].is_number() ||
      !g.contains("limit_dps") || !g["limit_dps"].is_number() || !flag(g, "exact", st.g_exact) ||
      !flag(g, "failed", st.g_failed))
    return bad("'g_term' needs 'g_term_dps', 'limit_dps', 'exact' and 'failed'");
  st.g_checked = true;
  st.g_term_dps = g["g_term_dps"].get<double>();
  st.g_limit_dps = g["limit_dps"].get<double>();
  if (g.contains("margin_dps") && g["margin_dps"].is_number())
    st.g_margin_dps = g["margin_dps"].get<double>();
  if (g.contains("source") && g["source"].is_string())
    st.g_source = plain_line(g["source"].get<std::string>());
  return ok();
}

// A run too short for the scatter and drift tests: its cycles, temperature and g-term (written
// since the fifth review of issue 31; absent in older files).
template <class Number, class Flag, class Bad>
status read_short_run(const json& j, method::stationarity& st, const Number& number,
                      const Flag& flag, const Bad& bad) {
  if (j.contains("cycles")) {
    if (!j["cycles"].is_number_unsigned()) return bad("'cycles' must be a whole number");
    st.cycles = j["cycles"].get<std::size_t>();
  }
  if (j.contains("temp_span_c") && (!number("temp_span_c", st.temp_span_c) || st.temp_span_c < 0.0))
    return bad("'temp_span_c' must be a finite number >= 0");
  if (j.contains("temp_failed") && !flag(j, "temp_failed", st.temp_failed))
    return bad("'temp_failed' must be a boolean");
  return read_g_term(j, st, flag, bad);
}

// The noise (against the specification) and outlier statistics (fifth review of issue 31, F11;
// absent in older files: not judged).
template <class Number, class Flag, class Bad>
status read_noise_outlier(const json& j, method::stationarity& st, const Number& number,
                          const Flag& flag, const Bad& bad) {
  if (j.contains("temp_checked") && !flag(j, "temp_checked", st.has_temp))
    return bad("'temp_checked' must be a boolean");
  if (j.contains("outlier_z")) {
    if (!number("outlier_z", st.outlier_z) || !number("outlier_limit", st.outlier_limit) ||
        !number("outlier_time_s", st.outlier_time_s) ||
        !flag(j, "outlier_failed", st.outlier_failed) || st.outlier_z < 0.0 ||
        st.outlier_limit < 0.0)
      return bad("'outlier_z' needs 'outlier_limit', 'outlier_time_s' and 'outlier_failed'");
    if (j.contains("outlier_cycle") && j["outlier_cycle"].is_number_unsigned())
      st.outlier_cycle = j["outlier_cycle"].get<std::size_t>();
  }
  if (!j.contains("noise") || j["noise"].is_null()) return ok();
  const json& n = j["noise"];
  if (!n.is_object() || !n.contains("ratio") || !n["ratio"].is_number() || !n.contains("limit") ||
      !n["limit"].is_number() || !flag(n, "failed", st.noise_failed))
    return bad("'noise' needs 'ratio', 'limit' and 'failed'");
  st.noise_checked = true;
  st.noise_ratio = n["ratio"].get<double>();
  st.noise_limit = n["limit"].get<double>();
  if (!std::isfinite(st.noise_ratio) || !std::isfinite(st.noise_limit) || st.noise_ratio < 0.0 ||
      st.noise_limit < 0.0)
    return bad("'noise' has a negative or non-finite ratio or limit");
  if (n.contains("source") && n["source"].is_string())
    st.noise_source = plain_line(n["source"].get<std::string>());
  return ok();
}

// A run's stationarity test as calibrate wrote it (schema 3); absent: not checked (older files).
status read_stationarity(const std::string& path, const std::string& at, const json& f,
                         calibration_entry& e) {
  const auto it = f.find("stationarity");
  if (it == f.end()) return ok();
  const json& j = *it;
  const auto bad = [&](std::string_view what) {
    return input_error({path}, fmt::format("{}: 'stationarity' {}", at, what));
  };
  if (!j.is_object() || !j.contains("checked") || !j["checked"].is_boolean())
    return bad("must be an object with a boolean 'checked'");
  method::stationarity st;
  st.checked = j["checked"].get<bool>();
  const auto number = [&](const char* key, double& out) {
    if (!j.contains(key) || !j[key].is_number()) return false;
    out = j[key].get<double>();
    return std::isfinite(out) && std::abs(out) <= max_magnitude;
  };
  const auto flag = [&](const json& o, const char* key, bool& out) {
    if (!o.contains(key) || !o[key].is_boolean()) return false;
    out = o[key].get<bool>();
    return true;
  };
  if (!st.checked) {
    if (j.contains("why_not") && j["why_not"].is_string())
      st.why_not = plain_line(j["why_not"].get<std::string>());
    if (auto s = read_short_run(j, st, number, flag, bad); !s) return s;
    e.stationarity = std::move(st);
    return ok();
  }
  if (!number("scatter_ratio", st.scatter_ratio) || !number("scatter_limit", st.scatter_limit) ||
      !number("drift_statistic", st.drift_statistic) ||
      !number("drift_limit", st.drift_limit_value) || !number("step_dps", st.step_dps) ||
      !number("step_time_s", st.step_time_s) || !number("step_limit_dps", st.step_limit_dps) ||
      !flag(j, "scatter_failed", st.scatter_failed) || !flag(j, "drift_failed", st.drift_failed))
    return bad("needs the finite statistics and verdicts calibrate writes");
  // Ratios, limits and errors are not negative (a hand-edited file is refused, not recomputed).
  for (const double v : {st.scatter_ratio, st.scatter_limit, st.drift_statistic,
                         st.drift_limit_value, st.step_limit_dps})
    if (v < 0.0) return bad("has a negative statistic, limit or error");
  // Written since the step and slope statistics (fifth review of issue 31; absent: 0, their
  // verdicts not judged, as calibrate did not judge them). Only the slope and the ramp are signed.
  for (const auto& [key, out, signed_ok] :
       {std::tuple{"step_statistic", &st.step_statistic, false},
        std::tuple{"step_statistic_limit", &st.step_statistic_limit_value, false},
        std::tuple{"slope_statistic", &st.slope_statistic, true},
        std::tuple{"slope_limit", &st.slope_limit, false},
        std::tuple{"ramp_dps", &st.ramp_dps, true},
        std::tuple{"long_run_std_dps", &st.long_run_std_dps, false},
        std::tuple{"step_hidden_dps", &st.step_hidden_dps, false},
        std::tuple{"step_hidden_end_dps", &st.step_hidden_end_dps, false},
        std::tuple{"ramp_hidden_dps", &st.ramp_hidden_dps, false}})
    if (j.contains(key) && (!number(key, *out) || (!signed_ok && *out < 0.0)))
      return bad(fmt::format("'{}' must be a finite number{}", key, signed_ok ? "" : " >= 0"));
  if (j.contains("trim_cycles")) {
    if (!j["trim_cycles"].is_number_unsigned()) return bad("'trim_cycles' must be a whole number");
    st.trim_cycles = j["trim_cycles"].get<std::size_t>();
  }
  // Written since the lower scatter limit (absent in the first schema-3 files: 0, not checked).
  if (j.contains("scatter_low_limit") &&
      (!number("scatter_low_limit", st.scatter_low_limit) || st.scatter_low_limit < 0.0))
    return bad("'scatter_low_limit' must be a finite number >= 0");
  if (j.contains("temp_span_c") && (!number("temp_span_c", st.temp_span_c) || st.temp_span_c < 0.0))
    return bad("'temp_span_c' must be a finite number >= 0");
  // Written since the isothermal rule joined the test (absent: not judged, false).
  if (j.contains("temp_failed") && !flag(j, "temp_failed", st.temp_failed))
    return bad("'temp_failed' must be a boolean");
  if (j.contains("cycles")) {
    if (!j["cycles"].is_number_unsigned()) return bad("'cycles' must be a whole number");
    st.cycles = j["cycles"].get<std::size_t>();
  }
  if (auto s = read_g_term(j, st, flag, bad); !s) return s;
  if (auto s = read_noise_outlier(j, st, number, flag, bad); !s) return s;
  // The verdict written must be the verdicts' (a file edited to read "stationary" is not).
  if (j.contains("stationary") && (!j["stationary"].is_boolean() || j["stationary"] == st.failed()))
    return bad("'stationary' contradicts its own verdicts");
  e.stationarity = std::move(st);
  return ok();
}

// A run's cycle print (written since the fifth review of issue 31, F5; absent in older files:
// their copies are found by the cycle signature only).
status read_cycle_print(const std::string& path, const std::string& at, const json& f,
                        calibration_entry& e) {
  const auto it = f.find("cycle_print");
  if (it == f.end()) return ok();
  const json& j = *it;
  const auto bad = [&] {
    return input_error({path}, fmt::format("{}: 'cycle_print' needs a finite 'offset_dps', a "
                                           "'step_dps' > 0 and 'q', an array of whole numbers",
                                           at));
  };
  if (!j.is_object() || !j.contains("offset_dps") || !j["offset_dps"].is_number() ||
      !j.contains("step_dps") || !j["step_dps"].is_number() || !j.contains("q") ||
      !j["q"].is_array())
    return bad();
  method::cycle_print p;
  p.offset_dps = j["offset_dps"].get<double>();
  p.step_dps = j["step_dps"].get<double>();
  if (!std::isfinite(p.offset_dps) || std::abs(p.offset_dps) > max_magnitude ||
      !(p.step_dps > 0.0) || !(p.step_dps <= max_magnitude))
    return bad();
  p.q.reserve(j["q"].size());
  for (const auto& v : j["q"]) {
    if (!v.is_number_integer()) return bad();
    const auto x = v.get<std::int64_t>();
    if (x < -1000000000 || x > 1000000000) return bad();
    p.q.push_back(static_cast<std::int32_t>(x));
  }
  e.print = std::move(p);
  return ok();
}

constexpr std::string_view rig_keys[] = {
    "n_avg", "settle_s",      "positions_deg", "flip",         "filter_word",
    "chop",  "steps_per_rev", "step_rate_sps", "latitude_deg", "axis"};

// Schema 4's `terms`: dN as the scheme's named terms. A file before it holds the 0/180 schemes'
// one term, its pooled dN. The terms must be the scheme's, each once, and `delta_n` the file's
// `delta_n_dps` (one number written twice: an edit of one of them is refused).
status read_terms(const std::string& path, const json& j, calibration_record& rec) {
  const auto expected = method::terms_of(rec.pooled, rec.pairing);
  const auto it = j.find("terms");
  if (it == j.end()) {
    rec.terms = expected;
    return ok();
  }
  if (!it->is_array()) return input_error({path}, "'terms' must be an array of named terms");
  const auto names = method::scheme_of(rec.pairing).terms();
  for (const auto& t : *it) {
    const std::string at = fmt::format("terms[{}]", rec.terms.size());
    if (!t.is_object() || !t.contains("name") || !t["name"].is_string() ||
        !t.contains("value_dps") || !t["value_dps"].is_number())
      return input_error({path}, at + ": each term must be {\"name\", \"value_dps\", ...}");
    method::delta_n_term term;
    term.name = t["name"].get<std::string>();
    term.value_dps = t["value_dps"].get<double>();
    if (t.contains("stderr_correlated_dps")) {
      if (!t["stderr_correlated_dps"].is_number())
        return input_error({path}, at + ": 'stderr_correlated_dps' must be a number");
      term.stderr_correlated_dps = t["stderr_correlated_dps"].get<double>();
    }
    if (std::find(names.begin(), names.end(), term.name) == names.end())
      return input_error({path},
                         fmt::format("{}: '{}' is not a term of the pairing '{}'", at,
                                     printable(term.name, 80), method::to_string(rec.pairing)));
    for (const auto& other : rec.terms)
      if (other.name == term.name)
        return input_error({path}, fmt::format("{}: term '{}' is given twice", at, term.name));
    if (auto s = check_magnitude(path, at + ": value_dps", term.value_dps); !s) return s;
    if (!(term.stderr_correlated_dps >= 0.0) || !(term.stderr_correlated_dps <= max_magnitude))
      return input_error({path}, at + ": 'stderr_correlated_dps' must be a number >= 0");
    rec.terms.push_back(std::move(term));
  }
  for (const auto& e : expected) {
    const auto t = std::find_if(rec.terms.begin(), rec.terms.end(),
                                [&e](const method::delta_n_term& x) { return x.name == e.name; });
    if (t == rec.terms.end())
      return input_error({path}, fmt::format("'terms' lacks the term '{}'", e.name));
    if (e.name == method::delta_n_term_name && t->value_dps != e.value_dps)
      return input_error({path}, fmt::format("terms: '{}' is {} but 'delta_n_dps' {}: one of them "
                                             "was edited",
                                             e.name, t->value_dps, e.value_dps));
  }
  return ok();
}

// Schema 4's `terms_covariance` (a harmonic calibration's): terms.size() rows of as many finite
// numbers, symmetric, with the terms' squared errors on its diagonal.
status read_terms_covariance(const std::string& path, const json& j, calibration_record& rec) {
  const auto it = j.find("terms_covariance");
  if (it == j.end() || it->is_null()) return ok();
  const std::size_t n = rec.terms.size();
  const auto bad = [&path, n] {
    return input_error({path}, fmt::format("'terms_covariance' must be {} rows of {} numbers (the "
                                           "terms' covariance, (deg/s)^2)",
                                           n, n));
  };
  if (!it->is_array() || it->size() != n) return bad();
  for (const auto& row : *it) {
    if (!row.is_array() || row.size() != n) return bad();
    for (const auto& x : row) {
      if (!x.is_number()) return bad();
      const double v = x.get<double>();
      if (!std::isfinite(v)) return bad();
      rec.terms_covariance.push_back(v);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double v = rec.terms_covariance[i * n + i];
    if (!(v >= 0.0)) return input_error({path}, "'terms_covariance': a negative variance");
    for (std::size_t k = 0; k < i; ++k)
      if (rec.terms_covariance[i * n + k] != rec.terms_covariance[k * n + i])
        return input_error({path}, "'terms_covariance' is not symmetric");
  }
  return ok();
}

json separability_json(const method::separability& s) {
  json meanings = json::array(), pairs = json::array();
  for (const auto& m : s.meanings) meanings.push_back({{"term", m.term}, {"holds", m.holds}});
  for (const auto& p : s.pairs)
    pairs.push_back({{"first", p.first},
                     {"second", p.second},
                     {"in_terms", p.in_terms},
                     {"why", p.why},
                     {"separated_by", p.separated_by}});
  json out{{"positions_deg", s.positions},    {"table_axis", s.axis},
           {"estimable", s.estimable},        {"not_observable", s.unobservable},
           {"meanings", std::move(meanings)}, {"inseparable", std::move(pairs)}};
  if (!s.axis_recorded) out["table_axis_recorded"] = false;  // issue 33: taken, not recorded
  return out;
}

// Schema 4's `separability`, as written (strings; a field of another type is refused).
status read_separability(const std::string& path, const json& j, calibration_record& rec) {
  const auto it = j.find("separability");
  if (it == j.end() || it->is_null()) return ok();
  const auto bad = [&path](std::string_view what) {
    return input_error({path}, fmt::format("'separability': {}", what));
  };
  if (!it->is_object()) return bad("must be an object");
  method::separability s;
  const auto text = [&](const char* key, std::string& out) -> bool {
    if (!it->contains(key)) return true;
    if (!(*it)[key].is_string()) return false;
    out = (*it)[key].get<std::string>();
    return true;
  };
  const auto list = [&](const char* key, std::vector<std::string>& out) -> bool {
    if (!it->contains(key)) return true;
    if (!(*it)[key].is_array()) return false;
    for (const auto& x : (*it)[key]) {
      if (!x.is_string()) return false;
      out.push_back(x.get<std::string>());
    }
    return true;
  };
  if (!text("positions_deg", s.positions) || !text("table_axis", s.axis) ||
      !list("estimable", s.estimable) || !list("not_observable", s.unobservable))
    return bad(
        "positions_deg and table_axis are strings, estimable and not_observable lists of "
        "strings");
  if (const auto r = it->find("table_axis_recorded"); r != it->end()) {
    if (!r->is_boolean()) return bad("'table_axis_recorded' must be true or false");
    s.axis_recorded = r->get<bool>();
  }
  for (const char* key : {"meanings", "inseparable"}) {
    if (!it->contains(key)) continue;
    if (!(*it)[key].is_array()) return bad(fmt::format("'{}' must be an array", key));
    for (const auto& x : (*it)[key]) {
      if (!x.is_object()) return bad(fmt::format("'{}' holds objects", key));
      const auto field = [&x](const char* k) {
        return x.contains(k) && x[k].is_string() ? x[k].get<std::string>() : std::string();
      };
      if (std::string_view(key) == "meanings")
        s.meanings.push_back({field("term"), field("holds")});
      else
        s.pairs.push_back({field("first"), field("second"), field("in_terms"), field("why"),
                           field("separated_by")});
    }
  }
  rec.separability = std::move(s);
  return ok();
}

}  // namespace

json stationarity_to_json(const method::stationarity& st) {
  return stationarity_json(st);
}

sensor_record sensor_of(std::span<const csv_metadata> metadata) {
  sensor_record r;
  std::string name;
  std::string serial;
  std::string given;  // `sensor: ...` (simulate's --sensor argument, or a hand-written header)
  for (const auto& m : metadata) {
    if (m.key == "sensor_name") name = m.value;
    if (m.key == "sensor") given = m.value;
    if (m.key == "serial") serial = m.value;
    for (const auto k : rig_keys)
      if (m.key == k) r.rig.push_back(m);
  }
  if (name.empty()) name = given;
  if (!name.empty() || !serial.empty())
    r.sensor =
        serial.empty() ? name : fmt::format("{} serial {}", name.empty() ? "?" : name, serial);
  return r;
}

std::vector<std::string> rig_differences(const sensor_record& a, const sensor_record& b) {
  std::vector<std::string> out;
  for (const auto& x : a.rig)
    for (const auto& y : b.rig)
      if (x.key == y.key && x.value != y.value)
        out.push_back(fmt::format("{} {} vs {}", x.key, x.value, y.value));
  return out;
}

namespace {

// What calibrate said to quote (schema 3, `uncertainty`): read so that compensate quotes the same
// (fourth review of issue 31, F2). null is NaN (not determined); a number must be >= 0.
status read_uncertainty(const std::string& path, const json& j, calibration_record& rec) {
  const auto it = j.find("uncertainty");
  if (it == j.end() || it->is_null()) return ok();
  if (!it->is_object()) return input_error({path}, "'uncertainty' must be an object");
  calibration_uncertainty u;
  const auto number = [&](const char* key, double& out) -> status {
    const auto k = it->find(key);
    if (k == it->end() || k->is_null()) {
      out = std::numeric_limits<double>::quiet_NaN();
      return ok();
    }
    if (!k->is_number() || !(k->get<double>() >= 0.0) || !(k->get<double>() <= max_magnitude))
      return input_error({path},
                         fmt::format("uncertainty: '{}' must be a number >= 0 or null", key));
    out = k->get<double>();
    return ok();
  };
  for (const auto& [key, member] : {std::pair{"new_power_up_dps", &u.new_power_up_dps},
                                    std::pair{"calibrated_dps", &u.calibrated_dps},
                                    std::pair{"repeatability_dps", &u.repeatability_dps},
                                    std::pair{"between_run_dps", &u.between_run_dps},
                                    std::pair{"coverage_factor", &u.coverage_factor}})
    if (auto s = number(key, *member); !s) return s;
  if (const auto k = it->find("repeatability_measured"); k != it->end() && k->is_boolean())
    u.repeatability_measured = k->get<bool>();
  if (const auto k = it->find("repeatability_source"); k != it->end() && k->is_string())
    u.repeatability_source = k->get<std::string>();
  if (const auto k = it->find("dof"); k != it->end() && k->is_number_unsigned())
    u.dof = std::min<std::size_t>(k->get<std::size_t>(), 1000000);
  rec.uncertainty = std::move(u);
  return ok();
}

}  // namespace

method::delta_n_model delta_n_model_of(const calibration_record& rec) {
  if (rec.model) return *rec.model;
  return method::constant_model(rec.pooled.delta_n_dps, rec.pooled.stderr_correlated_dps);
}

std::string separability_to_json(const method::separability& s, const std::string& file) {
  json j = schema_object("separability", 1);
  j["file"] = file.empty() ? json(nullptr) : json(file);
  j.update(separability_json(s));
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::vector<method::delta_n_term> terms_of(const calibration_record& rec) {
  return rec.terms.empty() ? method::terms_of(rec.pooled, rec.pairing) : rec.terms;
}

result<std::string> to_json(const calibration_record& rec) {
  json j = schema_object("calibration", 5);
  j.update(calibration_fields(rec.pooled, rec.geometry));
  j["pairing"] = method::to_string(rec.pairing);
  j["lat_deg"] = rec.geometry ? json(rec.geometry->lat_deg) : json(nullptr);
  j["axis_ned"] = rec.geometry ? json{rec.geometry->axis.north, rec.geometry->axis.east,
                                      rec.geometry->axis.down}
                               : json(nullptr);
  json terms = json::array();
  for (const auto& t : terms_of(rec))
    terms.push_back({{"name", t.name},
                     {"value_dps", t.value_dps},
                     {"stderr_correlated_dps", t.stderr_correlated_dps}});
  j["terms"] = std::move(terms);
  if (!rec.terms_covariance.empty()) {
    const std::size_t n = terms_of(rec).size();
    json cov = json::array();
    for (std::size_t i = 0; i < n && (i + 1) * n <= rec.terms_covariance.size(); ++i)
      cov.push_back(std::vector<double>(
          rec.terms_covariance.begin() + static_cast<std::ptrdiff_t>(i * n),
          rec.terms_covariance.begin() + static_cast<std::ptrdiff_t>((i + 1) * n)));
    j["terms_covariance"] = std::move(cov);
  }
  if (rec.separability) j["separability"] = separability_json(*rec.separability);
  json files = json::array();
  for (const auto& f : rec.files) {
    json e = calibration_fields(f.cal, rec.geometry);
    e["file"] = f.file;
    if (f.source) {
      e["sha256"] = f.source->sha256;
      e["size_bytes"] = f.source->size_bytes;
      e["origin"] = f.source->origin;
      e["origin_detail"] = plain_line(f.source->origin_detail);
    }
    if (f.stationarity) e["stationarity"] = stationarity_json(*f.stationarity);
    if (f.print)
      e["cycle_print"] = {{"offset_dps", f.print->offset_dps},
                          {"step_dps", f.print->step_dps},
                          {"steps_per_std", method::print_steps_per_std},
                          {"q", f.print->q}};
    files.push_back(std::move(e));
  }
  j["files"] = std::move(files);
  if (rec.sensor) {
    json rig = json::object();
    for (const auto& m : rec.sensor->rig) rig[m.key] = m.value;
    j["sensor"] = rec.sensor->sensor;
    j["rig"] = std::move(rig);
  }
  if (rec.model) {
    const auto& m = *rec.model;
    // A random-effects fit without degrees of freedom determines neither its covariance nor its
    // chi^2: null, not 0 (fourth review of issue 31, F8; the reader takes null, and the zeros of
    // older files, as the same).
    const bool determined = m.dof > 0 || !m.random_effects;
    j["model"] = {{"kind", "poly"},
                  {"degree", m.degree()},
                  {"coeffs_dps", m.coeffs_dps},
                  {"t_ref_c", number_or_null(m.t_ref_c)},
                  {"cov", determined ? json(m.cov) : json(nullptr)},
                  {"temp_range_c", {number_or_null(m.temp_min_c), number_or_null(m.temp_max_c)}},
                  {"chi2_per_dof", determined ? json(m.chi2_per_dof) : json(nullptr)},
                  {"fit", m.random_effects ? "random_effects" : "weighted"},
                  {"dof", m.dof},
                  {"between_run_var_dps2", number_or_null(m.between_run_var_dps2)}};
  }
  if (rec.uncertainty) {
    const auto& u = *rec.uncertainty;
    j["uncertainty"] = {{"quote", "new_power_up_dps"},
                        {"new_power_up_dps", number_or_null(u.new_power_up_dps)},
                        {"calibrated_dps", number_or_null(u.calibrated_dps)},
                        {"repeatability_dps", number_or_null(u.repeatability_dps)},
                        {"repeatability_measured", u.repeatability_measured},
                        {"repeatability_source", plain_line(u.repeatability_source)},
                        {"between_run_dps", number_or_null(u.between_run_dps)},
                        {"coverage_factor", u.coverage_factor},
                        {"dof", u.dof},
                        {"level", 0.683}};
  }
  // Every number finite, or no calibration file (finite_output.hpp).
  return finite_dump(j, "calibration");
}

result<calibration_record> read_calibration_file(const std::string& path) {
  auto f = mapped_file::open(path);
  if (!f) return f.err();
  return parse_calibration(f->data(), path);
}

result<calibration_record> parse_calibration(std::string_view text, const std::string& path) {
  json j;
  if (auto parsed = parse_json(path, text); parsed) {
    j = std::move(*parsed);
  } else {
    return parsed.err();
  }
  calibration_record rec;
  try {
    if (!j.is_object() || !j.contains("delta_n_dps"))
      return input_error({path}, "not a gyroflip calibration (no 'delta_n_dps')");
    // Files before schema 1 carry none; another schema is another format (review D3).
    if (const auto sc = j.find("schema"); sc != j.end())
      if (!sc->is_string() || (*sc != "gyroflip.calibration/1" && *sc != "gyroflip.calibration/2" &&
                               *sc != "gyroflip.calibration/3" && *sc != "gyroflip.calibration/4" &&
                               *sc != "gyroflip.calibration/5"))
        return input_error({path}, fmt::format("schema {} is not a gyroflip calibration this "
                                               "version reads (gyroflip.calibration/1 to /5)",
                                               printable(sc->dump(), 80)));
    rec.pooled.delta_n_dps = j.at("delta_n_dps").get<double>();
    if (!std::isfinite(rec.pooled.delta_n_dps))
      return input_error({path}, "'delta_n_dps' is not finite");
    if (j.contains("stderr_correlated_dps") && j["stderr_correlated_dps"].is_number())
      rec.pooled.stderr_correlated_dps = j["stderr_correlated_dps"].get<double>();
    if (j.contains("temp_c") && j["temp_c"].is_number())
      rec.pooled.temp_c = j["temp_c"].get<double>();
    if (j.contains("sensor")) {
      sensor_record sr;
      sr.sensor = j.at("sensor").get<std::string>();
      if (j.contains("rig"))
        for (const auto& [k, v] : j.at("rig").items()) sr.rig.push_back({k, v.get<std::string>()});
      rec.sensor = std::move(sr);
    }
    if (j.contains("pairing")) {
      const auto p = method::parse_pairing(j.at("pairing").get<std::string>());
      if (!p)
        return input_error({path}, fmt::format("'pairing' must be \"{}\"",
                                               method::scheme_names_joined("\" or \"")));
      rec.pairing = *p;
    }
    if (j.contains("model") && !j["model"].is_null()) {
      const json& m = j["model"];
      const auto kind = m.find("kind");
      if (kind == m.end() || !kind->is_string() || kind->get<std::string>() != "poly")
        return input_error({path}, "model 'kind' must be \"poly\"");
      method::delta_n_model model;
      model.coeffs_dps = m.at("coeffs_dps").get<std::vector<double>>();
      model.t_ref_c = m.at("t_ref_c").is_null() ? method::no_value : m.at("t_ref_c").get<double>();
      if (model.coeffs_dps.empty()) return input_error({path}, "model 'coeffs_dps' is empty");
      if (m.contains("cov") && !m["cov"].is_null()) model.cov = m["cov"].get<std::vector<double>>();
      if (m.contains("temp_range_c") && m["temp_range_c"].is_array() &&
          m["temp_range_c"].size() == 2) {
        const json& r = m["temp_range_c"];
        model.temp_min_c = r[0].is_null() ? method::no_value : r[0].get<double>();
        model.temp_max_c = r[1].is_null() ? method::no_value : r[1].get<double>();
      }
      if (m.contains("chi2_per_dof") && m["chi2_per_dof"].is_number())
        model.chi2_per_dof = m["chi2_per_dof"].get<double>();
      // Schema 3: the random-effects fit, its degrees of freedom and between-run variance.
      if (m.contains("fit")) {
        if (!m["fit"].is_string() || (m["fit"] != "random_effects" && m["fit"] != "weighted"))
          return input_error({path}, "model 'fit' must be \"random_effects\" or \"weighted\"");
        model.random_effects = m["fit"] == "random_effects";
      }
      if (m.contains("dof") && m["dof"].is_number_unsigned())
        model.dof = std::min<std::size_t>(m["dof"].get<std::size_t>(), 1000000);
      if (m.contains("between_run_var_dps2") && m["between_run_var_dps2"].is_number())
        model.between_run_var_dps2 = m["between_run_var_dps2"].get<double>();
      // A fit without degrees of freedom: `cov` null (schema 4 since the fourth review of
      // issue 31) or zeros (before), held as zeros as the fit makes it.
      if (model.random_effects && model.dof == 0 && m.contains("cov") && m["cov"].is_null())
        model.cov.assign(model.coeffs_dps.size() * model.coeffs_dps.size(), 0.0);
      if (model.random_effects && model.dof == 0 &&
          model.cov.size() == model.coeffs_dps.size() * model.coeffs_dps.size() &&
          std::any_of(model.cov.begin(), model.cov.end(), [](double c) { return c != 0.0; }))
        return input_error(
            {path}, "model: a random-effects fit without degrees of freedom has no covariance");
      if (model.coeffs_dps.size() > 1 && !std::isfinite(model.t_ref_c))
        return input_error({path}, "model of degree >= 1 needs a finite 't_ref_c'");
      for (double c : model.coeffs_dps)
        if (!std::isfinite(c))
          return input_error({path}, "model 'coeffs_dps' has a non-finite value");
      if (auto s = check_model(path, model); !s) return s.err();
      rec.model = std::move(model);
    }
    // The runs it was made of (their dN and errors: a report's budget of the dN applied).
    if (j.contains("files") && !j["files"].is_array())
      return input_error({path}, "'files' must be an array of runs");
    if (j.contains("files"))
      for (const auto& f : j["files"]) {
        calibration_entry e;
        const std::string at = fmt::format("files[{}]", rec.files.size());
        if (!f.is_object()) return input_error({path}, "files: each run must be an object");
        if (const auto it = f.find("file"); it != f.end() && it->is_string())
          e.file = it->get<std::string>();
        e.cal.delta_n_dps = f.at("delta_n_dps").get<double>();
        if (f.contains("stderr_correlated_dps") && f["stderr_correlated_dps"].is_number())
          e.cal.stderr_correlated_dps = f["stderr_correlated_dps"].get<double>();
        if (f.contains("temp_c") && f["temp_c"].is_number())
          e.cal.temp_c = f["temp_c"].get<double>();
        if (f.contains("cycles") && f["cycles"].is_number_unsigned())
          e.cal.cycles = f["cycles"].get<std::size_t>();
        // The std is part of a run's cycle signature (workflow::repeat_of): compensate tells a
        // copy of a calibration run in other bytes by it (fourth review of issue 31, F6).
        if (f.contains("std_dps") && f["std_dps"].is_number() &&
            std::isfinite(f["std_dps"].get<double>()))
          e.cal.std_dps = f["std_dps"].get<double>();
        if (auto s = read_source(path, at, f, e); !s) return s.err();
        if (auto s = read_stationarity(path, at, f, e); !s) return s.err();
        if (auto s = read_cycle_print(path, at, f, e); !s) return s.err();
        if (auto s = check_magnitude(path, "files: delta_n_dps", e.cal.delta_n_dps); !s)
          return s.err();
        if (!(e.cal.stderr_correlated_dps >= 0.0) ||
            !(e.cal.stderr_correlated_dps <= max_magnitude) ||
            !(std::isnan(e.cal.temp_c) || std::abs(e.cal.temp_c) <= max_magnitude))
          return input_error({path},
                             "files: a run's 'stderr_correlated_dps' or 'temp_c' is out "
                             "of range");
        rec.files.push_back(std::move(e));
      }
    if (auto s = check_magnitude(path, "delta_n_dps", rec.pooled.delta_n_dps); !s) return s.err();
    if (!(rec.pooled.stderr_correlated_dps >= 0.0) ||
        !(rec.pooled.stderr_correlated_dps <= max_magnitude))
      return input_error({path}, "'stderr_correlated_dps' must be a number >= 0");
    if (auto s = read_terms(path, j, rec); !s) return s.err();
    if (auto s = read_terms_covariance(path, j, rec); !s) return s.err();
    if (auto s = read_separability(path, j, rec); !s) return s.err();
    if (auto s = read_uncertainty(path, j, rec); !s) return s.err();
  } catch (const json::exception& e) {
    return input_error({path},
                       fmt::format("malformed calibration: {}", printable(reason(e.what()), 200)));
  }
  return rec;
}

}  // namespace gyroflip::io
