/// \file
/// \brief The phase rebuilt on demand from per-block carries (see phase_source.hpp).
///
/// Within a block the running sum stays small (the mean is removed), so double keeps it to
/// ~1e-16 relative; the slow long-double arithmetic runs once per block. A block's running sum
/// is a dependency chain (one add latency per point), so every pass here works on four blocks
/// side by side, which overlaps four chains in the CPU.
#include "gyroflip/analysis/phase_source.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "kernels.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis {
namespace {

constexpr std::size_t block = phase_source::block_points;
constexpr std::size_t blocks_per_item = 256;  // a work item of the preparing passes: 2 MB input

// Folds each block of `block` samples of y (the last may be shorter) with step(state, value),
// four blocks side by side (four(p, states) folds four whole blocks from p, as step would: by
// default with step); hands each block's final state to out(block index, state).
template <class State, class Step>
struct step_four {
  Step step;
  void operator()(const double* p, std::array<State, 4>& s) const {
    for (std::size_t i = 0; i < block; ++i)
      for (std::size_t l = 0; l < 4; ++l) step(s[l], p[l * block + i]);
  }
};

template <class State, class Step, class Out, class Four>
void fold_blocks(std::span<const double> y, State init, Step step, Out out, Four four) {
  const std::size_t full = y.size() / block;
  std::size_t b = 0;
  for (; b + 4 <= full; b += 4) {
    std::array<State, 4> s{init, init, init, init};
    four(y.data() + b * block, s);
    for (std::size_t l = 0; l < 4; ++l) out(b + l, s[l]);
  }
  for (; b * block < y.size(); ++b) {
    State s = init;
    for (double v : y.subspan(b * block, std::min(block, y.size() - b * block))) step(s, v);
    out(b, s);
  }
}

// fold_blocks over all samples on all cores, in work items of blocks_per_item blocks; each
// item's samples are released once folded (one pass over a mapped file stays non-resident).
template <class State, class Step, class Out, class Four>
void fold_all(const sample_source& s, State init, Step step, Out out, const progress_fn& p,
              Four four) {
  const std::size_t n = s.size();
  const std::size_t per_item = blocks_per_item * block;
  const std::size_t items = (n + per_item - 1) / per_item;
  detail::for_each_item(
      items, detail::worker_count(n),
      [&](std::size_t, std::size_t item) {
        const std::size_t first = item * per_item;
        const std::size_t last = std::min(n, first + per_item);
        fold_blocks(
            s.view(first, last - first), init, step,
            [&](std::size_t b, const State& st) { out(item * blocks_per_item + b, st); }, four);
        s.release(first, last);
      },
      p);
}

// Block b's sum is not finite or it holds a sample beyond max_sample_magnitude: name the first
// such sample, or say the sum overflowed.
error bad_block(const sample_source& s, std::size_t b) {
  const std::size_t first = b * block;
  const auto y = s.view(first, std::min(block, s.size() - first));
  for (std::size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i]))
      return usage_error(fmt::format("sample {} (0-based) is not finite", first + i));
    if (std::abs(y[i]) > phase_source::max_sample_magnitude)
      return usage_error(
          fmt::format("sample {} (0-based) is {:g}, beyond +-{:g}, the largest "
                      "magnitude the analysis takes (squares of sums must not "
                      "overflow)",
                      first + i, y[i], phase_source::max_sample_magnitude));
  }
  return usage_error(
      fmt::format("samples {}..{} are too large: their sum overflows", first, first + y.size()));
}

// x over points [0, count) of `lanes` blocks laid out `block` apart in y and x:
// x_0 = (base + (0 + err)) tau0, then part += y_{j-1} - mean, x_j = (base + (part + err)) tau0.
template <std::size_t lanes>
void integrate(const double* y, double* x, std::size_t count, const double* base, const double* err,
               double mean, double tau0_s) {
  std::array<double, lanes> part{};
  for (std::size_t l = 0; l < lanes; ++l) x[l * block] = (base[l] + (part[l] + err[l])) * tau0_s;
  for (std::size_t j = 1; j < count; ++j)
    for (std::size_t l = 0; l < lanes; ++l) {
      part[l] += y[l * block + j - 1] - mean;
      x[l * block + j] = (base[l] + (part[l] + err[l])) * tau0_s;
    }
}

