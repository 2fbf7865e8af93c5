// The shared host thread pool: every item once, worker ids in range and never shared while in
// use, nested and concurrent calls complete, and a pool without workers runs on its caller.
#include "common/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace fq {
namespace {

/// Runs [0, count) on `pool` and checks each item ran once, with a valid, unshared worker id.
void check_run(ThreadPool& pool, size_t count, int max_workers, size_t grain) {
  std::vector<std::atomic<int>> hits(count);
  std::vector<std::atomic<int>> busy(size_t(std::max(max_workers, 1)));
  std::atomic<bool> bad_worker{false}, shared_worker{false};
  pool.run(
      count, max_workers,
      [&](size_t begin, size_t end, size_t w) {
        if (w >= busy.size()) {
          bad_worker = true;
          return;
        }
        if (busy[w].fetch_add(1) != 0) shared_worker = true;
        for (size_t i = begin; i < end; ++i) hits[i].fetch_add(1);
        busy[w].fetch_sub(1);
      },
      grain);
  EXPECT_FALSE(bad_worker);
  EXPECT_FALSE(shared_worker);
  for (size_t i = 0; i < count; ++i) ASSERT_EQ(hits[i].load(), 1) << "item " << i;
}

TEST(ThreadPool, EveryItemOnceOnAValidWorker) {
  ThreadPool pool(3);
  EXPECT_EQ(pool.workers(), 3);
  for (size_t count : {size_t(0), size_t(1), size_t(7), size_t(1000), size_t(100003)}) {
    for (int workers : {1, 2, 4, 16}) {
      for (size_t grain : {size_t(1), size_t(64), size_t(4096)}) check_run(pool, count, workers, grain);
    }
  }
}

TEST(ThreadPool, WithoutHelpersEverythingRunsOnTheCaller) {
  ThreadPool pool(0);
  const auto caller = std::this_thread::get_id();
  std::atomic<bool> elsewhere{false};
  pool.run(500, 8, [&](size_t, size_t, size_t w) {
    elsewhere = elsewhere || w != 0 || std::this_thread::get_id() != caller;
  });
  EXPECT_FALSE(elsewhere);
  check_run(pool, 300, 4, 1);
}

TEST(ThreadPool, NestedAndConcurrentCallsComplete) {
  ThreadPool pool(2);
  // Several threads each run loops whose items run loops of their own on the same pool: the
  // caller always works on its own loop, so nothing waits for a worker that never comes.
  std::vector<std::thread> callers;
  std::atomic<size_t> total{0};
  for (int c = 0; c < 4; ++c) {
    callers.emplace_back([&] {
      for (int rep = 0; rep < 20; ++rep) {
        pool.run(8, 3, [&](size_t b, size_t e, size_t) {
          for (size_t i = b; i < e; ++i)
            pool.run(
                100, 2, [&](size_t b2, size_t e2, size_t) { total += e2 - b2; }, 7);
        });
      }
    });
  }
  for (auto& t : callers) t.join();
  EXPECT_EQ(total.load(), size_t(4) * 20 * 8 * 100);
}

TEST(ThreadPool, AnExceptionOnTheCallerReachesItAndThePoolGoesOn) {
  ThreadPool pool(2);
  // Only worker 0 (the caller) throws: on a pool thread an exception would end the process.
  // Helpers hold their first range until the caller has one, so that the caller surely does.
  std::atomic<bool> caller_in{false};
  EXPECT_THROW(pool.run(10000, 3,
                        [&](size_t, size_t, size_t w) {
                          if (w == 0) {
                            caller_in = true;
                            throw std::runtime_error("item failed");
                          }
                          while (!caller_in) std::this_thread::yield();
                        }),
               std::runtime_error);
  check_run(pool, 1000, 3, 8);
}

TEST(ThreadPool, SharedPoolLeavesTheCallerOneCore) {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  EXPECT_EQ(ThreadPool::shared().workers(), int(hw) - 1);
  check_run(ThreadPool::shared(), 5000, 64, 16);
}

}  // namespace
}  // namespace fq
