/// \file
/// \brief The finite-output gate (see finite_output.hpp).
#include "gyroflip/io/finite_output.hpp"

#include <array>
#include <cctype>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/error.hpp"

namespace gyroflip::io {
namespace {

bool separator(char c) {
  return c == ',' || c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == '[' || c == ']' ||
         c == '(' || c == ')' || c == ':' || c == ';' || c == '=';
}

bool non_finite_token(std::string_view t) {
  if (!t.empty() && (t.front() == '-' || t.front() == '+')) t.remove_prefix(1);
  if (t.size() != 3 && t.size() != 8) return false;
  std::string low(t);
  for (auto& c : low) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return low == "nan" || low == "inf" || low == "infinity";
}

bool all_finite(const nlohmann::json& j) {
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_array() || j.is_object()) {
    for (const auto& v : j)
      if (!all_finite(v)) return false;
  }
  return true;
}

error not_finite(std::string_view what) {
  return input_error({what},
                     "a computed value is not finite: the input holds numbers beyond what the "
                     "computation can represent; nothing was written");
}

}  // namespace

status check_finite(std::string_view text, std::string_view what) {
  // Every non-finite token contains an 'n' or 'N' ("nan", "inf", "infinity"): look only there,
  // with memchr (CSV rows of numbers have none, so a clean chunk costs two fast scans).
  for (const char letter : {'n', 'N'}) {
    for (std::size_t at = 0; at < text.size(); ++at) {
      const auto* hit =
          static_cast<const char*>(std::memchr(text.data() + at, letter, text.size() - at));
      if (hit == nullptr) break;
      at = static_cast<std::size_t>(hit - text.data());
      std::size_t b = at;
      while (b > 0 && !separator(text[b - 1])) --b;
      std::size_t e = at;
      while (e < text.size() && !separator(text[e])) ++e;
      if (non_finite_token(text.substr(b, e - b))) return not_finite(what);
      at = e;
    }
  }
  return ok();
}

status check_finite(std::span<const double> values, std::string_view what) {
  for (const double v : values)
    if (!std::isfinite(v)) return not_finite(what);
  return ok();
}

status check_finite(std::span<const method::compensated_cycle> cycles,
                    const method::compensation_summary& summary, std::string_view what) {
  for (const auto& c : cycles)
    if (auto s = check_finite(std::array{c.time_s, c.rate_dps, c.bias_dps, c.delta_n_dps}, what);
        !s)
      return s;
  return check_finite(std::array{summary.mean_dps, summary.std_dps, summary.stderr_dps,
                                 summary.stderr_correlated_dps, summary.drift_dps.value_or(0.0),
                                 summary.drift_window_s, summary.duration_s},
                      what);
}

result<std::string> finite_dump(const nlohmann::json& j, std::string_view what) {
  if (!all_finite(j)) return not_finite(what);
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace gyroflip::io
