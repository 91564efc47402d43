/// \file
/// \brief Rate and temperature profiles (syntax in profiles.hpp).
#include "gyroflip/rig/profiles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"

namespace gyroflip::rig {
namespace {

// The fields of `s` at `sep` and whole-field numbers: core's tokenizer (text.hpp).
std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  for (const auto& t : text::split(s, sep)) out.push_back(t.text);
  return out;
}

bool to_double(std::string_view s, double& x) {
  const auto v = text::to_double(s);
  if (v) x = *v;
  return v.has_value();
}

error bad_spec(std::string_view what, std::string_view spec, std::string_view why) {
  return usage_error(fmt::format("{} '{}': {}", what, printable(spec, 80), why));
}

// Parses "a:b:c" numbers after the kind word; `count` numbers (optional extra allowed).
result<std::vector<double>> numbers(std::string_view what, std::string_view spec,
                                    const std::vector<std::string_view>& parts, std::size_t min_n,
                                    std::size_t max_n) {
  if (parts.size() - 1 < min_n || parts.size() - 1 > max_n) {
    return bad_spec(what, spec, fmt::format("expected {} numbers after '{}:'", min_n, parts[0]));
  }
  std::vector<double> v(parts.size() - 1);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    if (!to_double(parts[i], v[i - 1])) {
      return bad_spec(what, spec,
                      fmt::format("'{}' is not a finite number", printable(parts[i], 40)));
    }
  }
  return v;
}

}  // namespace

profile profile::constant(double value) {
  profile p;
  p.value_ = value;
  return p;
}

namespace {
// `steps:T0:V0,T1:V1,...` shared by both profile kinds.
status parse_steps(std::string_view what, std::string_view spec, std::string_view body,
                   std::vector<double>& t, std::vector<double>& v) {
  for (auto item : split(body, ',')) {
    const auto tv = split(item, ':');
    double a = 0.0;
    double b = 0.0;
    if (tv.size() != 2 || !to_double(tv[0], a) || !to_double(tv[1], b)) {
      return bad_spec(what, spec, fmt::format("'{}' is not TIME_S:VALUE", printable(item, 40)));
    }
    if (!t.empty() && !(a > t.back())) return bad_spec(what, spec, "times must increase");
    t.push_back(a);
    v.push_back(b);
  }
  return ok();
}
}  // namespace

status profile::check_range(std::string_view what, double lo, double hi) const {
  double a = value_;
  double b = value_;
  if (kind_ == kind::sine || kind_ == kind::triangle) {
    a = value_ - std::abs(amp_);
    b = value_ + std::abs(amp_);
  } else if (kind_ != kind::constant) {
    a = *std::min_element(v_.begin(), v_.end());
    b = *std::max_element(v_.begin(), v_.end());
  }
  if (a >= lo && b <= hi) return ok();
  return usage_error(
      fmt::format("{} reaches {:g}..{:g}, outside [{:g}, {:g}]", what, a, b, lo, hi));
}

result<profile> profile::parse_rate(std::string_view spec) {
  constexpr std::string_view what = "rate profile";
  const auto parts = split(spec, ':');
  if (parts[0] == "sine") {
    auto n = numbers(what, spec, parts, 2, 3);
    if (!n) return n.err();
    profile p;
    if (!((*n)[1] >= 0.0 && (*n)[1] <= 1.0 / min_time_s))
      return bad_spec(what, spec,
                      fmt::format("frequency must be in [0, {:g}] Hz", 1.0 / min_time_s));
    p.kind_ = kind::sine;
    p.amp_ = (*n)[0];
    p.freq_hz_ = (*n)[1];
    p.value_ = n->size() > 2 ? (*n)[2] : 0.0;
    return p;
  }
  if (auto shared = parse_shared(what, spec, 0.0)) return std::move(*shared);
  return bad_spec(what, spec,
                  "expected a number, const:V, steps:T:V,... or sine:AMP:FREQ[:OFFSET]");
}

std::optional<result<profile>> profile::parse_shared(std::string_view what, std::string_view spec,
                                                     std::optional<double> before_steps) {
  double x = 0.0;
  if (to_double(spec, x)) return constant(x);
  const auto parts = split(spec, ':');
  if (parts[0] == "const") {
    auto n = numbers(what, spec, parts, 1, 1);
    if (!n) return result<profile>(n.err());
    return constant((*n)[0]);
  }
  if (parts[0] == "steps") {
    profile p;
    p.kind_ = kind::hold;
    if (before_steps) {  // a rate is 0 before the first step; a temperature starts at V0
      p.t_s_.push_back(-1e300);
      p.v_.push_back(*before_steps);
    }
    if (auto s = parse_steps(what, spec, spec.substr(6), p.t_s_, p.v_); !s) {
      return result<profile>(s.err());
    }
    return p;
  }
  return std::nullopt;
}