// integrate<4> with the four blocks' running sums as the lanes of one vector: each step of four
// points loads a 4 x 4 tile of samples (four points of each block), turns it so that a row
// holds one point of every block, and turns the four results back. The lanes do exactly the
// scalar operations, so the same bits; 1.4 times integrate<4>'s speed with AVX2.
using detail::lanes4;
using detail::transpose4;

GYROFLIP_KERNEL_CLONES void integrate4(const double* y, double* x, std::size_t count,
                                       const double* base, const double* err, double mean,
                                       double tau0_s) {
  const lanes4 b = {base[0], base[1], base[2], base[3]};
  const lanes4 e = {err[0], err[1], err[2], err[3]};
  const lanes4 mv = {mean, mean, mean, mean};
  const lanes4 t = {tau0_s, tau0_s, tau0_s, tau0_s};
  lanes4 part = {0.0, 0.0, 0.0, 0.0};
  const lanes4 x0 = (b + (part + e)) * t;
  for (std::size_t l = 0; l < 4; ++l) x[l * block] = x0[l];
  std::size_t j = 1;
  lanes4 r0, r1, r2, r3;  // r_l: samples j-1 .. j+2 of block l
  for (; j + 4 <= count; j += 4) {
    std::memcpy(&r0, y + j - 1, sizeof r0);
    std::memcpy(&r1, y + block + j - 1, sizeof r1);
    std::memcpy(&r2, y + 2 * block + j - 1, sizeof r2);
    std::memcpy(&r3, y + 3 * block + j - 1, sizeof r3);
    transpose4(r0, r1, r2, r3);  // r_k: sample j - 1 + k of the four blocks
    // o_k: point j + k of the four blocks.
    part += r0 - mv;
    lanes4 o0 = (b + (part + e)) * t;
    part += r1 - mv;
    lanes4 o1 = (b + (part + e)) * t;
    part += r2 - mv;
    lanes4 o2 = (b + (part + e)) * t;
    part += r3 - mv;
    lanes4 o3 = (b + (part + e)) * t;
    transpose4(o0, o1, o2, o3);  // o_l: points j .. j+3 of block l
    std::memcpy(x + j, &o0, sizeof o0);
    std::memcpy(x + block + j, &o1, sizeof o1);
    std::memcpy(x + 2 * block + j, &o2, sizeof o2);
    std::memcpy(x + 3 * block + j, &o3, sizeof o3);
  }
  for (; j < count; ++j) {
    part += lanes4{y[j - 1], y[block + j - 1], y[2 * block + j - 1], y[3 * block + j - 1]} - mv;
    const lanes4 w = (b + (part + e)) * t;
    for (std::size_t l = 0; l < 4; ++l) x[l * block + j] = w[l];
  }
}

// prepare_rate's fold of a block: the sum and the largest |v| (the mean, the checks) and, about
// an offset c, the carry increment sum(v - c) and the sum of the running sums.
struct rate_fold {
  double sum = 0.0;
  double largest = 0.0;  // max |v|: samples beyond max_sample_magnitude are refused
  double part = 0.0;
  double parts = 0.0;
};

// One sample of rate_fold (the scalar step).
void rate_step(rate_fold& a, double v, double c) {
  a.sum += v;
  a.largest = std::max(a.largest, std::abs(v));
  a.parts += a.part;
  a.part += v - c;
}

// rate_step over four whole blocks from y, the blocks as the lanes of one vector fed by 4 x 4
// tiles turned as in integrate4: each lane does rate_step's operations in its order (max as
// std::max: the old value unless it is less than |v|, whose -0 and NaN cannot change it), so the
// same bits; the
// scalar fold's four chains per block, each an add latency per sample, were half of a rate
// source's preparing pass.
GYROFLIP_KERNEL_CLONES void fold_rate4(const double* y, double c, rate_fold* out) {
  const lanes4 cv = {c, c, c, c};
  const lanes4 zero = {0.0, 0.0, 0.0, 0.0};
  lanes4 sum = zero, largest = zero, part = zero, parts = zero;
  const auto step = [&](const lanes4& v) {
    sum += v;
    const lanes4 a = v < zero ? -v : v;
    largest = largest < a ? a : largest;
    parts += part;
    part += v - cv;
  };
  lanes4 r0, r1, r2, r3;
  for (std::size_t i = 0; i < block; i += 4) {
    std::memcpy(&r0, y + i, sizeof r0);
    std::memcpy(&r1, y + block + i, sizeof r1);
    std::memcpy(&r2, y + 2 * block + i, sizeof r2);
    std::memcpy(&r3, y + 3 * block + i, sizeof r3);
    transpose4(r0, r1, r2, r3);  // r_k: sample i + k of the four blocks
    step(r0);
    step(r1);
    step(r2);
    step(r3);
  }
  for (std::size_t l = 0; l < 4; ++l) out[l] = {sum[l], largest[l], part[l], parts[l]};
}

}  // namespace

