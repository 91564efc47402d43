/// \file
/// \brief Private to the analysis module: how many threads a pass over the phase uses, and a pass
/// over numbered work items on them (the caller's thread included). No global state: each call
/// starts and joins its own threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

#include "gyroflip/analysis/phase_source.hpp"

namespace gyroflip::analysis::detail {

/// Threads for a pass over n points: 1 below 2^16 points (starting threads would cost more than
/// it saves), else every core up to 8.
inline std::size_t worker_count(std::size_t n_points) {
  if (n_points < (std::size_t{1} << 16)) return 1;
  return std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), 8);
}

/// Runs f(worker, item) for item in [0, count) on `workers` threads, each taking the next item;
/// `worker` (0 = the caller's thread) indexes per-thread state. f must not touch another item's
/// data. After each of its items the caller's thread reports the number done (progress line).
/// A report that throws cancels the pass (core/progress.hpp): no item starts after it, the
/// threads are joined, and the exception goes on to the caller.
template <class F>
void for_each_item(std::size_t count, std::size_t workers, F f,
                   const progress_fn& on_progress = {}) {
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::exception_ptr cancelled;
  const auto work = [&](std::size_t w) {
    for (std::size_t i = next++; i < count; i = next++) {
      f(w, i);
      const std::size_t d = ++done;
      if (w != 0 || !on_progress) continue;
      try {
        on_progress(d, count);
      } catch (...) {
        cancelled = std::current_exception();
        next = count;
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < std::min(workers, count); ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  if (cancelled) std::rethrow_exception(cancelled);
  if (on_progress) on_progress(count, count);
}

/// Progress of part `k` of `parts` equal parts of one long job, as one line.
inline progress_fn part_progress(const progress_fn& p, std::size_t k, std::size_t parts) {
  if (!p) return {};
  return
      [&p, k, parts](std::size_t done, std::size_t total) { p(k * total + done, parts * total); };
}

}  // namespace gyroflip::analysis::detail
