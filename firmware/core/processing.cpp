/// \file
/// \brief Fixed-point processing (processing.hpp).
#include "firmware/core/processing.hpp"

#include "firmware/util/intmath.hpp"

namespace gyroflip::fw {

int32_t mean_q8(int64_t sum, uint32_t n) {
  return static_cast<int32_t>(div_round(sum * 256, n));
}

cycle_q8 make_cycle(int32_t mean_a_q8, int32_t mean_b_q8) {
  const int64_t a = mean_a_q8;
  const int64_t b = mean_b_q8;
  return {static_cast<int32_t>(div_round(a - b, 2)), static_cast<int32_t>(div_round(a + b, 2))};
}

void calibrator::begin(uint16_t cycles) {
  *this = calibrator{};
  target_ = cycles;
}

bool calibrator::add(int32_t rate_q8, uint8_t flags) {
  if (!active()) return false;
  if (n_ == 0) first_ = rate_q8;
  const int64_t d = int64_t{rate_q8} - first_;
  constexpr int64_t limit = int64_t{1} << 24;
  if (d >= limit || d <= -limit) {
    saturated_ = true;
  } else {
    s2_ += static_cast<uint64_t>(d * d);
  }
  s1_ += d;
  flags_ = static_cast<uint8_t>(flags_ | flags);
  ++n_;
  return n_ == target_;
}

protocol::cal_result_msg calibrator::result() const {
  protocol::cal_result_msg m;
  m.cycles = n_;
  m.flags = flags_;
  if (n_ == 0) return m;
  m.delta_n_q8 = static_cast<int32_t>(first_ + div_round(s1_, n_));
  if (saturated_) {
    m.std_q8 = 0xFFFFFFFFu;
    return m;
  }
  if (n_ < 2) return m;
  // Q = sum d^2 - (sum d)^2 / n without forming (sum d)^2 (up to 2^80): with |sum d| = m n + q,
  // (sum d)^2 / n = m^2 n + 2 m q + q^2 / n.
  const uint64_t a =
      s1_ < 0 ? uint64_t{0} - static_cast<uint64_t>(s1_) : static_cast<uint64_t>(s1_);
  const uint64_t mq = a / n_;
  const uint64_t q = a % n_;
  const uint64_t sq = mq * mq * n_ + 2 * mq * q + (q * q + n_ / 2) / n_;
  const uint64_t ss = s2_ > sq ? s2_ - sq : 0;
  const uint64_t var = (ss + (n_ - 1u) / 2) / (n_ - 1u);
  uint64_t sd = isqrt(var);
  if ((sd + 1) * (sd + 1) - var < var - sd * sd) ++sd;  // nearest, not floor
  m.std_q8 = sd > 0xFFFFFFFEu ? 0xFFFFFFFEu : static_cast<uint32_t>(sd);
  return m;
}

}  // namespace gyroflip::fw
