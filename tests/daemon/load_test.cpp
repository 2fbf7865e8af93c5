// The latency policy under load: latest frame wins (superseded counted), frames older than
// a tiny budget are dropped (counted), and every frame is accounted for.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "tests/daemon/daemon_harness.h"

namespace fq::test {
namespace {

// frames_in == frames_out + errors + superseded + dropped_stale + refused once the pipeline is idle.
uint64_t accounted(const wire::StreamCounters& c) {
  return c.frames_out() + c.errors() + c.superseded() + c.dropped_stale() + c.refused();
}

// Polls the counters until every frame of `stream` is accounted for (or 60 s pass).
wire::StreamCounters settled_counters(DaemonHarness& h, const std::string& stream, uint64_t frames) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  wire::StreamCounters c = h.counters(stream);
  while (accounted(c) < frames && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // waiting, not ordering
    c = h.counters(stream);
  }
  return c;
}

TEST(DaemonLoad, LatestFrameWinsAndSupersededFramesAreCounted) {
  daemon::DaemonConfig c = test_config();
  c.engine.cpu_threads = 1;
  DaemonHarness h(c);
  // A burst of frames that takes the engine much longer to process than to arrive: while
  // it works on the first, the others replace each other in the stream's waiting slot.
  const Mesh mesh = noisy_sphere(5, 4);
  client::FrameSpec spec;
  spec.stream_id = "burst";
  std::vector<std::string> parts;
  ASSERT_TRUE(client::build_frame(mesh.view(), spec, 0, parts).ok());
  constexpr uint64_t kFrames = 8;
  for (uint64_t i = 0; i < kFrames; ++i) {
    ASSERT_GT(client::restamp_frame(parts, i), 0);
    h.send_parts(parts);
  }
  // The last frame is never superseded; once its result is out, every frame is accounted.
  std::vector<uint64_t> seen;
  for (;;) {
    const client::ReceivedResult r = h.receive("burst");
    ASSERT_NE(r.header.status(), wire::ERROR) << r.header.error();
    if (!seen.empty()) {
      EXPECT_GT(r.header.sequence(), seen.back()) << "results out of order";
    }
    seen.push_back(r.header.sequence());
    if (r.header.sequence() == kFrames - 1 || testing::Test::HasFailure()) break;
  }
  const wire::StreamCounters k = settled_counters(h, "burst", kFrames);
  EXPECT_EQ(k.frames_in(), kFrames);
  EXPECT_EQ(k.frames_out(), seen.size());
  EXPECT_GE(k.superseded(), 1u);
  EXPECT_EQ(k.frames_out() + k.superseded() + k.dropped_stale(), kFrames);
}

TEST(DaemonLoad, SeveralEnginesStillPublishEachStreamInOrder) {
  daemon::DaemonConfig c = test_config();
  c.engine.cpu_engines = 3;
  c.engine.cpu_threads = 1;
  DaemonHarness h(c);
  ASSERT_EQ(h.daemon()->engine_names().size(), 3u);
  // Large and small frames alternate: a small frame taken by a free engine while a large one
  // is on another finishes first, and the publisher must hold it back.
  const Mesh large = noisy_sphere(3, 4), small = noisy_sphere(4, 1);
  client::FrameSpec spec;
  spec.stream_id = "mixed";
  constexpr uint64_t kFrames = 12;
  std::vector<std::vector<std::string>> frames(2);
  ASSERT_TRUE(client::build_frame(large.view(), spec, 0, frames[0]).ok());
  ASSERT_TRUE(client::build_frame(small.view(), spec, 0, frames[1]).ok());
  for (uint64_t i = 0; i < kFrames; ++i) {
    std::vector<std::string> parts = frames[i % 2];
    ASSERT_GT(client::restamp_frame(parts, i), 0);
    h.send_parts(parts);
  }
  std::vector<uint64_t> seen;
  while (!testing::Test::HasFailure()) {
    const client::ReceivedResult r = h.receive("mixed");
    ASSERT_NE(r.header.status(), wire::ERROR) << r.header.error();
    seen.push_back(r.header.sequence());
    if (r.header.sequence() == kFrames - 1) break;
  }
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())) << "results out of order";
  EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << "a result twice";
  // A frame still in a decoder when the last result is out is counted superseded just after.
  const wire::StreamCounters k = settled_counters(h, "mixed", kFrames);
  EXPECT_EQ(k.frames_out(), seen.size());
  EXPECT_EQ(accounted(k), kFrames);
}

TEST(DaemonLoad, FramesOlderThanATinyBudgetAreDroppedAndCounted) {
  daemon::DaemonConfig c = test_config();
  c.streams["tiny"] = c.defaults;
  c.streams["tiny"].budget_ms = 0.001;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere();
  client::FrameSpec spec;
  spec.stream_id = "tiny";
  constexpr uint64_t kFrames = 6;
  for (uint64_t i = 0; i < kFrames; ++i) h.send(mesh, spec, i);
  const wire::StreamCounters k = settled_counters(h, "tiny", kFrames);
  EXPECT_EQ(k.frames_in(), kFrames);
  EXPECT_EQ(accounted(k), kFrames);
  EXPECT_GE(k.dropped_stale(), 1u);
  EXPECT_EQ(k.errors(), 0u);
  EXPECT_EQ(k.late(), k.frames_out()) << "a result past a 1 us budget must be flagged late";
}

}  // namespace
}  // namespace fq::test
