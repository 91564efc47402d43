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
  root_at(p, 0);
  t_ = 0;  // not known for this root
}

// The running root's step in 16-bit words where everything fits: 2a below 2^16, the root below
// 2^14, and the sums below checked for carries. On the MSP430F149 clang codes each 32-bit compare
// as a dozen instructions: the 32-bit loops below cost ~1 000 MCLK cycles a step at the top of a
// 2 000-steps/s ramp, these ~100 (docs/PERFORMANCE.md, "Fifth pass"). The same root and rest as
// the 32-bit code: both are fixed by v^2 = v0^2 + 2 a j alone.
bool mover::root_step16(const ramp_plan& p, uint16_t j) {
  if ((p.two_a >> 16) != 0 || root_ >= 0x4000u) return false;
  const auto a2 = static_cast<uint16_t>(p.two_a);
  uint16_t root = root_;
  uint16_t rest = rest_;
  // Where the root moves by more than ~64 a step, isqrt32 is cheaper (ramp_ticks).
  if (root < 512u && a2 > static_cast<uint16_t>(root << 7)) return false;
  if (j == root_j_ + 1u) {
    if (rest > static_cast<uint16_t>(0xFFFFu - a2)) return false;
    rest = static_cast<uint16_t>(rest + a2);
    auto odd = static_cast<uint16_t>(2u * root + 1u);  // (root + 1)^2 - root^2
    while (rest >= odd) {
      rest = static_cast<uint16_t>(rest - odd);
      odd = static_cast<uint16_t>(odd + 2u);
      ++root;
    }
  } else if (j + 1u == root_j_) {
    // rest < a2 inside the loop and the added odd numbers shrink: the sum stays below
    // a2 + 2 root.
    if (a2 > static_cast<uint16_t>(0xFFFFu - 2u * root)) return false;
    auto odd = static_cast<uint16_t>(2u * root - 1u);  // root^2 - (root - 1)^2
    while (rest < a2) {
      rest = static_cast<uint16_t>(rest + odd);
      odd = static_cast<uint16_t>(odd - 2u);
      --root;
    }
    rest = static_cast<uint16_t>(rest - a2);
  } else if (j != root_j_) {
    return false;
  }
  root_j_ = j;
  root_ = root;
  rest_ = rest;
  return true;
}

// floor((f + v / 2) / v) for the new root v from t_, the interval at v_old, in 16-bit words:
// r = N - t v, the remainder, moves by the change of N and by -t (v - v_old), and t by the few
// units that bring r back into [0, v). Needs f in [2^14, 40 960) (so every v < 2^14 has t >= 1
// and N + v < 2^16: the 32 768-Hz ticks of the F149 and the host port), t_ known, and a change
// t |v - v_old| below 2^16 and 8 v (a few corrections); 0 otherwise.
uint16_t mover::ticks_step16(const ramp_plan& p, uint16_t v_old) {
  const uint16_t v = root_;
  uint16_t t = t_;
  if ((p.tick_hz >> 16) != 0 || t == 0 || t >= 1024u || v >= 0x4000u || v_old >= 0x4000u) return 0;
  const auto f = static_cast<uint16_t>(p.tick_hz);
  if (f < 0x4000u || f >= 40960u) return 0;
  const auto n_old = static_cast<uint16_t>(f + v_old / 2u);
  const auto n = static_cast<uint16_t>(f + v / 2u);
  const bool up = v >= v_old;
  const auto dv = static_cast<uint16_t>(up ? v - v_old : v_old - v);
  if (dv >= 64u) return 0;
  const auto shift = static_cast<uint16_t>(t * dv);  // < 1024 * 64
  if (shift / 8u > v) return 0;
  // r = N - t v as a signed 32-bit value: (N_old - t v_old) + (N - N_old) -+ t dv.
  int32_t r = static_cast<uint16_t>(n_old - static_cast<uint16_t>(t * v_old));
  r += static_cast<int32_t>(n) - static_cast<int32_t>(n_old);
  r += up ? -static_cast<int32_t>(shift) : static_cast<int32_t>(shift);
  while (r < 0) {
    r += v;
    --t;
  }
  while (r >= static_cast<int32_t>(v)) {
    r -= v;
    ++t;
  }
  t_ = t;
  return t;
}

