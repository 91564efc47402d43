/// \file
/// \brief The demodulator interface's noise transfer, the 0/180 schemes behind it and the one
/// table of schemes (demodulator.hpp).
#include "gyroflip/method/demodulator.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/method/pairing.hpp"

namespace gyroflip::method {

double noise_transfer::white_autocovariance(std::size_t lag_cycles) const noexcept {
  const std::size_t shift = lag_cycles * cycle_dwells;
  double g = 0.0;
  for (std::size_t k = 0; k + shift < rate_kernel.size(); ++k)
    g += rate_kernel[k] * rate_kernel[k + shift];
  return g;
}

std::array<double, 3> noise_transfer::white_covariance() const noexcept {
  double rr = 0.0, rc = 0.0, cc = 0.0;
  for (std::size_t k = 0; k < rate_kernel.size(); ++k) {
    const double c = k < bias_kernel.size() ? bias_kernel[k] : 0.0;
    rr += rate_kernel[k] * rate_kernel[k];
    rc += rate_kernel[k] * c;
    cc += c * c;
  }
  return {rr, rc, cc};
}

double noise_transfer::white_std_over_adev() const noexcept {
  const double g0 = white_autocovariance(0);
  return std::sqrt(g0 / (g0 - white_autocovariance(1)));
}

double noise_transfer::white_avar_deficit() const noexcept {
  double sum = 0.0, weighted = 0.0;
  for (std::size_t h = 1; h * cycle_dwells < rate_kernel.size(); ++h) {
    const double g = white_autocovariance(h);
    sum += g;
    weighted += static_cast<double>(h) * g;
  }
  return 3.0 * weighted / (white_autocovariance(0) + 2.0 * sum);
}

namespace {

// The 0/180 schemes: the kernels of pairing.cpp (cycle_builder) on the two positions of a
// flip_pair. One class, two schemes: they differ only in the pairing the builder runs.
class flip_demodulator final : public demodulator {
 public:
  flip_demodulator(pairing p, flip_pair pair) noexcept
      : pairing_(p), pair_(pair), cycles_(p, pair) {}
  [[nodiscard]] std::string_view name() const noexcept override { return to_string(pairing_); }
  [[nodiscard]] std::uint32_t uses() const noexcept override {
    return (std::uint32_t{1} << pair_.plus) | (std::uint32_t{1} << pair_.minus);
  }
  [[nodiscard]] std::optional<cycle> push(const dwell& d) override { return cycles_.push(d); }
  [[nodiscard]] std::optional<cycle> flush() override { return cycles_.flush(); }
  [[nodiscard]] std::unique_ptr<demodulator> fresh() const override {
    return std::make_unique<flip_demodulator>(pairing_, pair_);
  }

