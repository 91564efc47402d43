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

namespace {
uint32_t ticks_at(uint32_t tick_hz, uint32_t v) {
  if (v == 0) return tick_hz;
  const uint32_t t = (tick_hz + v / 2) / v;
  return t == 0 ? 1 : t;
}
}  // namespace

ramp_plan make_plan(const ramp& r, uint32_t tick_hz) {
  ramp_plan p;
  const uint32_t v0 = r.start_sps;
  const uint32_t top = r.top_sps < r.start_sps ? r.start_sps : r.top_sps;
  p.v0_sq = v0 * v0;
  p.two_a = 2 * uint32_t{r.accel_sps2};
  p.tick_hz = tick_hz;
  p.top_sps = static_cast<uint16_t>(top);
  // j_top = ceil((top^2 - v0^2) / 2a): top^2 < 2^32. A move has at most 65535 steps, so j stays
  // below 32768 and a longer ramp is clamped without changing any interval.
  const uint32_t span = top * top - p.v0_sq;
  const uint32_t j_top = p.two_a == 0 ? 0xFFFFu : (span + p.two_a - 1) / p.two_a;
  p.ramp_steps = static_cast<uint16_t>(j_top > 0xFFFFu ? 0xFFFFu : j_top);
  p.cruise_ticks = ticks_at(tick_hz, top);
  return p;
}

uint32_t interval(const ramp_plan& p, uint32_t k, uint32_t n) {
  const uint32_t from_end = n - 1 - k;
  const uint32_t j = k < from_end ? k : from_end;
  if (j >= p.ramp_steps) return p.cruise_ticks;
  // j < j_top: v0^2 + 2 a j < top^2 < 2^32, and its root is below the top rate.
  return ticks_at(p.tick_hz, isqrt32(p.v0_sq + p.two_a * j));
}

void mover::begin(int32_t steps, uint32_t first_ticks, const ramp_plan& p, uint8_t ahead) {
  const uint32_t mag = steps < 0 ? static_cast<uint32_t>(-steps) : static_cast<uint32_t>(steps);
  total_ = static_cast<uint16_t>(mag > 0xFFFFu ? 0xFFFFu : mag);
  dir_ = steps < 0 ? -1 : 1;
  ramp_steps_ = p.ramp_steps;
  cruise_ticks_ = static_cast<uint16_t>(p.cruise_ticks > 0xFFFFu ? 0xFFFFu : p.cruise_ticks);
  share(done_, uint16_t{0});
  seg_base_ = 0;
  queued_ = 0;
  share(head_, uint8_t{0});
  share(tail_, uint8_t{0});
  share(paused_, false);
  next_ = first_ticks;
  restart_root(p);
  refill(p, ahead);
}

void mover::restart_root(const ramp_plan& p) {
  root_j_ = 0;
  root_ = static_cast<uint16_t>(isqrt32(p.v0_sq));
  rest_ = static_cast<uint16_t>(p.v0_sq - uint32_t{root_} * root_);
}

// The ramp's interval of its j-th step from the running root: each step of j adds (or takes) 2a
// to v^2 and moves the root by the few units that keep root^2 <= v^2 < (root+1)^2 (about a/v of
// them: ~10 at 2 000 steps/s and 20 000 steps/s^2), where isqrt32 takes 16 rounds of 32-bit
// shifts; where the root moves by more than ~64 a step (the slow start of a steep ramp), one
// isqrt32 is cheaper. Exactly interval()'s value (tests/firmware/test_drivers.cpp).
uint32_t mover::ramp_ticks(const ramp_plan& p, uint16_t j) {
  if (j >= p.ramp_steps) return p.cruise_ticks;
  if (p.two_a > 128u * uint32_t{root_} || j + 1u < root_j_ || j > root_j_ + 1u) {
    // j < j_top: v0^2 + 2 a j < top^2 < 2^32.
    const uint32_t v2 = p.v0_sq + p.two_a * j;
    root_j_ = j;
    root_ = static_cast<uint16_t>(isqrt32(v2));
    rest_ = static_cast<uint16_t>(v2 - uint32_t{root_} * root_);  // <= 2 root < 2^16 - 1
    return ticks_near(p, root_);
  }
  uint32_t rest = rest_;
  if (j > root_j_) {
    rest += p.two_a;
    while (rest >= 2u * uint32_t{root_} + 1u) {
      rest -= 2u * uint32_t{root_} + 1u;
      ++root_;
    }
  } else if (j < root_j_) {
    while (rest < p.two_a) {
      rest += 2u * uint32_t{root_} - 1u;
      --root_;
    }
    rest -= p.two_a;
  }
  root_j_ = j;
  rest_ = static_cast<uint16_t>(rest);
  return ticks_near(p, root_);
}

