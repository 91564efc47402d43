/// \file
/// \brief Builds the user-facing error messages (see error.hpp).
#include "gyroflip/core/error.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace gyroflip {

namespace {

// File names in messages: any length a path can have, but made printable (a name with invalid
// UTF-8 or control bytes would garble a terminal and make the JSON of a report invalid).
constexpr std::size_t path_max = 4096;

// Length of the valid UTF-8 sequence at s[i] (2..4), or 0 (invalid, overlong, surrogate, or
// beyond U+10FFFF; RFC 3629 section 4).
std::size_t utf8_sequence(std::string_view s, std::size_t i) {
  const auto b0 = static_cast<unsigned char>(s[i]);
  std::size_t len = 0;
  unsigned lo = 0x80;
  unsigned hi = 0xbf;
  if (b0 >= 0xc2 && b0 <= 0xdf) {
    len = 2;
  } else if (b0 >= 0xe0 && b0 <= 0xef) {
    len = 3;
    if (b0 == 0xe0) lo = 0xa0;
    if (b0 == 0xed) hi = 0x9f;
  } else if (b0 >= 0xf0 && b0 <= 0xf4) {
    len = 4;
    if (b0 == 0xf0) lo = 0x90;
    if (b0 == 0xf4) hi = 0x8f;
  } else {
    return 0;
  }
  if (i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k) {
    const auto b = static_cast<unsigned char>(s[i + k]);
    if (b < (k == 1 ? lo : 0x80u) || b > (k == 1 ? hi : 0xbfu)) return 0;
  }
  return len;
}

}  // namespace

bool is_valid_utf8(std::string_view text) noexcept {
  for (std::size_t i = 0; i < text.size();) {
    if (static_cast<unsigned char>(text[i]) < 0x80) {
      ++i;
      continue;
    }
    const std::size_t len = utf8_sequence(text, i);
    if (len == 0) return false;
    i += len;
  }
  return true;
}

status check_name_for_json(std::string_view file) {
  if (is_valid_utf8(file)) return ok();
  return input_error({file},
                     "the file name is not valid UTF-8, which JSON output cannot carry "
                     "(rename the file, or leave out the JSON output)");
}

namespace {

// The code point of the invisible control at text[i] (see visible_controls), or 0. All of them
// are two- or three-byte UTF-8 sequences.
unsigned direction_control_at(std::string_view text, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[i + k]); };
  if (i + 1 < text.size() && b(0) == 0xd8 && b(1) == 0x9c) return 0x061c;
  if (i + 2 >= text.size()) return 0;
  const unsigned cp = ((b(0) & 0x0fU) << 12U) | ((b(1) & 0x3fU) << 6U) | (b(2) & 0x3fU);
  if ((b(0) & 0xf0U) != 0xe0U || (b(1) & 0xc0U) != 0x80U || (b(2) & 0xc0U) != 0x80U) return 0;
  const bool control = cp == 0x200e || cp == 0x200f || (cp >= 0x2028 && cp <= 0x202e) ||
                       (cp >= 0x2066 && cp <= 0x2069) || cp == 0xfeff;
  return control ? cp : 0;
}

}  // namespace

std::string visible_controls(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (const unsigned cp = direction_control_at(text, i); cp != 0) {
      out += fmt::format("\\u{:04x}", cp);
      i += cp == 0x061c ? 1 : 2;
      continue;
    }
    out += text[i];
  }
  return out;
}

std::string printable(std::string_view text, std::size_t max_bytes) {
  std::string out;
  const std::size_t n = std::min(text.size(), max_bytes);
  out.reserve(n + 24);
  std::size_t i = 0;
  while (i < n) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    // Valid UTF-8 (a file name in another script) stays; C1 controls (U+0080..U+009F) do not.
    const std::size_t len = c >= 0x80 ? utf8_sequence(text, i) : 0;
    if (len > 0 && i + len <= n && !(c == 0xc2 && static_cast<unsigned char>(text[i + 1]) < 0xa0)) {
      out.append(text.substr(i, len));
      i += len;
      continue;
    }
    out += fmt::format("\\x{:02x}", c);
    ++i;
  }
  if (text.size() > i) out += fmt::format("... ({} more bytes)", text.size() - i);
  return visible_controls(out);
}

error input_error(const source_location& where, std::string_view what) {
  if (where.line != 0 && where.column != 0)
    return {errc::bad_input, fmt::format("{}:{}:{}: {}", printable(where.file, path_max),
                                         where.line, where.column, what)};
  if (where.line != 0)
    return {errc::bad_input,
            fmt::format("{}:{}: {}", printable(where.file, path_max), where.line, what)};
  return {errc::bad_input, fmt::format("{}: {}", printable(where.file, path_max), what)};
}

error io_error(std::string_view file, std::string_view what) {
  return {errc::io, fmt::format("{}: {}", printable(file, path_max), what)};
}

error runtime_error(std::string_view what) {
  return {errc::runtime, std::string(what)};
}

error usage_error(std::string_view what) {
  return {errc::bad_input, std::string(what)};
}

error parameter_error(std::string_view parameter, std::string_view what) {
  return {errc::bad_input, std::string(what), std::string(parameter)};
}

error about_parameter(error e, std::string_view parameter) {
  e.parameter = parameter;
  return e;
}

}  // namespace gyroflip
