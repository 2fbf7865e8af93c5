// CPU accounts: a scope charges its thread's CPU time to its account, pool threads that help a
// loop started inside a scope charge theirs to the same account, and nested scopes split the
// time instead of counting it twice. Work is measured in CPU time burnt, never in wall time.
#include "common/thread_cpu.h"

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>

#include "common/thread_pool.h"

namespace fq {
namespace {

constexpr int64_t kMs = 1'000'000;

/// Runs on the calling thread until it has used `ns` of CPU; returns the CPU it used.
int64_t burn(int64_t ns) {
  const int64_t t0 = thread_cpu_ns();
  volatile uint64_t x = 0;
  int64_t used = 0;
  while ((used = thread_cpu_ns() - t0) < ns) x = x + 1;
  return used;
}

TEST(ThreadCpu, ClockAdvancesWithWorkOnly) {
  const int64_t t0 = thread_cpu_ns();
  EXPECT_GE(burn(5 * kMs), 5 * kMs);
  EXPECT_GE(thread_cpu_ns() - t0, 5 * kMs);
}

TEST(CpuScope, ChargesTheThreadsWorkToItsAccount) {
  CpuAccount account{0};
  EXPECT_EQ(CpuScope::current(), nullptr);
  int64_t used = 0;
  {
    const CpuScope scope(account);
    EXPECT_EQ(CpuScope::current(), &account);
    used = burn(10 * kMs);
  }
  EXPECT_EQ(CpuScope::current(), nullptr);
  EXPECT_GE(account.load(), used);
}

TEST(CpuScope, NestedScopesSplitTheTime) {
  CpuAccount outer{0}, inner{0};
  int64_t outer_used = 0, inner_used = 0;
  {
    const CpuScope a(outer);
    outer_used += burn(5 * kMs);
    {
      const CpuScope b(inner);
      EXPECT_EQ(CpuScope::current(), &inner);
      inner_used = burn(30 * kMs);
    }
    EXPECT_EQ(CpuScope::current(), &outer);
    outer_used += burn(5 * kMs);
  }
  EXPECT_GE(inner.load(), inner_used);
  EXPECT_GE(outer.load(), outer_used);
  EXPECT_LT(outer.load(), inner_used) << "the inner scope's time was counted in the outer one too";
}

TEST(CpuScope, PoolThreadsChargeTheCallersAccount) {
  constexpr int kThreads = 3;
  ThreadPool pool(kThreads - 1);
  ASSERT_EQ(pool.workers(), kThreads - 1);
  CpuAccount account{0};
  std::atomic<int64_t> used{0};
  std::mutex m;
  std::condition_variable cv;
  int arrived = 0;
  {
    const CpuScope scope(account);
    // One item per thread, each waiting for the others: every item runs on its own thread.
    pool.run(kThreads, kThreads, [&](size_t begin, size_t end, size_t) {
      for (size_t i = begin; i < end; ++i) {
        {
          std::unique_lock lock(m);
          ++arrived;
          cv.notify_all();
          cv.wait(lock, [&] { return arrived == kThreads; });
        }
        used += burn(10 * kMs);
      }
    });
  }
  EXPECT_GE(used.load(), kThreads * 10 * kMs);
  EXPECT_GE(account.load(), used.load()) << "the pool threads' share was not charged";
}

}  // namespace
}  // namespace fq