// The ramp's interval of its j-th step from the running root: each step of j adds (or takes) 2a
// to v^2 and moves the root by the few units that keep root^2 <= v^2 < (root+1)^2 (about a/v of
// them: ~10 at 2 000 steps/s and 20 000 steps/s^2), where isqrt32 takes 16 rounds of 32-bit
// shifts; where the root moves by more than ~64 a step (the slow start of a steep ramp), or the
// 16-bit words do not hold it, one isqrt32. The interval follows the root the same way
// (ticks_step16), else ticks_near. Exactly interval()'s value (tests/firmware/test_drivers.cpp).
uint32_t mover::ramp_ticks(const ramp_plan& p, uint16_t j) {
  if (j >= p.ramp_steps) return p.cruise_ticks;
  const uint16_t v_old = root_;
  if (root_step16(p, j)) {
    if (root_ == v_old && t_ != 0) return t_;
    const uint16_t t = ticks_step16(p, v_old);
    if (t != 0) return t;
  } else {
    root_at(p, j);
  }
  // Called from here, not from the root's functions: the F149's worst-case stack is the sum of
  // the frames along a call chain (fit.py).
  return ticks_near(p, root_);
}

// The root of v0^2 + 2 a j from scratch (16 rounds of isqrt32), where the 16-bit step does not
// fit: a ramp's first step, a jump of j, 2a of 2^16 or more, or a root moving by more than ~64 a
// step (where the 32-bit running root was no cheaper and took 750 B of the F149's flash).
void mover::root_at(const ramp_plan& p, uint16_t j) {
  // j < j_top: v0^2 + 2 a j < top^2 < 2^32.
  const uint32_t v2 = p.v0_sq + p.two_a * j;
  root_j_ = j;
  root_ = static_cast<uint16_t>(isqrt32(v2));
  rest_ = static_cast<uint16_t>(v2 - uint32_t{root_} * root_);  // <= 2 root < 2^16 - 1
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
  // seg_base_ <= k < total_: 16-bit differences (cheaper on the F149, and in the step interrupt).
  const auto kk = static_cast<uint16_t>(k - seg_base_);
  const auto n = static_cast<uint16_t>(total_ - seg_base_);
  return kk >= ramp_steps_ && static_cast<uint16_t>(n - 1u - kk) >= ramp_steps_;
}

void mover::refill(const ramp_plan& p, uint8_t max_new) {
  // The interval of step k leads to step k + 1: needed for k = 0 .. total - 2; the cruise's are
  // not queued (take_step uses cruise_ticks_).
  // 16-bit index arithmetic (seg_base_ <= queued_ < total_), and the checks that end the loop
  // first: a call with nothing to do is the common one (every stage of every pass).
  const auto n = static_cast<uint16_t>(total_ - seg_base_);
  const uint32_t full = uint32_t{cruise_ticks_} * queue_len;
  for (uint8_t added = 0; added < max_new && queued_ + 1u < total_;) {
    const uint8_t tail = tail_;
    const auto ahead = static_cast<uint8_t>(tail - shared(head_));
    if (ahead >= queue_len) return;
    const uint16_t k = queued_;
    if (cruising(k)) {  // past the whole cruise at once: kk up to n - 1 - j_top
      queued_ = static_cast<uint16_t>(total_ - ramp_steps_);
      continue;
    }
    ++added;
    // Enough ahead: as long as a full queue at the top rate (the slow start's intervals need
    // one or two; each costs a square root and a division).
    if (ahead != 0) {
      const uint16_t last = queue_[static_cast<uint8_t>(tail - 1u) % queue_len];
      uint32_t held = last;
      for (uint8_t i = 1; i < ahead; ++i) held += last;  // ahead x last, without a product
      if (held >= full) return;
    }
    const auto kk = static_cast<uint16_t>(k - seg_base_);
    const auto from_end = static_cast<uint16_t>(n - 1u - kk);
    const uint32_t t = ramp_ticks(p, kk < from_end ? kk : from_end);
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