 private:
  pairing pairing_;
  flip_pair pair_;
  cycle_builder cycles_;
};

// Paper eqn 7: r = (y_a - y_b)/2, c = (y_a + y_b)/2.
const noise_transfer& simple_transfer() {
  static const noise_transfer t{{0.5, -0.5}, {0.5, 0.5}, 0, 2};
  return t;
}

// abba (pairing.hpp), equal spacing: the mean of the three-point estimates at the cycle's dwells
// a, b with neighbours p (before a) and n (after b): r = (-y_p + 3 y_a - 3 y_b + y_n)/8; c = (c_a
// + c_b)/2 with c_a = (y_a + (y_p + y_b)/2)/2, c_b = (y_b + (y_a + y_n)/2)/2, so (y_p + 3 y_a +
// 3 y_b + y_n)/8.
const noise_transfer& abba_transfer() {
  static const noise_transfer t{{-0.125, 0.375, -0.375, 0.125}, {0.125, 0.375, 0.375, 0.125}, 1, 2};
  return t;
}

result<std::unique_ptr<demodulator>> make_flip(pairing p, const position_table& table,
                                               const std::string& source) {
  auto pair = flip_pair_of(table, source);
  if (!pair) return pair.err();
  return make_flip_demodulator(p, *pair);
}

result<std::unique_ptr<demodulator>> make_abba(const position_table& table,
                                               const std::string& source) {
  return make_flip(pairing::abba, table, source);
}

result<std::unique_ptr<demodulator>> make_simple(const position_table& table,
                                                 const std::string& source) {
  return make_flip(pairing::simple, table, source);
}

// The 0/180 schemes' one term of dN.
std::span<const std::string_view> flip_terms() {
  static constexpr std::array<std::string_view, 1> names{delta_n_term_name};
  return names;
}

// The harmonic scheme's stated transfer: the four-position sweep 0, 90, 180, 270, 270, 180, 90,
// 0 (harmonic_transfer gives any other table and order).
const noise_transfer& harmonic_sweep_transfer() {
  static const noise_transfer t = [] {
    const double a[4] = {0.0, 90.0, 180.0, 270.0};
    const int order[8] = {0, 1, 2, 3, 3, 2, 1, 0};
    return *harmonic_transfer(*position_table::of_angles(a), order);
  }();
  return t;
}

std::span<const std::string_view> harmonic_terms() {
  return harmonic_term_names;
}

// The one table of schemes (pairing::abba is row 0, pairing::simple row 1, pairing::harmonic
// row 2: types.hpp).
constexpr std::array<scheme, 3> table_of_schemes{{
    {"abba", "abba",
     "each dwell against its opposite neighbours interpolated to its time (three-point chop); "
     "cancels a linear bias drift",
     abba_transfer, flip_terms, make_abba},
    {"simple", "simple (paper)", "adjacent 0/180 dwells, r = (y0 - y180)/2 (paper eqn 7)",
     simple_transfer, flip_terms, make_simple},
    {"harmonic", "harmonic (N positions)",
     "3 or more positions, one estimate per visiting period: least squares of the bias, its "
     "slope and the harmonics the table separates (docs/METHOD-NOTES.md)",
     harmonic_sweep_transfer, harmonic_terms, make_harmonic_demodulator},
}};

// kappa as a fraction with a power-of-two denominator (9/16) when it is one, else as a number.
std::string fraction(double x) {
  for (int d = 1; d <= 1024; d *= 2) {
    const double n = x * d;
    if (n == std::floor(n)) return d == 1 ? fmt::format("{:g}", n) : fmt::format("{:g}/{}", n, d);
  }
  return fmt::format("{:.4g}", x);
}

}  // namespace

std::span<const scheme> schemes() noexcept {
  return table_of_schemes;
}

const scheme& scheme_of(pairing p) noexcept {
  return table_of_schemes[std::min<std::size_t>(p.id, table_of_schemes.size() - 1)];
}

std::vector<std::string> scheme_names() {
  std::vector<std::string> out;
  for (const auto& s : table_of_schemes) out.emplace_back(s.name);
  return out;
}

std::string scheme_names_joined(std::string_view separator) {
  std::string out;
  for (const auto& s : table_of_schemes) {
    if (!out.empty()) out += separator;
    out += s.name;
  }
  return out;
}

std::unique_ptr<demodulator> make_flip_demodulator(pairing p, flip_pair pair) {
  return std::make_unique<flip_demodulator>(p, pair);
}

result<std::unique_ptr<demodulator>> make_demodulator(pairing p, const position_table& table,
                                                      const std::string& source) {
  return scheme_of(p).make(table, source);
}

std::vector<delta_n_term> terms_of(const calibration& cal, pairing p) {
  const auto names = scheme_of(p).terms();
  // The 0/180 schemes: one term, the calibration's dN.
  std::vector<delta_n_term> out;
  for (const auto name : names)
    if (name == delta_n_term_name)
      out.push_back({std::string(name), cal.delta_n_dps, cal.stderr_correlated_dps});
  return out;
}

analysis::noise_series noise_series_of(pairing p, double cycle_s) {
  const auto& t = scheme_of(p).transfer();
  analysis::noise_series s;
  s.cycle_s = cycle_s;
  s.white_avar_deficit = t.white_avar_deficit();
  if (s.shaped())
    s.note = fmt::format(
        "cycle values of the {} pairing (spacing {:g} s): neighbouring cycles share dwells "
        "(lag-1 correlation {:g} for white dwell noise), which the ARW term models as "
        "N^2 (1/tau - ({}) T/tau^2); without it that correlation reads as a false floor",
        to_string(p), cycle_s, t.white_autocovariance(1) / t.white_autocovariance(0),
        fraction(s.white_avar_deficit));
  return s;
}

}  // namespace gyroflip::method
