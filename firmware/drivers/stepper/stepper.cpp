/// \file
/// \brief Stepper ramp and move (stepper.hpp).
#include "firmware/drivers/stepper/stepper.hpp"

#include "firmware/util/intmath.hpp"

namespace gyroflip::stepper {

uint16_t step_rate(const ramp& r, uint32_t k, uint32_t n) {
  const uint32_t from_end = n - 1 - k;
  const uint32_t j = k < from_end ? k : from_end;
  const uint32_t v0 = r.start_sps;
  const uint64_t v2 = uint64_t{v0} * v0 + uint64_t{2} * r.accel_sps2 * j;
  const uint64_t v = fw::isqrt(v2);
  const uint32_t top = r.top_sps < r.start_sps ? r.start_sps : r.top_sps;
  return static_cast<uint16_t>(v > top ? top : v);
}

uint32_t step_interval(const ramp& r, uint32_t k, uint32_t n, uint32_t tick_hz) {
  const uint32_t v = step_rate(r, k, n);
  if (v == 0) return tick_hz;
  const uint32_t t = (tick_hz + v / 2) / v;
  return t == 0 ? 1 : t;
}

bool mover::poll(uint32_t now, const ramp& r, uint32_t tick_hz, motor& flip, motor& other,
                 follower rule) {
  // Due when now >= next_ (modulo 2^32: the difference read as signed). One step per call, so
  // the caller writes the port after every step: two steps at once would skip a phase and the
  // motor would not follow. A late caller catches up on the following calls.
  if (busy() && static_cast<int32_t>(now - next_) >= 0) {
    flip.step(dir_);
    if (rule == follower::same) other.step(dir_);
    if (rule == follower::opposite) other.step(static_cast<int8_t>(-dir_));
    next_ += step_interval(r, done_steps_, total_, tick_hz);
    ++done_steps_;
  }
  return busy();
}

}  // namespace gyroflip::stepper
