// fqd's ZeroMQ doors under the same rules, over real sockets on 127.0.0.1: SUB ingest takes only
// authenticated producers and refuses a part over the size cap at the socket, and producers it
// dropped for that, however many at once, come back; a control request of 100,000 parts gets one
// error reply and at most a few log lines, an oversized one nothing; a subscriber past
// caps.max_subscriptions is cut and counted while others keep their results.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <zmq_addon.hpp>

#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/http_metrics.h"
#include "tests/daemon/log_capture.h"
#include "tests/daemon/test_keys.h"

namespace fq::test {
namespace {

using std::chrono::milliseconds;

template <class F>
bool eventually(F&& done, std::chrono::seconds limit = std::chrono::seconds(30)) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done() && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(milliseconds(20));  // polling fqd's counters
  return done();
}

std::vector<std::string> frame_parts(const std::string& stream, uint64_t sequence) {
  client::FrameSpec spec;
  spec.stream_id = stream;
  std::vector<std::string> parts;
  EXPECT_TRUE(client::build_frame(noisy_sphere().view(), spec, sequence, parts).ok());
  return parts;
}

// A producer's PUB (an XPUB, to see fqd's subscription arrive), bound on a free port.
struct Producer {
  Producer(zmq::context_t& ctx, const client::CurveClientOptions* curve)
      : socket(ctx, zmq::socket_type::xpub) {
    socket.set(zmq::sockopt::linger, 0);
    socket.set(zmq::sockopt::xpub_verbose, 1);  // every subscription, also a repeated one
    if (curve) {
      EXPECT_TRUE(client::apply_curve_client(socket, *curve).ok());
    }
    socket.bind("tcp://127.0.0.1:*");
    endpoint = socket.get(zmq::sockopt::last_endpoint);
  }
  /// True once fqd's SUB socket subscribed (within `wait`); unsubscriptions (fqd's SUB
  /// leaving) are passed over.
  bool subscribed(milliseconds wait) {
    socket.set(zmq::sockopt::rcvtimeo, static_cast<int>(wait.count()));
    for (zmq::message_t m; socket.recv(m);)
      if (m.size() > 0 && m.data<uint8_t>()[0] == 1) return true;
    return false;
  }
  zmq::socket_t socket;
  std::string endpoint;
};

bool has_stream(DaemonHarness& h, const std::string& id) {
  daemon::StreamSettings unused;
  return h.daemon()->registry().find(id, unused);
}

TEST(ZmqDoors, SubIngestTakesOnlyAuthenticatedProducersAndRefusesAnOversizedPart) {
  const TestKeys k;
  zmq::context_t ctx(1);
  Producer plain(ctx, nullptr);
  const client::CurveClientOptions keyed_opts{k.server_pub, k.client_key};
  Producer keyed(ctx, &keyed_opts);
  daemon::DaemonConfig c = k.secured(test_config());
  c.sub_ingest.connect = {plain.endpoint, keyed.endpoint};
  c.caps.max_frame_bytes = 1 << 20;
  DaemonHarness h(c, keyed_opts);

  ASSERT_TRUE(keyed.subscribed(milliseconds(30000)));
  EXPECT_FALSE(plain.subscribed(milliseconds(1000))) << "fqd subscribed to a producer without keys";
  for (uint64_t i = 0; i < 3; ++i) client::send_parts(plain.socket, frame_parts("sub_plain", i));
  client::send_parts(keyed.socket, frame_parts("sub_keyed", 1));
  EXPECT_EQ(h.receive("sub_keyed").header.status(), wire::OK);

  // A part over caps.max_frame_bytes drops the connection before it is buffered; fqd's SUB
  // connects again and subscribes, and the next frame is served.
  std::vector<std::string> big = frame_parts("sub_keyed", 2);
  big.back() = std::string(4 << 20, 'x');
  client::send_parts(keyed.socket, big);
  ASSERT_TRUE(keyed.subscribed(milliseconds(30000))) << "fqd did not come back after the oversized part";
  client::send_parts(keyed.socket, frame_parts("sub_keyed", 3));
  const client::ReceivedResult r = h.receive("sub_keyed");
  EXPECT_EQ(r.header.status(), wire::OK);
  EXPECT_EQ(r.header.sequence(), 3u);
  EXPECT_EQ(h.counters("sub_keyed").frames_in(), 2u) << "the oversized frame reached fqd";
  EXPECT_FALSE(has_stream(h, "sub_plain")) << "frames from a producer without keys got in";
}

// Producers dropped at once (each sent a part over the cap) all come back, round after round,
// and each time fqd connected again is counted. fqd used to disconnect the endpoint libzmq had
// given up on and connect it again on the same SUB socket: libzmq 4.3 keeps that endpoint with
// pointers to the freed connection, and disconnecting it could end the connection just made to
// another producer, which then never came back.
TEST(ZmqDoors, ProducersDroppedTogetherAllComeBack) {
  const TestKeys k;
  zmq::context_t ctx(1);
  const client::CurveClientOptions keyed_opts{k.server_pub, k.client_key};
  daemon::DaemonConfig c = k.secured(test_config());
  c.caps.max_frame_bytes = 1 << 20;
  std::vector<std::unique_ptr<Producer>> producers;
  for (int i = 0; i < 6; ++i) {
    producers.push_back(std::make_unique<Producer>(ctx, &keyed_opts));
    c.sub_ingest.connect.push_back(producers.back()->endpoint);
  }
  DaemonHarness h(c, keyed_opts);
  for (auto& p : producers) ASSERT_TRUE(p->subscribed(milliseconds(30000)));

  std::vector<std::string> big = frame_parts("sub_many", 1);
  big.back() = std::string(2 << 20, 'x');
  constexpr int kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    for (auto& p : producers) client::send_parts(p->socket, big);
    for (size_t i = 0; i < producers.size(); ++i)
      ASSERT_TRUE(producers[i]->subscribed(milliseconds(30000)))
          << "producer " << i << " lost in round " << round;
  }
  const std::string m = h.daemon()->service_metrics();
  EXPECT_EQ(metric_value(m, "fq_ingest_reconnects_total"), kRounds * 6.0) << m;
  EXPECT_FALSE(has_stream(h, "sub_many")) << "an oversized frame reached fqd";
}