phase_source::phase_source(const sample_source& samples, input_kind in, double tau0_s) noexcept
    : samples_(&samples), kind_(in), tau0_s_(tau0_s) {}

result<phase_source> phase_source::make(const sample_source& samples, input_kind in, double tau0_s,
                                        const progress_fn& on_progress) {
  if (!(tau0_s >= min_tau0_s && tau0_s <= max_tau0_s))
    return parameter_error("sample_rate_hz",
                           fmt::format("sample interval {:g} s is outside [{:g}, {:g}] s", tau0_s,
                                       min_tau0_s, max_tau0_s));
  phase_source p(samples, in, tau0_s);
  const auto st =
      in == input_kind::rate ? p.prepare_rate(on_progress) : p.prepare_angle(on_progress);
  if (!st) return st.err();
  return p;
}

std::size_t phase_source::blocks() const noexcept {
  return (n_phase_ + block - 1) / block;
}

status phase_source::prepare_angle(const progress_fn& on_progress) {
  const sample_source& s = *samples_;
  n_phase_ = s.size();
  if (n_phase_ == 0) return ok();
  x0_ = s.view(0, 1)[0];
  if (!std::isfinite(x0_)) return bad_block(s, 0);
  sum_.assign(blocks(), 0.0L);
  std::vector<double> largest(blocks());
  const auto x0 = static_cast<long double>(x0_);
  struct fold {
    long double sum = 0.0L;
    double largest = 0.0;  // max |v|: samples beyond max_sample_magnitude are refused
  };
  const auto step = [x0](fold& a, double v) {
    a.sum += static_cast<long double>(v) - x0;
    a.largest = std::max(a.largest, std::abs(v));
  };
  fold_all(
      s, fold{}, step,
      [&](std::size_t b, const fold& a) {
        sum_[b] = a.sum;
        largest[b] = a.largest;
      },
      on_progress, step_four<fold, decltype(step)>{step});
  for (std::size_t b = 0; b < sum_.size(); ++b)
    if (!std::isfinite(sum_[b]) || !(largest[b] <= max_sample_magnitude)) return bad_block(s, b);
  return ok();
}

status phase_source::prepare_rate(const progress_fn& on_progress) {
  const sample_source& s = *samples_;
  const std::size_t m = s.size();
  n_phase_ = m + 1;
  const std::size_t sample_blocks = (m + block - 1) / block;
  // One pass: per block the sum and the largest |v| (the mean, the checks) and, about a
  // provisional offset c (the mean of the first block), the carry increment sum(v - c) and the sum
  // of the running sums. Those about the mean follow exactly (long double):
  // part = part_c - n (mean - c), parts = parts_c - (mean - c) n (n - 1) / 2, n the block's
  // samples. One read of the samples instead of two (the mean first, then the runs).
  double c = 0.0;
  if (m > 0) {
    const auto head = s.view(0, std::min(m, block));
    long double acc = 0.0L;
    for (double v : head) acc += static_cast<long double>(v);
    c = static_cast<double>(acc / static_cast<long double>(head.size()));
  }
  std::vector<rate_fold> folds(sample_blocks);
  fold_all(
      s, rate_fold{}, [c](rate_fold& a, double v) { rate_step(a, v, c); },
      [&](std::size_t b, const rate_fold& a) { folds[b] = a; }, on_progress,
      [c](const double* p, std::array<rate_fold, 4>& st) { fold_rate4(p, c, st.data()); });
  long double sum = 0.0L;
  for (std::size_t b = 0; b < sample_blocks; ++b) {
    if (!std::isfinite(folds[b].sum) || !(folds[b].largest <= max_sample_magnitude))
      return bad_block(s, b);
    sum += static_cast<long double>(folds[b].sum);
  }
  mean_ = static_cast<double>(sum / static_cast<long double>(std::max<std::size_t>(m, 1)));
  struct run {
    double part = 0.0;
    double parts = 0.0;
  };
  std::vector<run> runs(sample_blocks);
  const long double shift = static_cast<long double>(mean_) - static_cast<long double>(c);
  for (std::size_t b = 0; b < sample_blocks; ++b) {
    const auto n = static_cast<long double>(std::min(block, m - b * block));
    runs[b].part = static_cast<double>(static_cast<long double>(folds[b].part) - n * shift);
    runs[b].parts = static_cast<double>(static_cast<long double>(folds[b].parts) -
                                        shift * n * (n - 1.0L) / 2.0L);
  }
  base_.resize(blocks());
  err_.resize(blocks());
  sum_.resize(blocks());
  long double carry = 0.0L;
  for (std::size_t b = 0; b < blocks(); ++b) {
    base_[b] = static_cast<double>(carry);
    err_[b] = static_cast<double>(carry - static_cast<long double>(base_[b]));
    const std::size_t count = std::min(block, n_phase_ - b * block);
    // The last block holds one point more than its samples (x_M): add its running sum.
    long double parts = 0.0L;
    if (b < sample_blocks) {
      const std::size_t in_block = std::min(block, m - b * block);
      parts = static_cast<long double>(runs[b].parts) +
              (count > in_block ? static_cast<long double>(runs[b].part) : 0.0L);
    }
    sum_[b] = static_cast<long double>(tau0_s_) * (static_cast<long double>(count) * carry + parts);
    if (b < sample_blocks) carry += static_cast<long double>(runs[b].part);
  }
  return ok();
}

