// Attacks on how fqd shares its decoders and engines between streams, over real sockets on
// 127.0.0.1 with real Draco frames: each test counts the victim stream's results with the
// attack running beside it. The attacks first measured (the 2-core development machine):
//  - a stream of tiny frames preempted every frame of a heavy stream while the engine was
//    mostly idle, because the tiny stream had used no engine time (0 of 18; 18 of 18 alone);
//  - heavy frames on many stream ids over several connections kept a 5 fps stream's frame
//    at the back of the decode queue (0 of 75 results);
//  - set_params with create on 8 ids every 0.5 s held every slot (max_streams 8): a new
//    producer got 0 of 75 frames in ("too many streams").
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "clients/common/frame_sender.h"
#include "tests/daemon/daemon_harness.h"
#include "tests/support/test_meshes.h"
#include "wire/header_codec.h"

namespace fq::test {
namespace {

using Clock = std::chrono::steady_clock;

// Waits (bounded) until every frame of `stream` has an outcome; its counters then.
wire::StreamCounters settled(DaemonHarness& h, const std::string& stream) {
  wire::StreamCounters k;
  for (int i = 0; i < 3000; ++i) {
    k = h.counters(stream);
    if (k.frames_in() == k.frames_out() + k.errors() + k.superseded() + k.dropped_stale() + k.preempted())
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polling fqd's counters
  }
  return k;
}

void print(const char* what, const wire::StreamCounters& k) {
  double engine_ms = 0;
  for (const wire::StagePercentiles& p : k.stages())
    if (p.name() == "engine") engine_ms = p.p50_ms();
  std::printf(
      "%s: in %llu, out %llu, errors %llu, superseded %llu, stale %llu, preempted %llu, late %llu; engine "
      "p50 %.0f ms\n",
      what, static_cast<unsigned long long>(k.frames_in()), static_cast<unsigned long long>(k.frames_out()),
      static_cast<unsigned long long>(k.errors()), static_cast<unsigned long long>(k.superseded()),
      static_cast<unsigned long long>(k.dropped_stale()), static_cast<unsigned long long>(k.preempted()),
      static_cast<unsigned long long>(k.late()), engine_ms);
}

TEST(FairShare, TinyFramesDoNotPreemptAHeavyStreamWhileTheEngineHasRoom) {
  // One engine thread. The victim: frames of 10,242 vertices (filter and clustering: 0.8 s on
  // the 2-core development machine with a dozen compilers beside it), one every 2 s, with a
  // budget of 200 ms that they miss; the attacker: a 162-vertex frame at 5 fps under fqd's
  // default budget (100 ms). The engine has room for both streams, so none of the victim's
  // frames may be stopped for the attacker, whose usage is near zero (the old rule stopped
  // every one of them).
  daemon::DaemonConfig c = test_config();
  c.engine.cpu_threads = 1;
  c.defaults.budget_ms = 100;
  c.streams["victim"] = c.defaults;
  c.streams["victim"].budget_ms = 200;
  DaemonHarness h(c);
  std::vector<std::string> victim, tiny;
  ASSERT_TRUE(client::build_frame(noisy_sphere(7, 5).view(), frame_spec("victim"), 0, victim).ok());
  ASSERT_TRUE(client::build_frame(make_icosphere(2, 1.0f).view(), frame_spec("tiny"), 0, tiny).ok());
  constexpr int kVictimFrames = 18;
  const auto start = Clock::now();
  for (int tick = 0; tick < kVictimFrames * 10; ++tick) {  // a tick every 200 ms
    if (tick % 10 == 0) h.send_parts(victim);              // one every 2 s
    h.send_parts(tiny);
    std::this_thread::sleep_until(start + std::chrono::milliseconds(200) * (tick + 1));  // the attack's rate
  }
  const wire::StreamCounters v = settled(h, "victim"), t = settled(h, "tiny");
  print("victim", v);
  print("tiny", t);
  ASSERT_EQ(v.frames_in(), uint64_t{kVictimFrames});
  EXPECT_EQ(v.preempted(), 0u);
  EXPECT_GE(v.frames_out(), uint64_t{kVictimFrames - 1});
  EXPECT_EQ(t.preempted(), 0u);
}

TEST(FairShare, HeavyFramesOnManyIdsAndConnectionsLeaveALightStreamItsTurn) {
  // Four connections send heavy frames (40,962-vertex spheres, refused after the decode so
  // that only the decoders are loaded) as fast as fqd reads them, on 24 stream ids; the victim
  // sends a light frame every 200 ms with a budget of 1 s, 75 frames in all.
  daemon::DaemonConfig c = test_config();
  c.streams["victim"] = c.defaults;
  c.streams["victim"].budget_ms = 1000;
  DaemonHarness h(c);
  client::FrameSpec heavy_spec = frame_spec("heavy");
  heavy_spec.overrides.set_theta(2.0f);  // invalid: refused after the decode, before the engine
  std::vector<std::string> heavy, victim;
  ASSERT_TRUE(client::build_frame(make_icosphere(6, 1.0f).view(), heavy_spec, 1, heavy).ok());
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), frame_spec("victim"), 0, victim).ok());
  constexpr int kConnections = 4, kIdsPerConnection = 6, kVictimFrames = 75;
  std::atomic<bool> attacking{true};
  std::atomic<uint64_t> sent{0};
  std::vector<std::thread> attackers;
  attackers.reserve(kConnections);
  const std::string ingest = h.daemon()->endpoints().ingest;
  for (int a = 0; a < kConnections; ++a) {
    attackers.emplace_back([&, a] {
      zmq::context_t ctx(1);
      zmq::socket_t push(ctx, zmq::socket_type::push);
      push.set(zmq::sockopt::linger, 0);
      push.set(zmq::sockopt::sndhwm, 2);
      push.set(zmq::sockopt::sndtimeo, 100);
      push.connect(ingest);
      std::vector<std::vector<std::string>> frames;
      frames.reserve(kIdsPerConnection);
      for (int i = 0; i < kIdsPerConnection; ++i)
        frames.push_back(renamed_frame(heavy, "heavy" + std::to_string(a * kIdsPerConnection + i)));
      for (size_t i = 0; attacking; ++i) {
        std::vector<zmq::const_buffer> parts;
        for (const std::string& p : frames[i % frames.size()]) parts.push_back(zmq::buffer(p));
        if (zmq::send_multipart(push, parts)) ++sent;
      }
    });
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the attack under way first
  const auto start = Clock::now();
  for (int i = 0; i < kVictimFrames; ++i) {
    h.send_parts(victim);
    std::this_thread::sleep_until(start + std::chrono::milliseconds(200) * (i + 1));  // 5 fps
  }
  attacking = false;
  for (std::thread& t : attackers) t.join();
  const wire::StreamCounters v = settled(h, "victim");
  print("victim", v);
  std::printf("attack: %llu heavy frames sent\n", static_cast<unsigned long long>(sent.load()));
  ASSERT_EQ(v.frames_in(), uint64_t{kVictimFrames});
  EXPECT_GE(v.frames_out(), 68u);
}

