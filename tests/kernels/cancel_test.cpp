// Cooperative cancellation of the CPU engine (core/cancel_token.h): a token that never
// expires changes no result bit; an expired one ends the run with kCancelled, also part way
// through a long parallel loop, and the engine serves the next frame exactly as a fresh one.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>

#include "core/parallel_for.h"
#include "kernels/cpu_engine.h"
#include "tests/kernels/frame_result_checks.h"
#include "tests/support/test_meshes.h"

namespace fq {
namespace {

using test::expect_identical;
using test::noisy;

using Clock = CancelToken::Clock;

std::vector<std::pair<std::string, Params>> modes() {
  Params qf;
  qf.cluster = true;
  qf.clustering.sigma_d = 2.f;
  Params refined = qf;
  refined.filtering.method = FilterMethod::kQuadricRefined;
  Params bilateral = qf;
  bilateral.filtering.method = FilterMethod::kBilateral;
  Params target = qf;  // through the cluster options (several engine runs per frame)
  target.clustering.target_clusters = 12;
  Params links = qf;
  links.clustering.keep_links = true;
  return {{"qf", qf}, {"qf+", refined}, {"bf", bilateral}, {"target", target}, {"links", links}};
}

TEST(KernelCancel, ATokenThatNeverExpiresChangesNoResult) {
  const Mesh m = noisy(test::make_icosphere(4), 5);
  const std::atomic<bool> stop{false};
  const CancelToken token(&stop, Clock::now() + std::chrono::hours(1));
  for (const auto& [name, p] : modes()) {
    CpuEngine plain(2), watched(2);
    watched.set_cancel_token(&token);
    FrameResult a, b;
    ASSERT_TRUE(plain.process(m.view(), p, a).ok()) << name;
    const Status s = watched.process(m.view(), p, b);
    ASSERT_TRUE(s.ok()) << name << ": " << s.message();
    expect_identical(a, b, name);
  }
}

TEST(KernelCancel, AStoppedTokenEndsTheRunAndTheEngineServesTheNextFrame) {
  const Mesh m = noisy(test::make_icosphere(4), 6);
  for (const auto& [name, p] : modes()) {
    const std::atomic<bool> stop{true};
    const CancelToken token(&stop);
    CpuEngine engine(2), fresh(2);
    engine.set_cancel_token(&token);
    FrameResult r;
    const Status s = engine.process(m.view(), p, r);
    EXPECT_EQ(s.code(), StatusCode::kCancelled) << name << ": " << s.message();
    EXPECT_EQ(s.message(), "cancelled") << name;
    engine.set_cancel_token(nullptr);
    FrameResult again, want;
    ASSERT_TRUE(engine.process(m.view(), p, again).ok()) << name;
    ASSERT_TRUE(fresh.process(m.view(), p, want).ok()) << name;
    expect_identical(again, want, name + " after a cancelled run");
  }
}

// A neighbourhood far wider than the mesh: every pass visits every vertex from every
// vertex, seconds of work. A deadline in a few milliseconds ends it as kCancelled (and the
// time limit's message), however loaded the machine.
TEST(KernelCancel, ADeadlineEndsAWideNeighbourhoodRun) {
  const Mesh m = noisy(test::make_icosphere(5), 7);  // 10,242 vertices
  Params p;
  p.filtering.sigma_s = 200.f;
  p.cluster = true;
  p.clustering.sigma_d = 200.f;
  const CancelToken token(nullptr, Clock::now() + std::chrono::milliseconds(5));
  CpuEngine engine(2);
  engine.set_cancel_token(&token);
  FrameResult r;
  const Status s = engine.process(m.view(), p, r);
  EXPECT_EQ(s.code(), StatusCode::kCancelled) << s.message();
  EXPECT_EQ(s.message(), "time limit exceeded");
}

// Inside one loop: once the token expires, chunks not yet started are skipped.
TEST(KernelCancel, ALoopSkipsTheChunksLeftOnceTheTokenExpires) {
  constexpr uint32_t kItems = 1u << 20;
  for (int threads : {1, 2}) {
    std::atomic<bool> stop{false};
    const CancelToken token(&stop);
    std::atomic<uint32_t> ran{0};
    {
      const CancelScope scope(&token);
      parallel_for(kItems, threads, [&](uint32_t) {
        ran.fetch_add(1, std::memory_order_relaxed);
        stop = true;  // expires during the first chunk of each thread
      });
    }
    // At most the chunks already started when the flag was set (256 items each).
    EXPECT_GT(ran.load(), 0u) << threads << " threads";
    EXPECT_LT(ran.load(), kItems / 64) << threads << " threads: the loop ran on after the token expired";
    // Outside the scope, loops run whole whatever the token says.
    ran = 0;
    parallel_for(kItems, threads, [&](uint32_t) { ran.fetch_add(1, std::memory_order_relaxed); });
    EXPECT_EQ(ran.load(), kItems) << threads << " threads";
  }
}

}  // namespace
}  // namespace fq