// The largest t with t v <= N = tick_hz + v / 2 (ticks_at), searched from the last interval: the
// rate moves by a few units a step, so t by a step or two (a 32-bit division costs ~470 MCLK
// cycles on the MSP430F149, a step's whole budget at 2 000 steps/s is ~2 700 with the interrupts).
uint32_t mover::ticks_near(const ramp_plan& p, uint16_t v) {
  uint32_t t = t_;
  const uint32_t n = p.tick_hz + v / 2u;
  const uint32_t near = 4u * uint32_t{v};
  uint32_t prod = t * v;
  if (v == 0 || t == 0 || (prod > n ? prod - n : n - prod) > near) {
    t = ticks_at(p.tick_hz, v);
  } else {
    while (prod > n) {
      --t;
      prod -= v;
    }
    while (n - prod >= v) {
      ++t;
      prod += v;
    }
    if (t == 0) t = 1;
  }
  t_ = static_cast<uint16_t>(t > 0xFFFFu ? 0u : t);
  return t;
}

// Step k of the current ramp segment (from seg_base_) is in its cruise: at the top rate, its
// interval the constant cruise_ticks_ (the plan's j >= j_top).
bool mover::cruising(uint16_t k) const {
  const uint32_t kk = uint32_t{k} - seg_base_;
  const uint32_t n = uint32_t{total_} - seg_base_;
  return kk >= ramp_steps_ && n - 1 - kk >= ramp_steps_;
}

void mover::refill(const ramp_plan& p, uint8_t max_new) {
  // The interval of step k leads to step k + 1: needed for k = 0 .. total - 2; the cruise's are
  // not queued (take_step uses cruise_ticks_).
  const uint32_t n = uint32_t{total_} - seg_base_;
  for (uint8_t added = 0; added < max_new && queued_ + 1u < total_;) {
    const uint16_t k = queued_;
    if (cruising(k)) {  // past the whole cruise at once: kk up to n - 1 - j_top
      queued_ = static_cast<uint16_t>(total_ - ramp_steps_);
      continue;
    }
    ++added;
    const uint8_t tail = tail_;
    const uint8_t ahead = static_cast<uint8_t>(tail - shared(head_));
    if (ahead >= queue_len) return;
    // Enough ahead: as long as a full queue at the top rate (the slow start's intervals need
    // one or two; each costs a square root and a division).
    if (ahead != 0 && uint32_t{ahead} * queue_[static_cast<uint8_t>(tail - 1u) % queue_len] >=
                          uint32_t{queue_len} * cruise_ticks_)
      return;
    const uint32_t kk = uint32_t{k} - seg_base_;
    const uint32_t from_end = n - 1 - kk;
    const uint32_t t = ramp_ticks(p, static_cast<uint16_t>(kk < from_end ? kk : from_end));
    queue_[tail % queue_len] = static_cast<uint16_t>(t > 0xFFFFu ? 0xFFFFu : t);
    fw::barrier();  // the interval is in place before the index publishes it
    ++queued_;
    share(tail_, static_cast<uint8_t>(tail + 1u));
  }
}

bool mover::take_step(motor& flip, motor& other, follower rule, uint32_t now, uint32_t* next_due) {
  const uint16_t k = done_;
  if (k >= total_) return false;
  flip.step(dir_);
  if (rule == follower::same) other.step(dir_);
  if (rule == follower::opposite) other.step(static_cast<int8_t>(-dir_));
  share(done_, static_cast<uint16_t>(k + 1u));
  if (k + 1u >= total_) return false;
  uint16_t t = cruise_ticks_;
  if (!cruising(k)) {
    const uint8_t head = head_;
    if (shared(tail_) == head) {  // the main loop has not computed the next interval yet
      share(paused_, true);
      return false;
    }
    fw::barrier();
    t = queue_[head % queue_len];
    share(head_, static_cast<uint8_t>(head + 1u));
  }
  // Late by a whole interval or more (a main loop that steps a port without a timer and came
  // late): the next step is timed from now, never due at once (no burst of catch-up steps).
  const bool late = static_cast<int32_t>(now - next_) >= static_cast<int32_t>(t);
  next_ = (late ? now : next_) + t;
  *next_due = next_;
  return true;
}

void mover::rebase(uint32_t now, const ramp_plan& p) {
  // The consumer is not armed (paused): the main loop owns every index here.
  seg_base_ = done_;
  queued_ = done_;
  share(head_, tail_);
  ++rebases_;
  next_ = now;
  restart_root(p);
  refill(p);
  share(paused_, false);
}

}  // namespace gyroflip::stepper
