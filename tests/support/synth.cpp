#include "support/synth.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace gyroflip::test {

normal_source::normal_source(std::uint64_t seed) {
  // splitmix64 seeding of a xoshiro256** state.
  for (auto& s : state_) {
    seed += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = seed;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    s = z ^ (z >> 31);
  }
}

std::uint64_t normal_source::next() {
  const auto rotl = [](std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); };
  const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = rotl(state_[3], 45);
  return result;
}

double normal_source::operator()() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double u1 = (static_cast<double>(next() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
  const double u2 = static_cast<double>(next() >> 11) * 0x1.0p-53;
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(2.0 * std::numbers::pi * u2);
  has_spare_ = true;
  return r * std::cos(2.0 * std::numbers::pi * u2);
}

std::vector<method::row> synth_rows(const synth_spec& s) {
  normal_source noise(s.seed);
  std::vector<method::row> rows;
  const auto value = [&](double t, int sign) {
    return sign * (s.delta_n_dps(t) + s.input_dps) + s.bias_dps(t) + s.noise_dps * noise();
  };
  for (std::size_t k = 0; k < s.dwells; ++k) {
    const int sign = ((k % 2 == 0) != s.start_at_180) ? 1 : -1;
    const double angle = sign > 0 ? 0.0 : 180.0;
    const double centre = s.t0_s + static_cast<double>(k) * s.dwell_spacing_s;
    if (s.conversions == 1) {
      rows.push_back({centre, angle, value(centre, sign), s.temp_c, 1});
      continue;
    }
    // Conversions centred on the dwell time, then two "turning" rows with an empty angle.
    const double half = 0.5 * static_cast<double>(s.conversions - 1) * s.conversion_s;
    for (std::uint32_t i = 0; i < s.conversions; ++i) {
      const double t = centre - half + static_cast<double>(i) * s.conversion_s;
      rows.push_back({t, angle, value(t, sign), s.temp_c, 1});
    }
    for (int i = 1; i <= 2; ++i) {
      const double t = centre + half + i * 0.1;
      rows.push_back({t, method::no_value, 123.0, s.temp_c, 1});
    }
  }
  return rows;
}

std::string to_csv(const std::vector<method::row>& rows, bool with_temp) {
  std::string out = "# sensor: synthetic\n";
  out +=
      with_temp ? "time_s,angle_deg,rate_dps,temp_c,n_avg\n" : "time_s,angle_deg,rate_dps,n_avg\n";
  for (const auto& r : rows) {
    const std::string angle =
        std::isnan(r.angle_deg) ? std::string() : fmt::format("{}", r.angle_deg);
    if (with_temp)
      out += fmt::format("{},{},{},{},{}\n", r.time_s, angle, r.rate_dps, r.temp_c, r.n_avg);
    else
      out += fmt::format("{},{},{},{}\n", r.time_s, angle, r.rate_dps, r.n_avg);
  }
  return out;
}

}  // namespace gyroflip::test
