/// \file
/// \brief One sweep over the phase for all averaging factors of OADEV, TOTDEV, OHDEV and MDEV
/// (see sweep.hpp).
///
/// Memory traffic, not arithmetic, is what a sweep over 1e8 points per factor costs, so each
/// phase point is built (or read) as few times as possible: once for the window that serves all
/// factors up to m = 2^17 / order, and once per distinct far offset j m.
#include "sweep.hpp"

#include <algorithm>
#include <array>
#include <condition_variable>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "kernels.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis::detail {
namespace {

using index = std::ptrdiff_t;
constexpr index block_terms = 4096;
constexpr index chunk_terms = index{1} << 20;
constexpr std::size_t window_reach = std::size_t{1} << 17;  // order * m of a near factor
constexpr std::size_t far_per_sweep = 32;  // far factors per sweep: bounds the streams (buffers)
// Readers at offsets up to this many release steps of the sample source keep the samples they
// map; the sweep releases them once every chunk below is done. Nearby streams then share mapped
// pages instead of each faulting them in again (a page fault costs ~4 us on the project's VM),
// for 32 steps (64 MB for a file) more resident memory.
constexpr std::size_t keep_steps = 32;

index floor_div(index a, index b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// x*_k on [-(N-1), 2N-1): x reflected at both ends (SP1065 eqn 25). Ranges inside [0, N) come
// straight from the main reader; reflected parts are read forward by a second reader and
// mirrored into a scratch buffer (only near the ends of the record).
class star_reader {
 public:
  star_reader(const phase_source& x, double first, double last, bool hand_back)
      : main_(x, hand_back),
        mirror_(x),
        n_(static_cast<index>(x.size())),
        first2_(2.0 * first),
        last2_(2.0 * last) {}

  std::span<const double> read(index begin, std::size_t len) {
    const index end = begin + static_cast<index>(len);
    if (begin >= 0 && end <= n_) return main_.read(static_cast<std::size_t>(begin), len);
    scratch_.resize(len);
    const auto out = [this, begin](index k) -> double& {
      return scratch_[static_cast<std::size_t>(k - begin)];
    };
    const index left_end = std::min<index>(end, 0);
    if (begin < left_end) {  // x*_k = 2x_0 - x_{-k}
      const auto v = read_at(mirror_, 1 - left_end, left_end - begin);
      for (index k = begin; k < left_end; ++k)
        out(k) = first2_ - v[static_cast<std::size_t>(-k - (1 - left_end))];
    }
    const index mid_begin = std::max<index>(begin, 0);
    const index mid_end = std::min(end, n_);
    if (mid_begin < mid_end) {
      const auto v = read_at(main_, mid_begin, mid_end - mid_begin);
      std::copy(v.begin(), v.end(), &out(mid_begin));
    }
    const index right_begin = std::max(begin, n_);
    if (right_begin < end) {  // x*_k = 2x_{N-1} - x_{2(N-1)-k}
      const index lo = 2 * n_ - 1 - end;
      const auto v = read_at(mirror_, lo, end - right_begin);
      for (index k = right_begin; k < end; ++k)
        out(k) = last2_ - v[static_cast<std::size_t>(2 * (n_ - 1) - k - lo)];
    }
    return scratch_;
  }

 private:
  static std::span<const double> read_at(phase_reader& r, index begin, index len) {
    return r.read(static_cast<std::size_t>(begin), static_cast<std::size_t>(len));
  }

  phase_reader main_;
  phase_reader mirror_;
  index n_;
  double first2_;
  double last2_;
  std::vector<double> scratch_;
};

// Which streams one sweep reads and which stream each factor's x*_{i + j m} comes from.
struct plan {
  std::size_t order = 2;
  index dom_lo = 0;  // readable indices of x*
  index dom_hi = 0;
  index lo = 0;  // union of the term ranges
  index hi = 0;
  std::vector<term_range> factors;
  struct stream {
    index offset = 0;
    index extra = 0;  // points read past the block
  };
  std::vector<stream> streams;  // [0]: the window at offset 0
  std::vector<std::array<std::size_t, 4>> stream_of;
};

bool is_near(std::size_t order, std::size_t m) {
  return order * m <= window_reach;
}

plan make_plan(std::size_t n, std::size_t order, bool reflect, std::vector<term_range> fs) {
  plan p;
  p.order = order;
  const auto nn = static_cast<index>(n);
  p.dom_lo = reflect ? 1 - nn : 0;
  p.dom_hi = reflect ? 2 * nn - 1 : nn;
  p.lo = std::numeric_limits<index>::max();
  p.hi = std::numeric_limits<index>::min();
  index reach = 0;
  for (const auto& f : fs) {
    if (f.lo >= f.hi) continue;
    p.lo = std::min(p.lo, f.lo);
    p.hi = std::max(p.hi, f.hi);
    if (is_near(order, f.m)) reach = std::max(reach, static_cast<index>(order * f.m));
  }
  p.streams.push_back({0, reach});
  std::map<index, std::size_t> by_offset;
  for (const auto& f : fs) {
    std::array<std::size_t, 4> s{};
    for (std::size_t j = 1; j <= order && !is_near(order, f.m); ++j) {
      const auto offset = static_cast<index>(j * f.m);
      const auto [it, added] = by_offset.try_emplace(offset, p.streams.size());
      if (added) p.streams.push_back({offset, 0});
      s[j] = it->second;
    }
    p.stream_of.push_back(s);
  }
  p.factors = std::move(fs);
  return p;
}

// One worker's readers for a plan; per block it reads what the active factors need.
class stream_set {
 public:
  stream_set(const phase_source& x, const plan& p, double first, double last)
      : plan_(&p),
        data_(p.streams.size()),
        start_(p.streams.size()),
        lo_(p.streams.size()),
        hi_(p.streams.size()),
        active_(p.factors.size()),
        spare_(x) {
    const std::size_t keep = keep_steps * x.samples().release_step();
    for (const auto& s : p.streams)
      readers_.emplace_back(x, first, last, static_cast<std::size_t>(s.offset) > keep);
  }

  // Reads, for each stream, the union of what the factors active in [b, b + block_terms) need.
  void load(index b) {
    const plan& p = *plan_;
    std::fill(lo_.begin(), lo_.end(), std::numeric_limits<index>::max());
    std::fill(hi_.begin(), hi_.end(), std::numeric_limits<index>::min());
    for (std::size_t f = 0; f < p.factors.size(); ++f) {
      const index t0 = std::max(p.factors[f].lo, b);
      const index t1 = std::min(p.factors[f].hi, b + block_terms);
      active_[f] = t0 < t1;
      if (!active_[f]) continue;
      for (std::size_t j = 0; j <= p.order; ++j) {
        const std::size_t s = p.stream_of[f][j];
        const auto offset = static_cast<index>(j * p.factors[f].m);
        lo_[s] = std::min(lo_[s], t0 + offset);
        hi_[s] = std::max(hi_[s], t1 + offset);
      }
    }
    for (std::size_t s = 0; s < p.streams.size(); ++s) {
      const index k0 = std::max(p.dom_lo, lo_[s]);
      const index k1 = std::min(p.dom_hi, hi_[s]);
      if (k0 >= k1) continue;
      start_[s] = k0;
      data_[s] = readers_[s].read(k0, static_cast<std::size_t>(k1 - k0));
    }
  }
  [[nodiscard]] bool active(std::size_t f) const { return active_[f] != 0; }
  // &x*_{i + j m} for factor f (the index must be in the block's reach).
  [[nodiscard]] const double* at(std::size_t f, std::size_t j, index i) const {
    const std::size_t s = plan_->stream_of[f][j];
    return data_[s].data() + (i + static_cast<index>(j * plan_->factors[f].m) - start_[s]);
  }
  phase_reader& spare() { return spare_; }

 private:
  const plan* plan_;
  std::vector<star_reader> readers_;
  std::vector<std::span<const double>> data_;
  std::vector<index> start_;
  std::vector<index> lo_;  // per stream: what this block needs
  std::vector<index> hi_;
  std::vector<char> active_;
  phase_reader spare_;
};

// Releases the samples behind the sweep: below the lowest chunk not yet done no reader of the
// sweep goes again (the readers that keep their pages rely on this). A worker waits before
// starting a chunk more than `ahead` past that lowest one, so that a thread the system holds
// back cannot leave the others piling up kept pages.
class release_behind {
 public:
  release_behind(const sample_source& s, index first_chunk, std::size_t chunks, std::size_t ahead)
      : samples_(&s), first_chunk_(first_chunk), ahead_(ahead), done_(chunks, 0) {}
  void wait_turn(std::size_t c) {
    std::unique_lock<std::mutex> lock(mutex_);
    turn_.wait(lock, [&] { return c < low_ + ahead_; });
  }
  void chunk_done(std::size_t c) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_[c] = 1;
      while (low_ < done_.size() && done_[low_] != 0) ++low_;
      const index bound = (first_chunk_ + static_cast<index>(low_)) * chunk_terms;
      const auto to = static_cast<std::size_t>(
          std::clamp<index>(bound, 0, static_cast<index>(samples_->size())));
      if (to > released_) samples_->release(std::exchange(released_, to), to);
    }
    turn_.notify_all();
  }

