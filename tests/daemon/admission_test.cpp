// fqd under hostile and heavy input, over real sockets: junk topics leave no state,
// squatters expire, bad stream ids get a readable refusal, oversized parts are refused at
// the socket, oversized neighbourhoods before the engine, and overloaded streams share the
// engine fairly.
#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "eval/noise.h"
#include "io/ply_reader.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/support/test_meshes.h"

namespace fq::test {
namespace {

using Clock = std::chrono::steady_clock;

// Waits (bounded) until `done()` holds.
template <class F>
bool eventually(F&& done, std::chrono::seconds limit = std::chrono::seconds(60)) {
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return done();
}

TEST(DaemonAdmission, TwentyThousandJunkTopicsLeaveNoStateAndFlatMemory) {
  DaemonHarness h;
  daemon::StreamRegistry& r = h.daemon()->registry();
  auto junk = [&](int from, int to) {
    for (int i = from; i < to; ++i) h.send_parts({"junk-topic-" + std::to_string(i)});
  };
  // Every refusal is answered with an error result, which queues in this process until
  // read: sync_results() reads them all, and freed memory goes back before each reading, so
  // the RSS compares what stays allocated.
  auto settled_rss = [&] {
    h.sync_results();
    malloc_trim(0);
    return rss_bytes();
  };
  junk(0, 1000);  // warm-up: queues, log, allocator arenas
  const size_t before = settled_rss();
  EXPECT_EQ(r.refusals().get(daemon::Refusal::kMalformed), 1000u);
  junk(1000, 21000);
  const size_t after = settled_rss();
  EXPECT_EQ(r.refusals().get(daemon::Refusal::kMalformed), 21000u);
  // The harness's own "__probe" stream is the only one.
  EXPECT_EQ(r.list(), std::vector<std::string>{"__probe"}) << r.list().size() << " streams";
  // Before, every topic kept its own state: +202 MiB for 20,000 topics.
  EXPECT_LT(after, before + (16u << 20)) << "RSS grew from " << before << " to " << after;
  h.send(noisy_sphere(), frame_spec("cam"), 1);
  EXPECT_EQ(h.receive("cam").header.status(), wire::OK);
}

// Stream ids that come and go, as a capture farm's cameras do: each stream's state lives in
// its Stream object, so expiry frees all of it. Before, the slots, the publish order, the
// newest-queued arrivals and the label tracks (the previous frame's positions and ids) each
// kept an entry for every id ever seen.
TEST(DaemonAdmission, FiveThousandStreamIdsComeAndGoWithFlatMemory) {
  constexpr int kWave = 50;  // ids at a time; each sends one frame and goes idle
  daemon::DaemonConfig c = test_config();
  c.caps.stream_idle_s = 0.5;
  c.caps.max_streams = 8192;                  // never the limit, however fast ids come on this machine
  c.caps.max_subscriber_results = 2 * kWave;  // a wave's results all wait for the test's reads
  c.defaults.params.cluster = true;           // with track_ids: a stream keeps its previous frame's ids
  DaemonHarness h(c);
  daemon::StreamRegistry& r = h.daemon()->registry();
  const Mesh mesh = noisy_sphere(7, 2);  // 162 vertices
  size_t most_streams = 0;
  auto churn = [&](int from, int to) {
    for (int i = from; i < to; i += kWave) {
      const int end = std::min(to, i + kWave);
      for (int k = i; k < end; ++k) h.send(mesh, frame_spec("churn-" + std::to_string(k)), 0);
      for (int k = i; k < end; ++k)
        ASSERT_EQ(h.receive("churn-" + std::to_string(k)).header.status(), wire::OK);
      most_streams = std::max(most_streams, r.list().size());
    }
  };
  auto settled_rss = [&] {
    EXPECT_TRUE(eventually([&] { return r.list().size() <= 1; }, std::chrono::seconds(30)))
        << r.list().size() << " streams left";  // the harness's probe stream may be there
    h.sync_results();
    malloc_trim(0);
    return rss_bytes();
  };
  churn(0, 1000);  // warm-up: queues, pools, allocator arenas
  const size_t before = settled_rss();
  churn(1000, 5000);
  const size_t after = settled_rss();
  EXPECT_EQ(r.refusals().get(daemon::Refusal::kTooManyStreams), 0u);
  EXPECT_LT(after, before + (16u << 20)) << "RSS grew from " << before << " to " << after;
  std::printf("RSS %zu -> %zu MiB over 4,000 stream ids, at most %zu streams at once\n", before >> 20,
              after >> 20, most_streams);
}

TEST(DaemonAdmission, SquattedSlotsComeBackWhenTheSquattersGoIdle) {
  daemon::DaemonConfig c = test_config();
  c.caps.max_streams = 3;  // the harness's probe stream and two squatters
  c.caps.stream_idle_s = 1.0;
  c.defaults.params.cluster = false;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere();
  for (const char* squatter : {"squat0", "squat1"}) {
    h.send(mesh, frame_spec(squatter), 0);
    EXPECT_EQ(h.receive(squatter).header.status(), wire::OK);
  }
  h.send(mesh, frame_spec("cam"), 41);
  const client::ReceivedResult refused = h.receive("cam");
  EXPECT_EQ(refused.header.status(), wire::ERROR);
  EXPECT_NE(refused.header.error().find("too many streams"), std::string::npos) << refused.header.error();
  EXPECT_EQ(refused.header.sequence(), 41u) << "refusals carry the frame's sequence number";
  EXPECT_EQ(h.daemon()->registry().refusals().get(daemon::Refusal::kTooManyStreams), 1u);
  // The squatters send nothing more: after the idle time their slots are free again.
  ASSERT_TRUE(eventually([&] { return h.daemon()->registry().list().empty(); }, std::chrono::seconds(20)))
      << "streams left: " << h.daemon()->registry().list().size();
  h.send(mesh, frame_spec("cam"), 42);
  const client::ReceivedResult served = h.receive("cam");
  EXPECT_EQ(served.header.status(), wire::OK);
  EXPECT_EQ(served.header.sequence(), 42u);
}

TEST(DaemonAdmission, ANonUtf8StreamIdGetsAReadableRefusal) {
  DaemonHarness h;
  const Mesh mesh = noisy_sphere();
  std::vector<std::string> parts;
  ASSERT_TRUE(client::build_frame(mesh.view(), frame_spec("cam"), 5, parts).ok());
  parts[0] =
      "\xff\xfe"
      "cam";
  h.send_parts(parts);
  // Published under the escaped id, in a result header any protobuf reader accepts.
  const client::ReceivedResult e = h.receive("\\xff\\xfecam");
  EXPECT_EQ(e.header.status(), wire::ERROR);
  EXPECT_NE(e.header.error().find("not valid UTF-8"), std::string::npos) << e.header.error();
  EXPECT_EQ(h.daemon()->registry().refusals().get(daemon::Refusal::kBadStreamId), 1u);
  h.send(mesh, frame_spec("cam"), 6);
  EXPECT_EQ(h.receive("cam").header.status(), wire::OK);
}

TEST(DaemonAdmission, APartOverTheCapIsRefusedAtTheSocket) {
  daemon::DaemonConfig c = test_config();
  c.caps.max_frame_bytes = 1u << 20;
  DaemonHarness h(c);
  {
    // Another producer sends a 64 MiB part: fqd drops the connection before buffering it.
    zmq::context_t ctx(1);
    zmq::socket_t push(ctx, zmq::socket_type::push);
    push.set(zmq::sockopt::linger, 2000);
    push.connect(h.daemon()->endpoints().ingest);
    std::vector<std::string> parts{"cam", "header", std::string(64u << 20, 'x')};
    client::send_parts(push, parts);
  }
  h.send(noisy_sphere(), frame_spec("cam"), 1);
  const client::ReceivedResult r = h.receive("cam");
  EXPECT_EQ(r.header.status(), wire::OK);
  EXPECT_EQ(r.header.sequence(), 1u);
  EXPECT_EQ(h.counters("cam").frames_in(), 1u) << "the oversized message never reached the daemon";
}

// With clustering, the plan runs the sigma_s neighbourhoods ("qf+" alone does not read sigma_s).
TEST(DaemonAdmission, AHugeNeighbourhoodIsRefusedBeforeTheEngine) {
  DaemonHarness h;
  client::FrameSpec s = frame_spec("cam");
  s.compute = wire::FILTER_AND_CLUSTER;
  s.overrides.set_sigma_s(1e4f);
  h.send(noisy_sphere(), s, 1);
  const client::ReceivedResult e = h.receive("cam");
  EXPECT_EQ(e.header.status(), wire::ERROR);
  EXPECT_NE(e.header.error().find("max_neighbour_work"), std::string::npos) << e.header.error();
  h.send(noisy_sphere(), frame_spec("cam"), 2);
  EXPECT_EQ(h.receive("cam").header.status(), wire::OK);
}

TEST(DaemonAdmission, IdenticalStreamsShareAnOverloadedEngineFairly) {
  daemon::DaemonConfig c = test_config();
  c.engine.cpu_threads = 1;
  c.defaults.params.cluster = true;
  DaemonHarness h(c);
  const Mesh mesh = noisy_sphere(7, 4);  // 2562 vertices: tens of ms of engine time per frame
  const std::vector<std::string> streams{"a", "b", "c"};
  std::vector<std::vector<std::string>> frames;
  for (const std::string& id : streams) {
    frames.emplace_back();
    ASSERT_TRUE(client::build_frame(mesh.view(), frame_spec(id), 0, frames.back()).ok());
  }
  // Far faster than one engine thread can serve, until it has served enough to judge
  // (counted, not timed: the machine may be busy). A stream the ingest has not admitted yet (a
  // loaded machine) has served nothing; asking fqd for its counters then would fail the test.
  auto served = [&] {
    uint64_t n = 0;
    for (const std::string& id : streams)
      if (h.daemon()->registry().find(id)) n += h.counters(id).frames_out();
    return n;
  };
  constexpr uint64_t kEnough = 240;
  const auto end = Clock::now() + std::chrono::seconds(120);
  for (int round = 0; Clock::now() < end; ++round) {
    for (auto& parts : frames) h.send_parts(parts);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (round % 20 == 0 && served() >= kEnough) break;
  }
  std::vector<uint64_t> out;
  for (const std::string& id : streams) {
    ASSERT_TRUE(eventually([&] {
      const wire::StreamCounters k = h.counters(id);
      return k.frames_in() ==
             k.frames_out() + k.errors() + k.superseded() + k.dropped_stale() + k.preempted();
    }));
    out.push_back(h.counters(id).frames_out());
  }
  const auto [lo, hi] = std::minmax_element(out.begin(), out.end());
  const double n = double(out[0] + out[1] + out[2]);
  ASSERT_GE(n, double(kEnough) * 0.9)
      << "the engine served too few frames to judge: " << out[0] << " / " << out[1] << " / " << out[2];
  // The engine shares its time, not its frames: on a loaded machine a frame's time varies, and
  // so do the counts. Allowed: the spread of a fair draw, three standard deviations of the
  // difference of two streams' counts had each frame gone to one of the three at random
  // (sqrt(2n/3): 38 frames of 240). The old oldest-first rule gave 25 / 13 / 5 of 43 (16
  // allowed), 4,105 vs 1,523 before that.
  const double allowed = 3.0 * std::sqrt(2.0 * n / 3.0);
  EXPECT_LE(double(*hi - *lo), allowed) << out[0] << " / " << out[1] << " / " << out[2];
  std::printf("served %llu / %llu / %llu (difference %llu, %.0f allowed)\n",
              static_cast<unsigned long long>(out[0]), static_cast<unsigned long long>(out[1]),
              static_cast<unsigned long long>(out[2]), static_cast<unsigned long long>(*hi - *lo), allowed);
}

TEST(DaemonAdmission, AStreamOfHeavyFramesOverItsBudgetYieldsToALightOneAndStillProgresses) {
  // One engine thread. The hog's frames (the fandisk with a neighbourhood as wide as the mesh:
  // seconds each, inside the work budget and the time limit, over the 1 s budget) always have
  // one waiting; the victim sends a small frame every 200 ms, also with a 1 s budget. Round
  // robin by frames gave the victim one result per hog frame (6 of 100). A hog frame that
  // cannot meet its budget is stopped when a victim frame would miss its own behind it, but
  // after a stop the hog's next frame runs to its end (guaranteed progress), and the victim
  // waits for it.
  daemon::DaemonConfig c = test_config();
  c.engine.cpu_threads = 1;
  c.defaults.budget_ms = 1000;
  c.caps.engine_time_limit_s = 120;  // a loaded machine may take over 10 s for a hog frame
  DaemonHarness h(c);
  Mesh fandisk;
  ASSERT_TRUE(io::read_ply(std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply", fandisk).ok());
  client::FrameSpec hog = frame_spec("hog");
  hog.overrides.set_sigma_s(40.f);
  hog.overrides.set_sigma_d(40.f);
  std::vector<std::string> hog_frame, victim_frame;
  ASSERT_TRUE(client::build_frame(fandisk.view(), hog, 0, hog_frame).ok());
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), frame_spec("victim"), 0, victim_frame).ok());
  const int victim_frames = 100;  // 20 s
  for (int i = 0; i < victim_frames; ++i) {
    if (i % 2 == 0) h.send_parts(hog_frame);
    h.send_parts(victim_frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  for (const char* id : {"hog", "victim"}) {
    ASSERT_TRUE(eventually([&] {
      const wire::StreamCounters k = h.counters(id);
      return k.frames_in() ==
             k.frames_out() + k.errors() + k.superseded() + k.dropped_stale() + k.preempted();
    }));
  }
  const wire::StreamCounters v = h.counters("victim"), g = h.counters("hog");
  std::printf(
      "victim: %llu of %d results (%llu superseded, %llu stale); hog: %llu results, %llu preempted, %llu "
      "superseded, %llu errors\n",
      static_cast<unsigned long long>(v.frames_out()), victim_frames,
      static_cast<unsigned long long>(v.superseded()), static_cast<unsigned long long>(v.dropped_stale()),
      static_cast<unsigned long long>(g.frames_out()), static_cast<unsigned long long>(g.preempted()),
      static_cast<unsigned long long>(g.superseded()), static_cast<unsigned long long>(g.errors()));
  EXPECT_GT(g.preempted(), 0u);
  EXPECT_EQ(v.preempted(), 0u);
  // Progress: after each stop the hog's next frame ran to its end (the last stop may be the
  // run's last frame), and a stop is not an error.
  EXPECT_GE(g.frames_out() + 1, g.preempted());
  EXPECT_EQ(g.errors(), 0u);
  // The victim is served whenever no hog frame runs to its end: after each such frame, and
  // when the next one is stopped for it.
  EXPECT_GE(v.frames_out(), g.frames_out());
}

}  // namespace
}  // namespace fq::test

namespace fq::test {
namespace {

TEST(DaemonAdmission, MemoryReturnsWhenSmallFramesFollowAHugeOne) {
  daemon::DaemonConfig c = test_config();
  c.defaults.params.cluster = false;
  DaemonHarness h(c);
  const Mesh small = noisy_sphere();
  for (uint64_t i = 0; i < 3; ++i) {
    h.send(small, frame_spec("cam"), i);
    ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  }
  const size_t base = rss_bytes();
  Mesh huge = make_icosphere(7, 1.0f);  // 163,842 vertices
  add_gaussian_noise(huge, 0.2, 3);
  client::FrameSpec s = frame_spec("cam");
  s.chunks = 4;
  h.send(huge, s, 10);
  ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  const size_t peak = rss_bytes();
  ASSERT_GT(peak, base + (40u << 20)) << "the huge frame should have cost memory: " << base << " -> " << peak;
  for (uint64_t i = 11; i < 14; ++i) {
    h.send(small, frame_spec("cam"), i);
    ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  }
  // Buffers are freed at once; free pages go back to the system within a few seconds. What
  // stays is allocator bookkeeping and the test's own copy of the huge mesh (measured on
  // the 2-core development machine: 16 -> 122 -> 59 MB; 74 MB without the trim, 122 MB with
  // grow-only scratch and pools).
  size_t after = 0;
  EXPECT_TRUE(
      eventually([&] { return (after = rss_bytes()) < base + (peak - base) / 2; }, std::chrono::seconds(15)))
      << "RSS " << base << " -> " << peak << " -> " << after;
}

// Without frames for caps.pool_idle_s, the engine's buffers go back as the pools' do: here
// no small frame follows the huge one.
TEST(DaemonAdmission, EngineBuffersReturnWhenIdle) {
  daemon::DaemonConfig c = test_config();
  c.defaults.params.cluster = false;
  c.caps.pool_idle_s = 1.0;
  DaemonHarness h(c);
  h.send(noisy_sphere(), frame_spec("cam"), 0);
  ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  const size_t base = rss_bytes();
  Mesh huge = make_icosphere(7, 1.0f);  // 163,842 vertices
  add_gaussian_noise(huge, 0.2, 3);
  h.send(huge, frame_spec("cam"), 1);
  ASSERT_EQ(h.receive("cam").header.status(), wire::OK);
  const size_t peak = rss_bytes();
  ASSERT_GT(peak, base + (40u << 20)) << "the huge frame should have cost memory: " << base << " -> " << peak;
  size_t after = 0;
  EXPECT_TRUE(
      eventually([&] { return (after = rss_bytes()) < base + (peak - base) / 3; }, std::chrono::seconds(20)))
      << "RSS " << base << " -> " << peak << " -> " << after;
  std::printf("RSS %zu -> %zu -> %zu MiB\n", base >> 20, peak >> 20, after >> 20);
}

}  // namespace
}  // namespace fq::test
