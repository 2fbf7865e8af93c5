// The host memory budget (daemon/stream/memory_account.h): the account's arithmetic, and the
// order in which the pipeline's shedder makes room (daemon/pipeline/memory_shed.h) over real
// streams of a real registry, with histories a real CPU engine left and /latest copies.
#include "daemon/stream/memory_account.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "daemon/pipeline/memory_shed.h"
#include "daemon/stream/latest_results.h"
#include "daemon/stream/stream_history.h"
#include "daemon/stream/stream_registry.h"
#include "eval/noise.h"
#include "kernels/cpu_engine.h"
#include "tests/support/test_meshes.h"

namespace fq::daemon {
namespace {

TEST(MemoryAccount, ChargesWithinTheBudgetAndRefusesWhatWouldPassIt) {
  MemoryAccount a;
  a.set_budget(1000);
  EXPECT_TRUE(a.charge(MemoryKind::kHistory, 600, Shed::kNone, nullptr));
  EXPECT_TRUE(a.charge(MemoryKind::kQueued, 400, Shed::kNone, nullptr));      // exactly the budget
  EXPECT_FALSE(a.charge(MemoryKind::kLatest, 1, Shed::kHistories, nullptr));  // no shedder: nothing goes
  EXPECT_EQ(a.total(), 1000u);
  a.credit(MemoryKind::kHistory, 100);
  EXPECT_EQ(a.bytes(MemoryKind::kHistory), 500u);
  EXPECT_TRUE(a.charge(MemoryKind::kLatest, 100, Shed::kNone, nullptr));
  EXPECT_EQ(a.bytes(MemoryKind::kLatest), 100u);
  a.credit(MemoryKind::kLatest, 5000);  // never below zero
  EXPECT_EQ(a.bytes(MemoryKind::kLatest), 0u);
  EXPECT_EQ(a.total(), 900u);
  EXPECT_FALSE(a.charge(MemoryKind::kQueued, 2000, Shed::kHistories, nullptr));  // over the whole budget
  a.set_budget(0);                                                               // unbounded
  EXPECT_TRUE(a.charge(MemoryKind::kQueued, uint64_t{1} << 50, Shed::kNone, nullptr));
}

TEST(MemoryAccount, AChargeHoldsWhatItWasSetToUntilReleasedOrDestroyed) {
  MemoryAccount a;
  a.set_budget(1000);
  {
    MemoryCharge c;
    EXPECT_TRUE(c.set(&a, MemoryKind::kHistory, 300, Shed::kNone, nullptr));
    EXPECT_TRUE(c.set(&a, MemoryKind::kHistory, 800, Shed::kNone, nullptr));  // 500 more
    EXPECT_EQ(a.bytes(MemoryKind::kHistory), 800u);
    EXPECT_FALSE(c.set(&a, MemoryKind::kHistory, 1200, Shed::kNone, nullptr));
    EXPECT_EQ(c.bytes(), 800u);  // a failed set keeps what it held
    EXPECT_TRUE(c.set(&a, MemoryKind::kHistory, 200, Shed::kNone, nullptr));  // less: credited at once
    EXPECT_EQ(a.total(), 200u);
    MemoryCharge moved = std::move(c);  // the charge goes with it, not twice
    EXPECT_EQ(moved.bytes(), 200u);
    EXPECT_EQ(a.total(), 200u);
  }
  EXPECT_EQ(a.total(), 0u);
  MemoryCharge none;
  EXPECT_TRUE(none.set(nullptr, MemoryKind::kQueued, 1ull << 40, Shed::kNone, nullptr));  // no account
  EXPECT_EQ(none.bytes(), 0u);
}

// Each shed step frees only as far as the charge asks: the shedder here frees 100 bytes per
// call of what a test charged, and a charge that still does not fit fails.
TEST(MemoryAccount, AChargeThatDoesNotFitAsksTheShedderForWhatItLacks) {
  MemoryAccount a;
  a.set_budget(1000);
  MemoryCharge kept;
  ASSERT_TRUE(kept.set(&a, MemoryKind::kHistory, 900, Shed::kNone, nullptr));
  std::vector<uint64_t> asked;
  a.set_shedder([&](uint64_t need, Shed upto, const void*) {
    asked.push_back(need);
    if (upto == Shed::kHistories)
      kept.set(&a, MemoryKind::kHistory, kept.bytes() - 100, Shed::kNone, nullptr);
  });
  EXPECT_TRUE(a.charge(MemoryKind::kQueued, 200, Shed::kHistories, nullptr));
  EXPECT_EQ(asked, std::vector<uint64_t>{100});
  EXPECT_FALSE(a.charge(MemoryKind::kQueued, 200, Shed::kIdleLatest, nullptr));  // the shedder freed nothing
  EXPECT_EQ(a.total(), 1000u);
  a.set_shedder({});
}

Mesh noisy_sphere(uint64_t seed) {
  Mesh m = test::make_icosphere(3);
  add_gaussian_noise(m, 0.2, seed);
  return m;
}

Params temporal_params() {
  Params p;  // qf+, the default filter
  p.filtering.temporal = 0.75f;
  return p;
}

// Streams of a registry with the budget as fqd installs it: /latest copies of idle streams go
// first, then histories from the stream a frame used longest ago, never the charging stream's.
TEST(MemoryBudget, RoomIsMadeFromIdleLatestCopiesThenTheLeastRecentlyUsedHistories) {
  DaemonConfig c;
  c.caps.memory_budget_mb = 0;  // set below, once the sizes are known
  StreamRegistry registry(c);
  LatestResults latest(registry);
  MemoryAccount& memory = registry.memory();
  memory.set_shedder(
      [&](uint64_t need, Shed upto, const void* keep) { shed_memory(registry, latest, need, upto, keep); });
  CpuEngine engine(2);
  const Params p = temporal_params();
  std::vector<StreamPtr> streams;
  for (int i = 0; i < 3; ++i) {
    StreamPtr s = registry.admit("cam" + std::to_string(i), 0);
    ASSERT_TRUE(s);
    FrameResult r;
    const Mesh m = noisy_sphere(static_cast<uint64_t>(i) + 1);
    ASSERT_TRUE(with_history(*s, 1, p, engine, [&] { return engine.process(m.view(), p, r); }).ok());
    EXPECT_GT(s->temporal.charge.bytes(), 0u);
    EXPECT_EQ(s->temporal.charge.bytes(), history_bytes(s->temporal.history));
    s->kept_ns = 100 + i;  // cam0 had its frame longest ago
    streams.push_back(s);
  }
  const uint64_t history = streams[0]->temporal.charge.bytes();
  // A /latest copy of cam2, which nobody watches any more.
  const std::vector<std::string> chunks = {std::string(4096, 'x')};
  wire::ResultHeader h;
  h.set_status(wire::OK);
  h.set_form(wire::MESH);
  EXPECT_EQ(latest.wait_newer("cam2", 0, std::chrono::milliseconds(0)), nullptr);  // watched now
  latest.offer(*streams[2], h, chunks, {});
  EXPECT_EQ(streams[2]->latest.charge.bytes(), 4096u);
  streams[2]->latest.watched_until = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  EXPECT_EQ(memory.bytes(MemoryKind::kLatest), 4096u);

  memory.set_budget(memory.total() + 1000);
  // 3,000 more: the idle copy (4,096) is enough.
  MemoryCharge frame;
  ASSERT_TRUE(frame.set(&memory, MemoryKind::kQueued, 3000, Shed::kHistories, streams[1].get()));
  EXPECT_EQ(memory.bytes(MemoryKind::kLatest), 0u);
  EXPECT_EQ(streams[2]->latest.latest, nullptr);
  for (const StreamPtr& s : streams) EXPECT_FALSE(s->temporal.history.empty()) << s->id();
  // A /latest copy may not take histories: cam1's would need one.
  MemoryCharge copy;
  EXPECT_FALSE(copy.set(&memory, MemoryKind::kLatest, 3000, Shed::kIdleLatest, streams[1].get()));
  for (const StreamPtr& s : streams) EXPECT_FALSE(s->temporal.history.empty()) << s->id();
  // A frame of cam0 needing a history's room: cam1's goes (cam0 is the charging stream).
  ASSERT_TRUE(frame.set(&memory, MemoryKind::kQueued, 3000 + history, Shed::kHistories, streams[0].get()));
  EXPECT_FALSE(streams[0]->temporal.history.empty());
  EXPECT_TRUE(streams[1]->temporal.history.empty());
  EXPECT_FALSE(streams[2]->temporal.history.empty());
  EXPECT_EQ(streams[1]->samples().counters.memory_resets, 1u);
  EXPECT_EQ(streams[1]->temporal.charge.bytes(), 0u);
  // More than every other history frees: cam2's goes, then nothing is left but cam0's own.
  EXPECT_FALSE(
      frame.set(&memory, MemoryKind::kQueued, 3000 + 3 * history, Shed::kHistories, streams[0].get()));
  EXPECT_TRUE(streams[2]->temporal.history.empty());
  EXPECT_FALSE(streams[0]->temporal.history.empty());
  EXPECT_EQ(streams[0]->samples().counters.memory_resets, 0u);
  EXPECT_EQ(streams[2]->samples().counters.memory_resets, 1u);
  EXPECT_LE(memory.total(), memory.budget());
  // The next frame of a stream that lost its history runs alone and keeps one again.
  FrameResult r;
  const Mesh m = noisy_sphere(9);
  frame.release();
  ASSERT_TRUE(with_history(*streams[1], 2, p, engine, [&] { return engine.process(m.view(), p, r); }).ok());
  EXPECT_EQ(streams[1]->temporal.history.frames, 1u);
  memory.set_shedder({});
}

// A history that does not fit once every other stream's is gone is dropped itself, counted.
TEST(MemoryBudget, AHistoryThatDoesNotFitIsDroppedAndCounted) {
  DaemonConfig c;
  c.caps.memory_budget_mb = 0;
  StreamRegistry registry(c);
  LatestResults latest(registry);
  registry.memory().set_shedder(
      [&](uint64_t need, Shed upto, const void* keep) { shed_memory(registry, latest, need, upto, keep); });
  registry.memory().set_budget(1000);  // less than one history of 642 vertices
  CpuEngine engine(2);
  const Params p = temporal_params();
  StreamPtr s = registry.admit("cam", 0);
  FrameResult r;
  const Mesh m = noisy_sphere(1);
  ASSERT_TRUE(with_history(*s, 1, p, engine, [&] { return engine.process(m.view(), p, r); }).ok());
  EXPECT_TRUE(s->temporal.history.empty());
  EXPECT_EQ(s->samples().counters.memory_resets, 1u);
  EXPECT_EQ(registry.memory().total(), 0u);
  registry.memory().set_shedder({});
}

}  // namespace
}  // namespace fq::daemon
