/// \file
/// \brief The one tokenizer of short texts: option values and specs ("0,180", "N,E,D",
/// "1,2,10", "steps:0:20,600:4"), split into fields with their columns, and numbers parsed whole
/// (std::from_chars: locale-free, exact). Files are read by io's csv_reader, not here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace gyroflip::text {

/// `s` without leading and trailing blanks (space, tab, CR).
[[nodiscard]] std::string_view trim(std::string_view s) noexcept;

/// One field of a split text: its text, blanks trimmed, and its 1-based column in the text.
struct token {
  std::string_view text;
  std::size_t column = 1;
};

/// Splits `s` at every `sep` ("a,,b" has three fields, the middle one empty; "" has one).
[[nodiscard]] std::vector<token> split(std::string_view s, char sep);

/// The whole of `s` (trimmed; a leading '+' allowed) as a finite double, or nullopt (empty,
/// trailing text, nan, inf, out of the range of a double).
[[nodiscard]] std::optional<double> to_double(std::string_view s) noexcept;

/// The whole of `s` (trimmed) as an unsigned integer, or nullopt (sign, trailing text, overflow).
[[nodiscard]] std::optional<std::uint64_t> to_unsigned(std::string_view s) noexcept;

/// `s` split at `sep` into finite doubles; nullopt when a field is not one. `bad`, when not null,
/// receives the first offending field.
[[nodiscard]] std::optional<std::vector<double>> to_doubles(std::string_view s, char sep,
                                                            token* bad = nullptr);

}  // namespace gyroflip::text
