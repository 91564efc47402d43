/// \file
/// \brief The library's one parallel helper: numbered work items on a few threads (the caller's
/// included), each taking the next item, with exceptions passed on to the caller. Used by the
/// analysis passes over the phase and by the workflow's simulation campaigns. No global state:
/// each call starts and joins its own threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "gyroflip/core/progress.hpp"

namespace gyroflip {

/// The number of hardware threads (at least 1).
[[nodiscard]] inline std::size_t hardware_threads() noexcept {
  return std::max(1u, std::thread::hardware_concurrency());
}

/// Runs f(worker, item) for item in [0, count) on `workers` threads, each taking the next item;
/// `worker` (0 = the caller's thread) indexes per-thread state. f must not touch another item's
/// data. After each of its items the caller's thread reports the number done (`on_progress(done,
/// count)`, then once more `(count, count)` at the end).
///
/// Exceptions are passed on: the first one thrown, by f on any thread or by the progress report
/// (a cancel, core/progress.hpp), stops the pass (no item starts after it), the threads are
/// joined and that exception is rethrown on the caller's thread. The library's public functions
/// turn what f throws into a `result` error where it is a failure of the data.
template <class F>
void for_each_item(std::size_t count, std::size_t workers, F f,
                   const progress_fn& on_progress = {}) {
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::exception_ptr first;
  std::mutex first_mutex;
  const auto stop_with = [&](std::exception_ptr e) {
    const std::lock_guard lock(first_mutex);
    if (!first) first = std::move(e);
    next = count;
  };
  const auto work = [&](std::size_t w) {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        f(w, i);
        const std::size_t d = ++done;
        if (w == 0 && on_progress) on_progress(d, count);
      } catch (...) {
        stop_with(std::current_exception());
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < std::min(workers, count); ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  if (first) std::rethrow_exception(first);
  if (on_progress) on_progress(count, count);
}

/// Progress of part `k` of `parts` equal parts of one long job, as one line.
[[nodiscard]] inline progress_fn part_progress(const progress_fn& p, std::size_t k,
                                               std::size_t parts) {
  if (!p) return {};
  return
      [&p, k, parts](std::size_t done, std::size_t total) { p(k * total + done, parts * total); };
}

}  // namespace gyroflip
