/// \file
/// \brief How many digits a number with an uncertainty supports: the one rule of every "v ± u"
/// the report, the budget and the figures print.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

namespace gyroflip {

/// The decimals that show an uncertainty `u` > 0 to two significant digits (1.2e-5 -> 6; 0.35
/// -> 2; 120 -> 0), at most 15. The value beside it takes the same decimals.
[[nodiscard]] inline int decimals_of_error(double u) {
  return std::clamp(1 - static_cast<int>(std::floor(std::log10(u))), 0, 15);
}

/// `v` rounded at the second significant digit of its uncertainty `u` > 0 where that lies left
/// of the decimal point (u = 3613: to hundreds, -1507 -> -1500; review of issue 31, L2: "-1507 ±
/// 3613 ppm"); otherwise `v` itself (decimals_of_error then rounds it in print). No -0.
[[nodiscard]] inline double rounded_to_error(double v, double u) {
  const int place = 1 - static_cast<int>(std::floor(std::log10(u)));
  if (place >= 0) return v;
  const double unit = std::pow(10.0, -place);
  return std::round(v / unit) * unit + 0.0;
}

/// `v` and `u` > 0 each in fixed notation at the second significant digit of `u`: ("0.00327",
/// "0.00081"), ("-1500", "3600"). The one rule of every "v ± u".
/// A value that rounds to zero prints without its sign ("0.00000 ± 0.00098", not "-0.00000";
/// third review of issue 31).
/// Past a million (|v| or u >= 1e6) both take scientific notation at one exponent, the larger
/// one's, with the mantissa's decimals at u's second significant digit ("-4.5e+96", "5.2e+96";
/// fifth review of issue 31, F12: 97 fixed digits, most of them invented).
[[nodiscard]] inline std::pair<std::string, std::string> digits_of_error(double v, double u) {
  if (std::max(std::abs(v), u) >= 1e6) {
    const int eu = static_cast<int>(std::floor(std::log10(u)));
    const double top = std::max(std::abs(rounded_to_error(v, u)), rounded_to_error(u, u));
    const int e = std::max(eu, static_cast<int>(std::floor(std::log10(top))));
    const int decimals = std::clamp(e - eu + 1, 0, 15);
    const double scale = std::pow(10.0, -e);
    const auto sci = [&](double x) {
      std::string m = fmt::format("{:.{}f}", x * scale, decimals);
      if (m.front() == '-' && m.find_first_not_of("-0.") == std::string::npos) m.erase(0, 1);
      return fmt::format("{}e{:+03d}", m, e);
    };
    return {sci(v), sci(u)};
  }
  const int decimals = decimals_of_error(u);
  std::string value = fmt::format("{:.{}f}", rounded_to_error(v, u), decimals);
  if (value.front() == '-' && value.find_first_not_of("-0.") == std::string::npos)
    value.erase(0, 1);
  return {value, fmt::format("{:.{}f}", rounded_to_error(u, u), decimals)};
}

/// `v` to `n` >= 1 significant digits with its significant trailing zeros ("0.00020", not
/// "0.0002" as `{:.2g}` prints; review of issue 31, L2) and no trailing decimal point ("12").
[[nodiscard]] inline std::string significant(double v, int n) {
  if (!std::isfinite(v) || n < 1) return fmt::format("{}", v);
  if (v == 0.0) return fmt::format("{:.{}f}", 0.0, n - 1);
  // The exponent after rounding to n digits (9.96 -> 1.0e+01), then fixed notation with the
  // decimals that show n digits; scientific far from 1.
  const std::string sci = fmt::format("{:.{}e}", v, n - 1);
  const int exponent = std::stoi(sci.substr(sci.find('e') + 1));
  if (exponent < -5 || exponent >= 15) return sci;
  return fmt::format("{:.{}f}", v, std::max(0, n - 1 - exponent));
}

/// `v` to `n` >= 1 significant digits in fixed notation whatever its size ("0.0000086", "1230",
/// "0.00020"): the report pages' one notation, so a column never holds "8.6e-06" beside
/// "0.000010" (fourth review of issue 31, low; significant() turns scientific below 1e-5). At most
/// 15 decimals (smaller numbers print as zeros); no -0.
[[nodiscard]] inline std::string fixed_significant(double v, int n) {
  if (!std::isfinite(v) || n < 1) return fmt::format("{}", v);
  if (v == 0.0) return fmt::format("{:.{}f}", 0.0, n - 1);
  const std::string sci = fmt::format("{:.{}e}", v, n - 1);
  const int exponent = std::stoi(sci.substr(sci.find('e') + 1));
  const int decimals = std::clamp(n - 1 - exponent, 0, 15);
  double shown = v;
  if (n - 1 - exponent < 0) {  // round left of the decimal point: 1234 to 3 digits is 1230
    const double unit = std::pow(10.0, exponent - (n - 1));
    shown = std::round(v / unit) * unit;
  }
  std::string text = fmt::format("{:.{}f}", shown, decimals);
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

/// `v` with the digits its uncertainty `u` supports (digits_of_error's rule), without the ±;
/// without a usable `u` (not finite, or not > 0) `v` to `fallback_digits` significant digits with
/// their trailing zeros, in fixed notation (fixed_significant); "–" for a `v` that is not finite.
/// The one formatter of a number printed beside, or instead of, its "± u" (third review of issue
/// 31, H4: the report and its figures each had a copy, differing in the fallback).
[[nodiscard]] inline std::string to_digits_of(double v, double u, int fallback_digits) {
  if (!std::isfinite(v)) return "–";
  if (!(std::isfinite(u) && u > 0.0)) return fixed_significant(v, fallback_digits);
  return digits_of_error(v, u).first;
}

}  // namespace gyroflip