TEST(ZmqDoors, AControlRequestOfManyPartsGetsOneAnswerAndAnOversizedOneNone) {
  LogCapture log;  // before fqd's threads log
  DaemonHarness h;
  zmq::context_t ctx(1);
  zmq::socket_t dealer(ctx, zmq::socket_type::dealer);
  dealer.set(zmq::sockopt::linger, 0);
  dealer.set(zmq::sockopt::rcvtimeo, 30000);
  dealer.connect(h.daemon()->endpoints().control);
  // [empty delimiter][100,000 parts]: a REQ's envelope around a request of many parts.
  wire::ControlRequest q;
  q.mutable_list_streams();
  const std::string request = q.SerializeAsString();
  dealer.send(zmq::message_t(), zmq::send_flags::sndmore);
  for (int i = 0; i < 100'000; ++i)
    dealer.send(zmq::buffer(request), i + 1 < 100'000 ? zmq::send_flags::sndmore : zmq::send_flags::none);
  std::vector<zmq::message_t> reply;
  ASSERT_TRUE(zmq::recv_multipart(dealer, std::back_inserter(reply)));
  ASSERT_EQ(reply.size(), 2u);  // the delimiter and one answer
  wire::ControlReply r;
  ASSERT_TRUE(r.ParseFromArray(reply[1].data(), static_cast<int>(reply[1].size())));
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error().find("one message part"), std::string::npos) << r.error();
  dealer.set(zmq::sockopt::rcvtimeo, 500);
  zmq::message_t extra;
  EXPECT_FALSE(dealer.recv(extra)) << "more than one answer to one request";
  EXPECT_LE(log.lines_with("control"), 5u);
  EXPECT_EQ(h.daemon()->registry().refusals().get(daemon::Refusal::kOversized), 1u);

  // One part over the cap: the connection is dropped before the part is buffered; the
  // control socket keeps serving others.
  dealer.send(zmq::message_t(), zmq::send_flags::sndmore);
  dealer.send(zmq::buffer(std::string(1 << 20, 'x')), zmq::send_flags::none);
  EXPECT_FALSE(dealer.recv(extra));
  wire::ControlRequest list;
  list.mutable_list_streams();
  EXPECT_TRUE(h.control(list).ok());
}

TEST(ZmqDoors, ASubscriberPastTheSubscriptionCapIsCutAndTheOthersKeepTheirResults) {
  daemon::DaemonConfig c = test_config();
  c.caps.max_subscriptions = 16;
  DaemonHarness h(c);
  zmq::context_t ctx(1);
  auto subscriber = [&](int topics) {
    auto s = std::make_unique<zmq::socket_t>(ctx, zmq::socket_type::sub);
    s->set(zmq::sockopt::linger, 0);
    s->set(zmq::sockopt::reconnect_ivl, -1);  // a cut subscriber stays away
    s->set(zmq::sockopt::rcvtimeo, 30000);
    for (int i = 0; i < topics; ++i) s->set(zmq::sockopt::subscribe, "t" + std::to_string(100 + i));
    s->connect(h.daemon()->endpoints().publish);
    return s;
  };
  auto result_on = [&](zmq::socket_t& s, const std::string& stream, uint64_t sequence) {
    client::FrameSpec spec;
    spec.stream_id = stream;
    h.send(noisy_sphere(), spec, sequence);
    h.receive(stream);  // published by now
    client::ReceivedResult r;
    const StatusOr<bool> got = client::receive_result(s, r);
    return got.ok() && *got && r.topic == stream;
  };
  auto greedy = subscriber(16);  // at the cap: served
  h.sync_results();              // its subscriptions are in before the next result
  EXPECT_TRUE(result_on(*greedy, "t103", 1));
  greedy->set(zmq::sockopt::subscribe, "t116");  // one more: cut
  EXPECT_TRUE(eventually(
      [&] { return h.daemon()->registry().refusals().get(daemon::Refusal::kSubscriptions) == 1; }));
  greedy->set(zmq::sockopt::rcvtimeo, 1000);
  client::FrameSpec t104;
  t104.stream_id = "t104";
  h.send(noisy_sphere(), t104, 2);
  EXPECT_EQ(h.receive("t104").header.status(), wire::OK);  // the harness's subscriber still gets it
  zmq::message_t m;
  EXPECT_FALSE(greedy->recv(m)) << "a cut subscriber still got results";
  greedy.reset();
  // A newcomer (likely on the departed one's socket number) starts from nothing.
  auto next = subscriber(16);
  h.sync_results();
  EXPECT_TRUE(result_on(*next, "t105", 3));
  EXPECT_EQ(h.daemon()->registry().refusals().get(daemon::Refusal::kSubscriptions), 1u);
}

}  // namespace
}  // namespace fq::test