TEST(FairShare, SlotsMadeBySetParamsAloneGiveWayToAProducer) {
  daemon::DaemonConfig c = test_config();
  c.caps.max_streams = 8;  // the harness's probe stream holds one
  DaemonHarness h(c);
  std::atomic<bool> squatting{true};
  std::atomic<uint64_t> made{0};
  // The squatter's own control socket: the harness's is for this thread.
  std::thread squatter([&] {
    zmq::context_t ctx(1);
    zmq::socket_t req(ctx, zmq::socket_type::req);
    req.set(zmq::sockopt::linger, 0);
    req.set(zmq::sockopt::rcvtimeo, 5000);
    req.connect(h.daemon()->endpoints().control);
    while (squatting) {
      for (int i = 0; i < 8 && squatting; ++i) {
        wire::ControlRequest q;
        q.set_version(wire::kWireVersion);
        q.mutable_set_params()->set_stream_id("squat" + std::to_string(i));
        q.mutable_set_params()->set_create(true);
        q.mutable_set_params()->mutable_params()->set_sigma_r(0.5f);
        const std::string bytes = q.SerializeAsString();
        req.send(zmq::buffer(bytes));
        zmq::message_t reply;
        if (!req.recv(reply)) return;
        wire::ControlReply r;
        if (r.ParseFromArray(reply.data(), static_cast<int>(reply.size())) && r.ok()) ++made;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the attack's period
    }
  });
  while (made < 7) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // every slot held
  std::vector<std::string> frame;
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), frame_spec("cam"), 0, frame).ok());
  constexpr int kFrames = 75;
  const auto start = Clock::now();
  for (int i = 0; i < kFrames; ++i) {
    h.send_parts(frame);
    std::this_thread::sleep_until(start + std::chrono::milliseconds(200) * (i + 1));  // 5 fps
  }
  squatting = false;
  squatter.join();
  const wire::StreamCounters k = settled(h, "cam");
  print("cam", k);
  std::printf("set_params accepted: %llu; refused too_many_streams: %llu\n",
              static_cast<unsigned long long>(made.load()),
              static_cast<unsigned long long>(
                  h.daemon()->registry().refusals().get(daemon::Refusal::kTooManyStreams)));
  EXPECT_GE(k.frames_out(), 68u);
}

}  // namespace
}  // namespace fq::test