 private:
  const sample_source* samples_;
  index first_chunk_;
  std::size_t ahead_;
  std::vector<char> done_;
  std::size_t low_ = 0;
  std::size_t released_ = 0;
  std::mutex mutex_;
  std::condition_variable turn_;
};

// Runs chunk(stream_set, chunk begin, chunk end, sums) over the chunks of the plan's index range
// on all cores and adds the per-chunk sums in chunk order.
template <class Chunk>
std::vector<long double> run_sweep(const phase_source& x, const plan& p, Chunk chunk,
                                   const progress_fn& on_progress) {
  const std::size_t nf = p.factors.size();
  std::vector<long double> out(nf, 0.0L);
  if (p.lo >= p.hi) return out;
  const index c_lo = floor_div(p.lo, chunk_terms);
  const auto chunks = static_cast<std::size_t>(floor_div(p.hi - 1, chunk_terms) - c_lo + 1);
  double first = 0.0, last = 0.0;
  {
    phase_reader r(x);
    first = r.read(0, 1)[0];
    last = r.read(x.size() - 1, 1)[0];
  }
  const std::size_t workers = worker_count(x.size());
  std::vector<std::unique_ptr<stream_set>> sets(workers);
  std::vector<long double> partial(chunks * nf, 0.0L);
  release_behind releaser(x.samples(), c_lo, chunks, workers + 1);
  for_each_item(
      chunks, workers,
      [&](std::size_t w, std::size_t c) {
        releaser.wait_turn(c);
        if (!sets[w]) sets[w] = std::make_unique<stream_set>(x, p, first, last);
        const index begin = (c_lo + static_cast<index>(c)) * chunk_terms;
        chunk(*sets[w], begin, begin + chunk_terms, partial.data() + c * nf);
        releaser.chunk_done(c);
      },
      on_progress);
  for (std::size_t c = 0; c < chunks; ++c)
    for (std::size_t f = 0; f < nf; ++f) out[f] += partial[c * nf + f];
  return out;
}

