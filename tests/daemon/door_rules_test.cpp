// Rules every door keeps, over real sockets on 127.0.0.1: refused CURVE connections are logged at
// a bounded rate (counted each), and producer send times outside a sane window are counted
// instead of folded into the latency metrics.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>

#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/log_capture.h"
#include "tests/daemon/test_keys.h"
#include "wire/header_codec.h"

namespace fq::test {
namespace {

TEST(DoorRules, RefusedCurveConnectionsAreCountedEachAndLoggedAtABoundedRate) {
  const TestKeys k;
  LogCapture log;  // before fqd's threads log
  DaemonHarness h(k.secured(test_config()), {k.server_pub, k.client_key});
  zmq::context_t ctx(1);
  const auto t0 = std::chrono::steady_clock::now();
  constexpr int kStrangers = 200;
  std::vector<std::unique_ptr<zmq::socket_t>> strangers;
  for (int i = 0; i < kStrangers; ++i) {
    strangers.push_back(std::make_unique<zmq::socket_t>(ctx, zmq::socket_type::push));
    strangers.back()->set(zmq::sockopt::linger, 0);
    strangers.back()->set(zmq::sockopt::reconnect_ivl, -1);  // one attempt each
    ASSERT_TRUE(client::apply_curve_client(*strangers.back(), {k.server_pub, k.stranger_key}).ok());
    strangers.back()->connect(h.daemon()->endpoints().ingest);
  }
  const auto& refusals = h.daemon()->registry().refusals();
  const auto end = t0 + std::chrono::seconds(60);
  while (refusals.get(daemon::Refusal::kUnauthenticated) < kStrangers &&
         std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polling fqd's counter
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(refusals.get(daemon::Refusal::kUnauthenticated), static_cast<uint64_t>(kStrangers));
  EXPECT_LE(log.lines_with("refused a connection"), 5 * static_cast<size_t>(std::ceil(seconds) + 1))
      << "over " << seconds << " s";
  EXPECT_GE(log.lines_with("refused a connection"), 1u);
}

// One frame of `stream` whose producer says it was sent `offset` from now.
std::vector<std::string> sent_at(const std::string& stream, uint64_t sequence,
                                 std::chrono::nanoseconds offset) {
  client::FrameSpec spec;
  spec.stream_id = stream;
  std::vector<std::string> parts;
  EXPECT_TRUE(client::build_frame(noisy_sphere().view(), spec, sequence, parts).ok());
  wire::FrameHeader h;
  EXPECT_TRUE(wire::parse_frame_header(parts[1], h).ok());
  h.set_send_time_ns(h.send_time_ns() + offset.count());
  parts[1] = h.SerializeAsString();
  return parts;
}

TEST(DoorRules, SendTimesOutsideTheWindowAreCountedNotFoldedIntoTheHistograms) {
  DaemonHarness h;
  using std::chrono::hours;
  for (const auto& [sequence, offset] : {std::pair<uint64_t, std::chrono::nanoseconds>{1, hours(24)},
                                         {2, -hours(2)},
                                         {3, std::chrono::nanoseconds(0)}}) {
    h.send_parts(sent_at("clock", sequence, offset));
    EXPECT_EQ(h.receive("clock").header.status(), wire::OK);
  }
  const wire::StreamCounters c = h.counters("clock");
  EXPECT_EQ(c.bad_send_time(), 2u);
  EXPECT_EQ(c.frames_out(), 3u);
  bool found = false;
  for (const wire::StagePercentiles& s : c.stages()) {
    if (s.name() != "send_to_publish") continue;
    found = true;
    EXPECT_EQ(s.count(), 1u);
    EXPECT_GE(s.p99_ms(), 0.0);
    EXPECT_LT(s.p99_ms(), 60'000.0);
  }
  EXPECT_TRUE(found);
  std::vector<daemon::StreamSnapshot> snaps;
  ASSERT_TRUE(h.daemon()->registry().snapshot("clock", snaps));
  const auto& hist = snaps.at(0).histograms.at("send_to_publish");
  EXPECT_EQ(hist.count(), 1u);
  EXPECT_GE(hist.sum_ms(), 0.0);
}

TEST(DoorRules, AKeyRevokedByAReloadLosesItsOpenConnections) {
  const TestKeys k;
  daemon::DaemonConfig c = k.secured(test_config());
  // The harness's client and a second one, the stranger, both allowed at first.
  c.security.client_keys_file = (k.dir / "both.pub").string();
  {
    std::ofstream both(c.security.client_keys_file);
    both << std::ifstream(k.client_pub).rdbuf() << std::ifstream(k.stranger_pub).rdbuf();
  }
  DaemonHarness h(c, {k.server_pub, k.client_key});
  zmq::context_t ctx(1);
  zmq::socket_t push(ctx, zmq::socket_type::push), sub(ctx, zmq::socket_type::sub);
  for (zmq::socket_t* s : {&push, &sub}) {
    s->set(zmq::sockopt::linger, 0);
    s->set(zmq::sockopt::reconnect_ivl, -1);  // a cut connection stays cut
    ASSERT_TRUE(client::apply_curve_client(*s, {k.server_pub, k.stranger_key}).ok());
  }
  sub.set(zmq::sockopt::subscribe, "");
  sub.set(zmq::sockopt::rcvtimeo, 30000);
  push.connect(h.daemon()->endpoints().ingest);
  sub.connect(h.daemon()->endpoints().publish);
  h.sync_results();  // the stranger's subscription is in
  client::FrameSpec spec;
  spec.stream_id = "stranger";
  std::vector<std::string> parts;
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), spec, 1, parts).ok());
  client::send_parts(push, parts);
  EXPECT_EQ(h.receive("stranger").header.status(), wire::OK);
  client::ReceivedResult r;
  const StatusOr<bool> first = client::receive_result(sub, r);
  ASSERT_TRUE(first.ok() && *first);

  daemon::DaemonConfig fresh = c;
  fresh.security.client_keys_file = k.client_pub;  // the stranger's key revoked
  ASSERT_TRUE(h.daemon()->reload(fresh).ok());
  const auto& refusals = h.daemon()->registry().refusals();
  const uint64_t before = refusals.get(daemon::Refusal::kUnauthenticated);
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), spec, 2, parts).ok());
  client::send_parts(push, parts);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (refusals.get(daemon::Refusal::kUnauthenticated) < before + 2 &&
         std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polling fqd's counter
  EXPECT_GE(refusals.get(daemon::Refusal::kUnauthenticated), before + 2) << "the frame and the subscriber";
  h.send(noisy_sphere(), spec, 3);  // the harness's key is still allowed
  EXPECT_EQ(h.receive("stranger").header.sequence(), 3u);
  EXPECT_EQ(h.counters("stranger").frames_in(), 2u) << "a frame from the revoked key got in";
  // What was queued for the stranger before the cut may still come; nothing published after.
  sub.set(zmq::sockopt::rcvtimeo, 1000);
  for (StatusOr<bool> got = client::receive_result(sub, r); got.ok() && *got;
       got = client::receive_result(sub, r))
    EXPECT_FALSE(r.topic == "stranger" && r.header.sequence() == 3)
        << "the revoked subscriber still gets results";
}

}  // namespace
}  // namespace fq::test
