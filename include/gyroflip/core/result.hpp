/// \file
/// \brief `gyroflip::result<T>`: a value or an error, for failures that depend on the data.
///
/// C++20 has no `std::expected` (g++ 12), so the library returns this small type instead of
/// throwing. Broken preconditions (programming errors) are asserted, not returned.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace gyroflip {

/// What went wrong, coarsely; the CLI maps it to an exit code (docs/cli.md).
enum class errc {
  bad_input,  ///< the user's data or arguments are malformed (exit 2)
  io,         ///< a file could not be opened, read or written (exit 2)
  runtime,    ///< the input is valid but the computation cannot proceed (exit 1)
};

/// An error code plus the complete, user-facing message (already carrying FILE:LINE:COL).
struct error {
  errc code;
  std::string message;
  /// The library parameter the error is about (`sample_rate_hz`, `duration_s`, ...), or empty.
  /// The library never names a CLI flag; a front end maps this to its own option name.
  std::string parameter{};
};

/// Either a `T` or an `error`. Accessing the wrong alternative is a programming error.
template <class T>
class [[nodiscard]] result {
 public:
  result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit by design
  result(error e) : v_(std::in_place_index<1>, std::move(e)) {}      // NOLINT: implicit by design

  [[nodiscard]] bool ok() const noexcept { return v_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }

  [[nodiscard]] T& value() & {
    assert(ok());
    return std::get<0>(v_);
  }
  [[nodiscard]] const T& value() const& {
    assert(ok());
    return std::get<0>(v_);
  }
  [[nodiscard]] T&& value() && {
    assert(ok());
    return std::get<0>(std::move(v_));
  }
  [[nodiscard]] const error& err() const& {
    assert(!ok());
    return std::get<1>(v_);
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::variant<T, error> v_;
};

/// Success without a value.
struct ok_t {};
using status = result<ok_t>;
inline status ok() {
  return ok_t{};
}

}  // namespace gyroflip