// Sweeps over groups of factors: the near ones with the first far ones, then the other far
// factors `far_per_sweep` at a time. A series of one chunk or less cannot spread a sweep over
// the cores, so there the groups run side by side instead (`--taus all` on 557 k points: 2300
// groups); each group's sums are the same either way.
template <class Sweep>
std::vector<long double> in_groups(std::size_t order, const std::vector<term_range>& fs,
                                   std::size_t n_phase, const progress_fn& on_progress,
                                   Sweep sweep) {
  const bool one_chunk = static_cast<index>(n_phase) <= chunk_terms;
  // Side by side, the groups must also be of similar work (terms summed), or one big group of
  // near factors would keep one core busy alone; and small enough that the caller's thread
  // reports progress often: at most 1/64 of all the work per group.
  double total_work = 0.0;
  for (const auto& f : fs) total_work += static_cast<double>(f.hi - f.lo);
  const double max_work = one_chunk ? total_work / 64.0 : total_work + 1.0;
  std::vector<std::vector<std::size_t>> groups(1);
  std::size_t far = 0;
  double work = 0.0;
  for (std::size_t f = 0; f < fs.size(); ++f) {
    const bool is_far = !is_near(order, fs[f].m);
    if ((is_far && far == far_per_sweep) || (work > max_work && !groups.back().empty())) {
      groups.emplace_back();
      far = 0;
      work = 0.0;
    }
    far += is_far ? 1 : 0;
    work += static_cast<double>(fs[f].hi - fs[f].lo);
    groups.back().push_back(f);
  }
  std::vector<long double> out(fs.size(), 0.0L);
  const auto run_group = [&](std::size_t g, const progress_fn& prog) {
    std::vector<term_range> sub;
    for (std::size_t f : groups[g]) sub.push_back(fs[f]);
    const auto sums = sweep(sub, prog);
    for (std::size_t i = 0; i < groups[g].size(); ++i) out[groups[g][i]] = sums[i];
  };
  if (one_chunk && groups.size() > 1) {
    // The inner sweeps stay on their thread (one chunk) and report nothing (progress only from
    // the caller's thread): for_each_item reports groups done.
    for_each_item(
        groups.size(), worker_count(std::size_t{1} << 16),
        [&](std::size_t, std::size_t g) { run_group(g, {}); }, on_progress);
    return out;
  }
  for (std::size_t g = 0; g < groups.size(); ++g)
    run_group(g, part_progress(on_progress, g, groups.size()));
  return out;
}

}  // namespace

