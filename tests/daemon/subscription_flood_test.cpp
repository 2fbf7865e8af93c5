// The publish socket against subscription floods, fqd as a child process: subscriptions longer
// than a stream id drop the subscriber at the socket, a subscriber past caps.max_subscriptions
// is cut and counted, and fqd's memory stays flat either way.
#include <gtest/gtest.h>

#include <zmq.hpp>

#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/fqd_process.h"
#include "tests/daemon/http_metrics.h"

namespace fq::test {
namespace {

constexpr size_t kMiB = 1 << 20;

// Subscribes `count` distinct topics of `bytes` each, then stays connected a moment so that
// fqd reads them (its receive loop wakes at least once a second).
void flood(zmq::context_t& ctx, const std::string& endpoint, int count, size_t bytes) {
  zmq::socket_t s(ctx, zmq::socket_type::sub);
  s.set(zmq::sockopt::linger, 0);
  s.set(zmq::sockopt::rcvtimeo, 2500);
  for (int i = 0; i < count; ++i) {
    std::string topic = std::to_string(i) + "-";
    topic.resize(bytes, 'x');
    s.set(zmq::sockopt::subscribe, topic);
  }
  s.connect(endpoint);
  zmq::message_t m;
  (void)s.recv(m);  // nothing is published: waits 2.5 s while fqd takes the subscriptions in
}

TEST(SubscriptionFlood, LongOrManySubscriptionsLeaveFqdsMemoryFlat) {
  FqdProcess fqd({"--config", write_temp_file("sub_flood.toml", ops_config(http_without_viewer()))});
  ASSERT_FALSE(fqd.endpoint("http").empty());
  zmq::context_t ctx(1);
  const size_t rss0 = rss_bytes(fqd.pid());
  flood(ctx, fqd.endpoint("publish"), 500, 60'000);  // 30 MB of topics: 480 MB in fqd before
  flood(ctx, fqd.endpoint("publish"), 2000, 120);    // far past caps.max_subscriptions (128)
  const size_t rss1 = rss_bytes(fqd.pid());
  EXPECT_LT(rss1, rss0 + 16 * kMiB) << "fqd RSS " << rss0 / kMiB << " -> " << rss1 / kMiB << " MiB";
  // Counted when fqd's loop reads the subscriptions, which a loaded machine may take longer
  // to do than the flood stays connected: polled.
  std::string m;
  EXPECT_TRUE(eventually([&] {
    m = http_get(fqd.endpoint("http"), "/metrics");
    return metric_value(m, "fq_refused_total{reason=\"subscriptions\"}") >= 1;
  })) << m;
  EXPECT_EQ(fqd.stop(), 0);
}

}  // namespace
}  // namespace fq::test
