// The one thread pool (sweep/parallel.h): every index once, the lowest failing index's
// exception (the serial loop's), cancellation, the monitor on the calling thread.

#include "deploysim/sweep/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

TEST(ParallelFor, RunsEveryIndexExactlyOnce) {
  for (const int threads : {1, 2, 4}) {
    for (const std::size_t chunk : {1u, 7u}) {
      std::vector<std::atomic<int>> hits(1000);
      ParallelOptions o;
      o.threads = threads;
      o.chunk = chunk;
      ParallelFor(
          hits.size(), [&](std::size_t k) { hits[k].fetch_add(1); }, o);
      for (std::size_t k = 0; k < hits.size(); ++k) {
        ASSERT_EQ(hits[k].load(), 1) << "index " << k << ", " << threads << " threads";
      }
    }
  }
}

TEST(ParallelFor, RethrowsTheLowestFailingIndexLikeASerialLoop) {
  for (const int threads : {1, 3}) {
    ParallelOptions o;
    o.threads = threads;
    o.chunk = 4;
    std::atomic<std::size_t> below{0};
    try {
      ParallelFor(
          400,
          [&](std::size_t k) {
            if (k % 50 == 17) throw std::invalid_argument("case " + std::to_string(k));
            if (k < 17) below.fetch_add(1);
          },
          o);
      FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
      EXPECT_STREQ(e.what(), "case 17");
    }
    EXPECT_EQ(below.load(), 17u) << "every index below the failing one ran";
  }
}

TEST(ParallelFor, StopsStartingIndicesWhenCancelled) {
  std::atomic<std::size_t> ran{0};
  std::atomic<bool> cancel{false};
  ParallelOptions o;
  o.threads = 2;
  o.cancelled = [&] { return cancel.load(); };
  ParallelFor(
      100000,
      [&](std::size_t) {
        // Every body from the tenth on raises the flag before it returns, so a thread
        // completes at most one body once ten have started: the other thread may run any
        // number of bodies between a fetch_add and a store, but each of those stores too.
        if (ran.fetch_add(1) + 1 >= 10) cancel.store(true);
      },
      o);
  EXPECT_GE(ran.load(), 10u);
  EXPECT_LE(ran.load(), 11u);  // ten, plus one already started on the other thread
}

TEST(ParallelFor, MonitorRunsOnTheCallingThreadWhileWorkersWork) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> monitor_calls{0};
  std::atomic<bool> monitor_elsewhere{false};
  std::atomic<bool> body_on_caller{false};
  // The work waits for the monitor's first call (a handshake, not a delay): the monitor
  // has then run while the workers were busy, whatever the machine's load.
  std::promise<void> first_call;
  const std::shared_future<void> monitored = first_call.get_future().share();
  ParallelOptions o;
  o.threads = 2;
  o.monitor_interval = 0.001;
  o.monitor = [&] {
    if (std::this_thread::get_id() != caller) monitor_elsewhere = true;
    if (monitor_calls.fetch_add(1) == 0) first_call.set_value();
  };
  ParallelFor(
      20,
      [&](std::size_t) {
        if (std::this_thread::get_id() == caller) body_on_caller = true;
        monitored.wait();
      },
      o);
  EXPECT_GE(monitor_calls.load(), 2);  // during the run and once at the end
  EXPECT_FALSE(monitor_elsewhere.load());
  EXPECT_FALSE(body_on_caller.load());
}

TEST(ParallelFor, AMonitorErrorStopsTheWorkAndIsRethrown) {
  std::atomic<std::size_t> ran{0};
  ParallelOptions o;
  o.threads = 2;
  o.monitor_interval = 0.001;
  o.monitor = [] { throw std::runtime_error("disk full"); };
  EXPECT_THROW(ParallelFor(
                   1000000,
                   [&](std::size_t) {
                     ran.fetch_add(1);
                     std::this_thread::sleep_for(std::chrono::microseconds(50));
                   },
                   o),
               std::runtime_error);
  EXPECT_LT(ran.load(), 1000000u);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