std::size_t phase_source::table_bytes() const noexcept {
  return base_.size() * sizeof(double) + err_.size() * sizeof(double) +
         sum_.size() * sizeof(long double);
}

void phase_source::rebuild(std::size_t b, std::size_t count, double* out) const noexcept {
  const auto y = samples_->view(b * block, count - 1);
  integrate<1>(y.data(), out, count, &base_[b], &err_[b], mean_, tau0_s_);
}

void phase_source::rebuild4(std::size_t b, double* out) const noexcept {
  const auto y = samples_->view(b * block, 4 * block - 1);
  integrate4(y.data(), out, block, &base_[b], &err_[b], mean_, tau0_s_);
}

void phase_source::build(std::span<double> out) const {
  assert(out.size() == n_phase_);
  const sample_source& s = *samples_;
  // Work items of 64 blocks (512 kB written), a multiple of four for rebuild4.
  constexpr std::size_t blocks_per_piece = 64;
  const std::size_t pieces = (blocks() + blocks_per_piece - 1) / blocks_per_piece;
  detail::for_each_item(pieces, detail::worker_count(n_phase_), [&](std::size_t, std::size_t i) {
    const std::size_t first = i * blocks_per_piece * block;
    const std::size_t last = std::min(n_phase_, first + blocks_per_piece * block);
    if (kind_ == input_kind::angle) {
      const auto v = s.view(first, last - first);
      std::copy(v.begin(), v.end(), out.data() + first);
    } else {
      // As phase_reader::generate builds them: four whole blocks at a time, then one by one.
      for (std::size_t k = first; k < last;) {
        const std::size_t count = k + 4 * block <= last ? 4 * block : std::min(last - k, block);
        if (count == 4 * block)
          rebuild4(k / block, out.data() + k);
        else
          rebuild(k / block, count, out.data() + k);
        k += count;
      }
    }
    s.release(first, std::min(last, s.size()));
  });
}

phase_source phase_source::built(const sample_source& x) const {
  assert(x.size() == n_phase_);
  phase_source p(x, input_kind::angle, tau0_s_);
  p.n_phase_ = n_phase_;
  // A rate source's phase starts at x_0 = 0 (its block sums are of x_k); an angle source's
  // block sums are of x_k - x_0.
  p.x0_ = kind_ == input_kind::angle ? x0_ : 0.0;
  p.sum_ = sum_;
  return p;
}

long double phase_source::offset_sum(std::size_t begin, std::size_t end,
                                     phase_reader& reader) const {
  long double s = 0.0L;
  for (std::size_t k = begin; k < end;) {
    const std::size_t b = k / block;
    const std::size_t block_end = std::min(n_phase_, (b + 1) * block);
    if (k == b * block && block_end <= end) {
      s += sum_[b];
      k = block_end;
      continue;
    }
    const std::size_t e = std::min(end, block_end);
    for (double v : reader.read(k, e - k))
      s += static_cast<long double>(v) - static_cast<long double>(x0_);
    k = e;
  }
  return s;
}