result<profile> profile::parse_temperature(std::string_view spec) {
  constexpr std::string_view what = "temperature profile";
  if (auto shared = parse_shared(what, spec, std::nullopt)) return std::move(*shared);
  const auto parts = split(spec, ':');
  profile p;
  if (parts[0] == "ramp") {
    auto n = numbers(what, spec, parts, 3, 3);
    if (!n) return n.err();
    if (!((*n)[2] >= min_time_s))
      return bad_spec(what, spec, fmt::format("duration must be >= {:g} s", min_time_s));
    p.kind_ = kind::linear;
    p.t_s_ = {0.0, (*n)[2]};
    p.v_ = {(*n)[0], (*n)[1]};
    return p;
  }
  if (parts[0] == "fridge") {
    auto n = numbers(what, spec, parts, 3, 3);
    if (!n) return n.err();
    if (!((*n)[2] >= min_time_s))
      return bad_spec(what, spec, fmt::format("period must be >= {:g} s", min_time_s));
    p.kind_ = kind::triangle;
    p.value_ = (*n)[0];
    p.amp_ = (*n)[1] / 2.0;
    p.half_period_s_ = (*n)[2] / 2.0;
    return p;
  }
  return bad_spec(what, spec,
                  "expected a number, const:V, steps:T:V,..., ramp:FROM:TO:DUR_S or "
                  "fridge:MEAN:SWING:PERIOD_S (a CSV file is read by the caller)");
}

bool profile::is_temperature_spec(std::string_view spec) {
  double x = 0.0;
  if (to_double(spec, x)) return true;
  const auto kind = split(spec, ':')[0];
  return kind == "const" || kind == "steps" || kind == "ramp" || kind == "fridge";
}

result<profile> profile::table(std::vector<double> t_s, std::vector<double> v) {
  if (t_s.empty() || t_s.size() != v.size())
    return usage_error("a profile table needs as many values as times, and at least one");
  for (std::size_t i = 0; i < t_s.size(); ++i) {
    if (!std::isfinite(t_s[i]) || !std::isfinite(v[i]))
      return usage_error(fmt::format("profile table row {}: not a finite number", i + 1));
    if (i > 0 && !(t_s[i] > t_s[i - 1]))
      return usage_error(fmt::format("profile table row {}: time must increase", i + 1));
  }
  profile p;
  p.kind_ = kind::linear;
  p.t_s_ = std::move(t_s);
  p.v_ = std::move(v);
  return p;
}

double profile::eval(double t) noexcept {
  if (kind_ == kind::sine) return value_ + amp_ * std::sin(2.0 * std::numbers::pi * freq_hz_ * t);
  return piece_at(t).at(t);
}

profile::piece profile::triangle_piece(std::int64_t half) const noexcept {
  // Even halves fall from MEAN + A to MEAN - A, odd halves rise back (2A per half period).
  const double t0 = static_cast<double>(half) * half_period_s_;
  const double slope = 2.0 * amp_ / half_period_s_;
  const bool falling = half % 2 == 0;
  return {t0, falling ? value_ + amp_ : value_ - amp_, falling ? -slope : slope,
          static_cast<double>(half + 1) * half_period_s_};
}

profile::piece profile::piece_at(double t) noexcept {
  constexpr double inf = std::numeric_limits<double>::infinity();
  switch (kind_) {
    case kind::constant:
    case kind::sine:  // not affine: eval() handles it; here only to keep the switch total
      return {0.0, value_, 0.0, inf};
    case kind::triangle: {
      piece p = triangle_piece(half_);
      if (half_ >= 0 && t >= p.t0_s && t < p.t_end_s) return p;
      // The next half when time moves on by less than a half period (the simulator's case),
      // else from scratch. Rounding may leave t a hair outside the piece: the triangle is
      // continuous, so the value is still right to the last bits.
      if (half_ >= 0 && t >= p.t_end_s && t < p.t_end_s + half_period_s_) {
        ++half_;
      } else {
        half_ = static_cast<std::int64_t>(std::floor(t / half_period_s_));
      }
      return triangle_piece(half_);
    }
    case kind::hold:
    case kind::linear:
      break;
  }
  if (cursor_ >= t_s_.size() || t < t_s_[cursor_]) cursor_ = 0;  // time went back: rescan
  while (cursor_ + 1 < t_s_.size() && t >= t_s_[cursor_ + 1]) ++cursor_;
  const std::size_t c = cursor_;
  if (t < t_s_[c]) return {t_s_[c], v_[c], 0.0, t_s_[c]};  // before the first knot: held
  const bool last = c + 1 == t_s_.size();
  const double t_end = last ? inf : t_s_[c + 1];
  if (kind_ == kind::hold || last) return {t_s_[c], v_[c], 0.0, t_end};
  return {t_s_[c], v_[c], (v_[c + 1] - v_[c]) / (t_s_[c + 1] - t_s_[c]), t_end};
}

void profile::fill(const double* t_s, double* out, std::size_t n) noexcept {
  if (kind_ == kind::constant) {
    std::fill(out, out + n, value_);
    return;
  }
  if (kind_ == kind::sine) {
    for (std::size_t i = 0; i < n; ++i) out[i] = eval(t_s[i]);
    return;
  }
  std::size_t i = 0;
  while (i < n) {
    const piece p = piece_at(t_s[i]);
    // Times are sorted: the piece covers t_s[i] and every later time before its end.
    const double* end =
        std::partition_point(t_s + i + 1, t_s + n, [&](double t) { return t < p.t_end_s; });
    const auto m = static_cast<std::size_t>(end - t_s);
    if (p.slope_per_s == 0.0) {
      std::fill(out + i, out + m, p.v0);
    } else {
      for (std::size_t k = i; k < m; ++k) out[k] = p.v0 + p.slope_per_s * (t_s[k] - p.t0_s);
    }
    i = m;
  }
}

}  // namespace gyroflip::rig
