// fqd with CURVE on: an allow-listed client gets frames through, results and control
// replies; a client without keys and one with an unknown key get nothing, and the
// unknown key is counted.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <zmq_addon.hpp>

#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/test_keys.h"

namespace fq::test {
namespace {

TEST(DaemonCurve, AnAllowListedClientRoundTripsFramesAndControl) {
  const TestKeys k;
  DaemonHarness h(k.secured(test_config()), {k.server_pub, k.client_key});  // waits for a probe result
  client::FrameSpec spec;
  spec.stream_id = "cam";
  h.send(noisy_sphere(), spec, 3);
  const client::ReceivedResult r = h.receive_decoded("cam");
  EXPECT_EQ(r.header.status(), wire::OK);
  EXPECT_EQ(h.counters("cam").frames_out(), 1u);
}

TEST(DaemonCurve, ClientsWithoutAnAllowedKeyGetNothing) {
  const TestKeys k;
  DaemonHarness h(k.secured(test_config()), {k.server_pub, k.client_key});
  zmq::context_t ctx(1);
  // One producer without keys, one with a key fqd does not know.
  zmq::socket_t plain(ctx, zmq::socket_type::push), stranger(ctx, zmq::socket_type::push);
  for (zmq::socket_t* s : {&plain, &stranger}) s->set(zmq::sockopt::linger, 0);
  ASSERT_TRUE(client::apply_curve_client(stranger, {k.server_pub, k.stranger_key}).ok());
  plain.connect(h.daemon()->endpoints().ingest);
  stranger.connect(h.daemon()->endpoints().ingest);
  std::vector<std::string> parts;
  client::FrameSpec spec;
  spec.stream_id = "intruder";
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), spec, 0, parts).ok());
  for (int i = 0; i < 3; ++i) {
    for (zmq::socket_t* s : {&plain, &stranger}) {
      std::vector<zmq::const_buffer> b;
      for (const std::string& p : parts) b.push_back(zmq::buffer(p));
      (void)zmq::send_multipart(*s, b, zmq::send_flags::dontwait);
    }
  }
  // A subscriber without keys gets no result either.
  zmq::socket_t sub(ctx, zmq::socket_type::sub);
  sub.set(zmq::sockopt::linger, 0);
  sub.set(zmq::sockopt::subscribe, "");
  sub.set(zmq::sockopt::rcvtimeo, 1500);
  sub.connect(h.daemon()->endpoints().publish);
  // The allowed client's frame goes through meanwhile.
  spec.stream_id = "cam";
  h.send(noisy_sphere(), spec, 1);
  EXPECT_EQ(h.receive("cam").header.status(), wire::OK);
  zmq::message_t m;
  EXPECT_FALSE(sub.recv(m)) << "a subscriber without keys received a result";
  daemon::StreamSettings unused;
  EXPECT_FALSE(h.daemon()->registry().find("intruder", unused)) << "frames without an allowed key got in";
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (h.daemon()->registry().refusals().get(daemon::Refusal::kUnauthenticated) == 0 &&
         std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_GE(h.daemon()->registry().refusals().get(daemon::Refusal::kUnauthenticated), 1u);
}

// security.control_keys_file: the control socket takes only the keys it lists (an operator's),
// not those of client_keys_file, which still carry frames and results; its own keys reach
// no other socket.
TEST(DaemonCurve, TheControlSocketTakesOnlyItsOwnKeyList) {
  const TestKeys k;
  daemon::DaemonConfig c = k.secured(test_config());
  c.security.control_keys_file = k.stranger_pub;     // the operator's key
  DaemonHarness h(c, {k.server_pub, k.client_key});  // frames and results with the client key
  client::FrameSpec spec;
  spec.stream_id = "cam";
  h.send(noisy_sphere(), spec, 1);
  EXPECT_EQ(h.receive("cam").header.status(), wire::OK);
  zmq::context_t ctx(1);
  auto control_with = [&](const std::string& key, wire::ControlReply& reply) {
    zmq::socket_t req(ctx, zmq::socket_type::req);
    req.set(zmq::sockopt::linger, 0);
    EXPECT_TRUE(client::apply_curve_client(req, {k.server_pub, key}).ok());
    req.connect(h.daemon()->endpoints().control);
    wire::ControlRequest q;
    q.mutable_get_counters()->set_stream_id("cam");
    return client::control_call(req, q, reply, 3000);
  };
  const uint64_t refused = h.daemon()->registry().refusals().get(daemon::Refusal::kUnauthenticated);
  wire::ControlReply reply;
  EXPECT_FALSE(control_with(k.client_key, reply).ok()) << "a client key reached the control socket";
  EXPECT_GT(h.daemon()->registry().refusals().get(daemon::Refusal::kUnauthenticated), refused);
  const Status s = control_with(k.stranger_key, reply);
  ASSERT_TRUE(s.ok()) << s.message();
  ASSERT_EQ(reply.counters_size(), 1);
  EXPECT_EQ(reply.counters(0).frames_out(), 1u);
  // The operator's key on the ingest socket: refused there (not in client_keys_file).
  zmq::socket_t push(ctx, zmq::socket_type::push);
  push.set(zmq::sockopt::linger, 0);
  ASSERT_TRUE(client::apply_curve_client(push, {k.server_pub, k.stranger_key}).ok());
  push.connect(h.daemon()->endpoints().ingest);
  std::vector<std::string> parts;
  spec.stream_id = "operator";
  ASSERT_TRUE(client::build_frame(noisy_sphere().view(), spec, 0, parts).ok());
  std::vector<zmq::const_buffer> b;
  b.reserve(parts.size());
  for (const std::string& p : parts) b.push_back(zmq::buffer(p));
  (void)zmq::send_multipart(push, b, zmq::send_flags::dontwait);
  h.sync_results();
  daemon::StreamSettings unused;
  EXPECT_FALSE(h.daemon()->registry().find("operator", unused)) << "the control key got a frame in";
}

TEST(DaemonCurve, MissingOrBadKeyFilesStopTheStartWithTheirName) {
  const TestKeys k;
  daemon::DaemonConfig c = k.secured(test_config());
  c.security.client_keys_file.clear();
  daemon::Daemon d1(c);
  Status s = d1.start();
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("client_keys_file"), std::string::npos) << s.message();
  c = k.secured(test_config());
  c.security.curve_key_file = k.server_pub;  // public only: no secret
  daemon::Daemon d2(c);
  s = d2.start();
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no secret key"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace fq::test