phase_reader::phase_reader(phase_reader&& other) noexcept
    : src_(other.src_),
      hand_back_(other.hand_back_),
      buf_(std::move(other.buf_)),
      base_(other.base_),
      end_(other.end_),
      pending_begin_(std::exchange(other.pending_begin_, 0)),
      pending_end_(std::exchange(other.pending_end_, 0)) {}

phase_reader::~phase_reader() {
  flush();
}

std::span<const double> phase_reader::read(std::size_t begin, std::size_t len) {
  const phase_source& s = *src_;
  assert(begin + len <= s.size());
  if (len == 0) return {};
  if (s.kind_ == input_kind::angle) {
    consumed(begin, begin + len);
    return s.samples_->view(begin, len);
  }
  // Not continuing the buffered range: start again at the block of `begin`.
  if (begin < base_ || begin > end_) base_ = end_ = begin / block * block;
  const std::size_t need = std::min(s.size(), (begin + len + block - 1) / block * block);
  make_room(begin, need);
  generate(need);
  return {buf_.data() + (begin - base_), len};
}

void phase_reader::make_room(std::size_t begin, std::size_t need) {
  if (need - base_ <= buf_.size()) return;
  // Keep x[from, end_), which the read still needs, at the front; twice the room needed keeps
  // the moves to about one per buffer length.
  const std::size_t from = std::min(begin, end_);
  const std::size_t kept = end_ - from;
  if (buf_.size() < 2 * (need - from)) {
    std::vector<double> bigger(2 * (need - from));
    std::copy_n(buf_.data() + (from - base_), kept, bigger.data());
    buf_.swap(bigger);
  } else {
    std::memmove(buf_.data(), buf_.data() + (from - base_), kept * sizeof(double));
  }
  base_ = from;
}

void phase_reader::generate(std::size_t need) {
  const phase_source& s = *src_;
  while (end_ < need) {
    const std::size_t b = end_ / block;
    double* out = buf_.data() + (end_ - base_);
    const std::size_t count = end_ + 4 * block <= need ? 4 * block : std::min(need - end_, block);
    if (count == 4 * block)
      s.rebuild4(b, out);
    else
      s.rebuild(b, count, out);
    // Block points [0, count) used samples [end_, end_ + count - 1); the next one is the carry.
    end_ += count;
    consumed(end_ - count, std::min(end_, s.samples_->size()));
  }
}

// Samples [begin, end) are in use now; pending samples around them are done with (reads move
// forward, or backward for a reflection). Ranges less than a release step apart collect, gaps
// included (sparse reads of a decimated phase: releasing samples nobody viewed is harmless and
// takes back the pages the kernel maps around each fault), until they span a release step; then
// all but the current range go back. A range farther away hands back all that is pending.
void phase_reader::consumed(std::size_t begin, std::size_t end) noexcept {
  if (!hand_back_) return;
  const std::size_t step = src_->samples_->release_step();
  if (end + step < pending_begin_ || begin > pending_end_ + step) {
    flush();
    pending_begin_ = begin;
    pending_end_ = end;
    return;
  }
  pending_begin_ = std::min(pending_begin_, begin);
  pending_end_ = std::max(pending_end_, end);
  if (pending_end_ - pending_begin_ < step) return;
  if (pending_begin_ < begin) src_->samples_->release(pending_begin_, begin);
  if (end < pending_end_) src_->samples_->release(end, pending_end_);
  pending_begin_ = begin;
  pending_end_ = end;
}

void phase_reader::flush() noexcept {
  if (src_ != nullptr && pending_end_ > pending_begin_)
    src_->samples_->release(pending_begin_, pending_end_);
  pending_begin_ = pending_end_;
}

std::vector<double> phase_from_rate(std::span<const double> rate, double tau0_s) {
  const span_samples samples(rate);
  const auto src = phase_source::make(samples, input_kind::rate, tau0_s);
  if (!src) return std::vector<double>(rate.size() + 1, std::nan(""));
  phase_reader reader(*src);
  const auto x = reader.read(0, src->size());
  return {x.begin(), x.end()};
}

}  // namespace gyroflip::analysis
