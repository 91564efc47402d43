// The library's one parallel helper (issue 22): every item once, on several threads, and an
// exception thrown by a work item on any thread, or by the progress report, reaches the caller
// after the threads are joined (before issue 22 a work item's exception on a worker thread ended
// the process: std::terminate).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/core/parallel.hpp"

namespace gyroflip {
namespace {

TEST(Parallel, EveryItemRunsOnceAndProgressEndsAtTheCount) {
  std::vector<std::atomic<int>> seen(1000);
  std::size_t last = 0;
  for_each_item(
      seen.size(), 4, [&](std::size_t, std::size_t i) { ++seen[i]; },
      [&](std::size_t done, std::size_t total) {
        EXPECT_EQ(total, 1000u);
        EXPECT_GE(done, last);
        last = done;
      });
  for (const auto& s : seen) EXPECT_EQ(s.load(), 1);
  EXPECT_EQ(last, 1000u);
}

TEST(Parallel, AWorkItemsExceptionOnAnyThreadReachesTheCaller) {
  for (const std::size_t bad : {0u, 1u, 57u, 399u}) {
    std::atomic<std::size_t> started{0};
    try {
      for_each_item(400, 4, [&](std::size_t, std::size_t i) {
        ++started;
        if (i == bad) throw std::runtime_error("item " + std::to_string(i));
        std::this_thread::sleep_for(std::chrono::microseconds(500));
      });
      ADD_FAILURE() << "no exception for item " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "item " + std::to_string(bad));
    }
    // The threads were joined before the exception came out: nothing runs after it.
    const std::size_t at_return = started.load();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_EQ(started.load(), at_return) << bad;
    // A failure stops the pass: of 400 half-millisecond items (0.05 s on 4 threads) the first
    // one's failure leaves most unstarted.
    if (bad == 0) {
      EXPECT_LT(at_return, 200u);
    }
  }
}

TEST(Parallel, AProgressReportThatThrowsCancelsThePass) {
  std::atomic<std::size_t> ran{0};
  // Items of 0.2 ms: only the caller's thread reports, so with instant items the other thread
  // could finish all of them while the caller's waits for a core (seen on a loaded machine).
  EXPECT_THROW(for_each_item(
                   10000, 2,
                   [&](std::size_t, std::size_t) {
                     ++ran;
                     std::this_thread::sleep_for(std::chrono::microseconds(200));
                   },
                   [](std::size_t done, std::size_t) {
                     if (done >= 10) throw std::logic_error("cancelled");
                   }),
               std::logic_error);
  EXPECT_LT(ran.load(), 10000u);
}

}  // namespace
}  // namespace gyroflip
