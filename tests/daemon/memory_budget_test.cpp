// The host memory budget in a running fqd (caps.memory_budget_mb, daemon/stream/memory_account.h):
// many streams filtered across frames on a real mesh (fandisk, 6,475 vertices) under a budget
// too small for all their histories stay within it, the histories of the streams fed longest
// ago go first and are counted, and frames that do not fit at all are dropped and counted.
// Real sockets on 127.0.0.1, the CPU engine.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "eval/noise.h"
#include "io/ply_reader.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/http_metrics.h"

namespace fq::test {
namespace {

Mesh fandisk(uint64_t seed) {
  Mesh m;
  EXPECT_TRUE(io::read_ply(std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply", m).ok());
  add_gaussian_noise(m, 0.1, seed);
  return m;
}

daemon::DaemonConfig temporal_config(uint64_t budget_mb, uint32_t streams) {
  daemon::DaemonConfig c = test_config();
  c.defaults.params.cluster = false;
  c.defaults.params.filtering.temporal = 0.75f;
  c.caps.max_streams = streams + 8;  // and the harness's probe stream
  c.caps.memory_budget_mb = budget_mb;
  return c;
}

std::string stream_name(int i) { return "m" + std::to_string(i); }

double gauge(DaemonHarness& h, const std::string& series) {
  return metric_value(h.daemon()->service_metrics(), series);
}

// Every frame a stream was sent ended as a result or a counted drop.
void expect_accounted(DaemonHarness& h, const std::string& stream) {
  const wire::StreamCounters c = h.counters(stream);
  EXPECT_EQ(c.frames_in(), c.frames_out() + c.errors() + c.superseded() + c.dropped_stale() + c.preempted() +
                               c.refused() + c.dropped_memory())
      << stream;
}

// 8 streams fed one after another, each frame's result read before the next is sent, under a
// budget of 1 MiB: a fandisk history after one frame is about 0.23 MB (36 bytes a vertex:
// positions, normals and the last averaged input) and a frame in flight about 0.4 MB, so only a
// few histories fit. The streams that
// lost theirs are the ones fed first, each counted memory_resets once; the last fed keep theirs, and their
// next frame follows it (track A) while a stream that lost its history runs alone.
TEST(MemoryBudget, ManyTemporalStreamsStayWithinTheBudgetAndTheLeastRecentlyFedLoseTheirHistories) {
  constexpr int kStreams = 8;
  DaemonHarness h(temporal_config(1, kStreams));
  const Mesh mesh = fandisk(1);
  for (int i = 0; i < kStreams; ++i) {
    h.send(mesh, frame_spec(stream_name(i)), 0);
    const client::ReceivedResult r = h.receive(stream_name(i));
    ASSERT_EQ(r.header.status(), wire::OK) << r.header.error();
  }
  const double budget = gauge(h, "fq_memory_budget_bytes");
  EXPECT_EQ(budget, 1.0 * (1 << 20));
  EXPECT_LE(gauge(h, "fq_memory_peak_bytes"), budget);
  EXPECT_GT(gauge(h, "fq_memory_bytes{kind=\"history\"}"), 0);
  std::vector<uint64_t> resets;
  resets.reserve(kStreams);
  for (int i = 0; i < kStreams; ++i) resets.push_back(h.counters(stream_name(i)).memory_resets());
  // A prefix of the streams, in the order they were fed, lost their histories; the rest kept them.
  int lost = 0;
  while (lost < kStreams && resets[static_cast<size_t>(lost)] == 1) ++lost;
  EXPECT_GE(lost, 1);
  EXPECT_LE(lost, kStreams - 2);
  for (int i = lost; i < kStreams; ++i) EXPECT_EQ(resets[static_cast<size_t>(i)], 0u) << stream_name(i);
  std::printf("fandisk history on the budget: %d of %d streams kept theirs within %.0f bytes, peak %.0f\n",
              kStreams - lost, kStreams, budget, gauge(h, "fq_memory_peak_bytes"));

  // The last stream fed follows its history; the first one, whose history went, runs alone.
  const Mesh next = fandisk(2);
  h.send(next, frame_spec(stream_name(kStreams - 1)), 1);
  EXPECT_EQ(h.receive(stream_name(kStreams - 1)).header.temporal_track(), wire::TEMPORAL_IDS);
  h.send(next, frame_spec(stream_name(0)), 1);
  EXPECT_NE(h.receive(stream_name(0)).header.temporal_track(), wire::TEMPORAL_IDS);
  EXPECT_LE(gauge(h, "fq_memory_peak_bytes"), budget);
  for (int i = 0; i < kStreams; ++i) expect_accounted(h, stream_name(i));
}

// The done-when, scaled: "64 streams of 1M-vertex frames with temporal filtering stay under the
// configured memory budget". Everything charged is per vertex (a history about 130 bytes a
// vertex once track A runs; a frame in flight its chunks and 52 bytes a vertex), so 64 streams
// of 1M vertices, each with a history and a frame in flight, want about 64 x 183 MB = 11.7 GB
// against the default 4096 MiB. Here the frames are fandisk's 6,475 vertices, 6.475e-3 of 1M,
// and the budget is scaled by the same factor (4096 MiB x 6.475e-3 = 26.5 MiB, rounded down to
// 26 MiB): the same demand against the same budget, 1,000 times smaller. Two frames a stream,
// sent a round at a time (64 frames in flight at once): the charged total never passes the
// budget, some histories are shed (counted), and every frame ends as a result or a counted drop.
TEST(MemoryBudget, SixtyFourTemporalStreamsStayUnderTheScaledBudget) {
  constexpr int kStreams = 64;
  DaemonHarness h(temporal_config(26, kStreams));
  const size_t rss_before = rss_bytes();
  for (uint64_t round = 0; round < 2; ++round) {
    const Mesh mesh = fandisk(round + 1);
    for (int i = 0; i < kStreams; ++i) h.send(mesh, frame_spec(stream_name(i)), round);
    for (int i = 0; i < kStreams; ++i) {
      const client::ReceivedResult r = h.receive(stream_name(i));
      EXPECT_EQ(r.header.status(), wire::OK) << r.header.error();
    }
  }
  const double budget = gauge(h, "fq_memory_budget_bytes");
  const double peak = gauge(h, "fq_memory_peak_bytes");
  EXPECT_EQ(budget, 26.0 * (1 << 20));
  EXPECT_LE(peak, budget);
  uint64_t resets = 0, dropped = 0;
  for (int i = 0; i < kStreams; ++i) {
    const wire::StreamCounters c = h.counters(stream_name(i));
    resets += c.memory_resets();
    dropped += c.dropped_memory();
    expect_accounted(h, stream_name(i));
  }
  EXPECT_GT(resets, 0u);
  std::printf(
      "64 fandisk streams: peak %.0f of %.0f bytes charged, %llu histories shed, %llu frames dropped; "
      "histories now %.0f bytes; RSS %zu -> %zu bytes\n",
      peak, budget, static_cast<unsigned long long>(resets), static_cast<unsigned long long>(dropped),
      gauge(h, "fq_memory_bytes{kind=\"history\"}"), rss_before, rss_bytes());
}

// Frames larger than the whole budget (a 40,962-vertex sphere, about 2.1 MB once decoded,
// against 1 MiB) cannot be let in whatever is shed: each is dropped at admission, counted
// dropped_memory, and a frame that fits still gets its result.
TEST(MemoryBudget, AFrameThatCannotFitIsDroppedAndCounted) {
  DaemonHarness h(temporal_config(1, 2));
  const Mesh big = noisy_sphere(3, 6);
  for (uint64_t i = 0; i < 3; ++i) h.send(big, frame_spec("big"), i);
  h.send(noisy_sphere(4), frame_spec("small"), 0);
  EXPECT_EQ(h.receive("small").header.status(), wire::OK);
  h.sync_results();
  const wire::StreamCounters c = h.counters("big");
  EXPECT_EQ(c.frames_in(), 3u);
  EXPECT_EQ(c.dropped_memory(), 3u);
  EXPECT_EQ(c.frames_out(), 0u);
  expect_accounted(h, "big");
  expect_accounted(h, "small");
  EXPECT_NE(h.daemon()->service_metrics().find("fq_memory_bytes{kind=\"queued\"}"), std::string::npos);
}

// Cluster id tracks are charged too (120 bytes a vertex): under 2 MiB, two fandisk tracks
// (0.78 MB each) and a frame in flight (0.4 MB) fit, three do not: the third stream's frame
// takes the room of the track of the stream fed first, counted there, not of the one fed since.
TEST(MemoryBudget, ClusterIdTracksAreChargedAndShedOldestFirst) {
  daemon::DaemonConfig c = temporal_config(2, 3);
  c.defaults.params.filtering.temporal = 0.f;
  c.defaults.params.cluster = true;
  c.defaults.params.clustering.track_ids = true;
  DaemonHarness h(c);
  const Mesh mesh = fandisk(1);
  for (const char* stream : {"c", "d", "e"}) {
    h.send(mesh, frame_spec(stream), 0);
    ASSERT_EQ(h.receive(stream).header.status(), wire::OK);
  }
  EXPECT_EQ(gauge(h, "fq_memory_bytes{kind=\"label_track\"}"), 2 * 120.0 * mesh.num_vertices());
  EXPECT_LE(gauge(h, "fq_memory_peak_bytes"), gauge(h, "fq_memory_budget_bytes"));
  EXPECT_EQ(h.counters("c").memory_resets(), 1u);
  EXPECT_EQ(h.counters("d").memory_resets(), 0u);
  EXPECT_EQ(h.counters("e").memory_resets(), 0u);
}

}  // namespace
}  // namespace fq::test
