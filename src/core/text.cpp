/// \file
/// \brief The tokenizer of short texts (see text.hpp).
#include "gyroflip/core/text.hpp"

#include <charconv>
#include <cmath>

namespace gyroflip::text {

std::string_view trim(std::string_view s) noexcept {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<token> split(std::string_view s, char sep) {
  std::vector<token> out;
  std::size_t start = 0;
  while (true) {
    const auto p = s.find(sep, start);
    const std::string_view raw = s.substr(start, p == std::string_view::npos ? p : p - start);
    const std::string_view t = trim(raw);
    out.push_back({t, start + 1 + static_cast<std::size_t>(t.data() - raw.data())});
    if (p == std::string_view::npos) return out;
    start = p + 1;
  }
}

std::optional<double> to_double(std::string_view s) noexcept {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double x = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (s.empty() || ec != std::errc{} || end != s.data() + s.size() || !std::isfinite(x))
    return std::nullopt;
  return x;
}

std::optional<std::uint64_t> to_unsigned(std::string_view s) noexcept {
  s = trim(s);
  std::uint64_t x = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
  if (s.empty() || ec != std::errc{} || end != s.data() + s.size()) return std::nullopt;
  return x;
}

std::optional<std::vector<double>> to_doubles(std::string_view s, char sep, token* bad) {
  std::vector<double> out;
  for (const auto& t : split(s, sep)) {
    const auto v = to_double(t.text);
    if (!v) {
      if (bad != nullptr) *bad = t;
      return std::nullopt;
    }
    out.push_back(*v);
  }
  return out;
}

}  // namespace gyroflip::text