std::vector<long double> difference_sums(const phase_source& x, std::size_t order, bool reflect,
                                         const std::vector<term_range>& factors,
                                         const progress_fn& on_progress) {
  return in_groups(
      order, factors, x.size(), on_progress, [&](const auto& fs, const progress_fn& prog) {
        const plan p = make_plan(x.size(), order, reflect, fs);
        return run_sweep(
            x, p,
            [&p](stream_set& ss, index c0, index c1, long double* sums) {
              for (index b = c0; b < c1; b += block_terms) {
                ss.load(b);
                for (std::size_t f = 0; f < p.factors.size(); ++f) {
                  if (!ss.active(f)) continue;
                  const index t0 = std::max(p.factors[f].lo, b);
                  const auto n =
                      static_cast<std::size_t>(std::min(p.factors[f].hi, b + block_terms) - t0);
                  sums[f] += static_cast<long double>(
                      p.order == 2 ? sum_second_differences(ss.at(f, 0, t0), ss.at(f, 1, t0),
                                                            ss.at(f, 2, t0), n)
                                   : sum_third_differences(ss.at(f, 0, t0), ss.at(f, 1, t0),
                                                           ss.at(f, 2, t0), ss.at(f, 3, t0), n));
                }
              }
            },
            prog);
      });
}

namespace {

// MDEV's inner sum at j exactly: sum_{i=j}^{j+m-1} d_i = S(j+2m) - 2 S(j+m) + S(j) with S(a) the
// phase summed over [a, a + m) (minus x_0, which cancels).
double mdev_inner(const phase_source& x, std::size_t j, std::size_t m, phase_reader& r) {
  const auto s = [&](std::size_t a) { return x.offset_sum(a, a + m, r); };
  return static_cast<double>(s(j + 2 * m) - 2.0L * s(j + m) + s(j));
}

// One chunk of MDEV sums: restart every factor's inner sum, then slide it block by block.
void mdev_chunk(const phase_source& x, const plan& p, stream_set& ss, index c0, index c1,
                long double* sums) {
  const std::size_t nf = p.factors.size();
  std::vector<double> inner(nf, 0.0);
  for (std::size_t f = 0; f < nf; ++f)
    if (c0 < p.factors[f].hi)
      inner[f] = mdev_inner(x, static_cast<std::size_t>(c0), p.factors[f].m, ss.spare());
  std::vector<double> delta(static_cast<std::size_t>(block_terms));
  for (index b = c0; b < c1; b += block_terms) {
    ss.load(b);
    for (std::size_t f = 0; f < nf; ++f) {
      if (!ss.active(f)) continue;
      const index hi = p.factors[f].hi;
      const auto n = static_cast<std::size_t>(std::min(hi, b + block_terms) - b);
      // The last term of the whole range has no next step.
      const auto steps =
          static_cast<std::size_t>(std::min<index>(static_cast<index>(n), hi - 1 - b));
      if (steps > 0) {
        // d_{j+m} - d_j = x_{j+3m} - 3x_{j+2m} + 3x_{j+m} - x_j.
        mdev_steps(ss.at(f, 0, b), ss.at(f, 1, b), ss.at(f, 2, b), ss.at(f, 3, b), delta.data(),
                   steps);
      }
      std::fill(delta.begin() + static_cast<index>(steps), delta.begin() + static_cast<index>(n),
                0.0);
      sums[f] += static_cast<long double>(slide(inner[f], delta.data(), n));
    }
  }
}

}  // namespace

std::vector<long double> mdev_sums(const phase_source& x, const std::vector<std::size_t>& factors,
                                   const progress_fn& on_progress) {
  std::vector<term_range> fs;
  fs.reserve(factors.size());
  for (std::size_t m : factors)
    fs.push_back({m, 0, 3 * m <= x.size() ? static_cast<index>(x.size() - 3 * m + 1) : 0});
  return in_groups(3, fs, x.size(), on_progress, [&](const auto& sub, const progress_fn& prog) {
    const plan p = make_plan(x.size(), 3, false, sub);
    return run_sweep(
        x, p,
        [&](stream_set& ss, index c0, index c1, long double* sums) {
          mdev_chunk(x, p, ss, c0, c1, sums);
        },
        prog);
  });
}

}  // namespace gyroflip::analysis::detail
