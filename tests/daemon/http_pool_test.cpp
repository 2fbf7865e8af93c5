// fqd's HTTP listener against connections that hold it: slowloris heads, connections that say
// nothing, long polls, more connections than the bound. /healthz keeps answering within 1 s
// (a Kubernetes probe's default timeout), every holder is cut at its bound, and SIGTERM ends
// them all within caps.stop_grace_s + 1 s.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "tests/daemon/fqd_process.h"
#include "tests/daemon/http_metrics.h"
#include "tests/daemon/raw_http.h"

namespace fq::test {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using Connections = std::vector<std::unique_ptr<RawConnection>>;

std::string config(const std::string& http_extra) {
  return ops_config(http_without_viewer() + "request_timeout_s = 2\nidle_timeout_s = 3\n" + http_extra +
                    "[streams.cam0]\nbudget_ms = 60000\n");
}

Connections connect(int port, int count, const std::string& first_bytes = "") {
  Connections c;
  for (int i = 0; i < count; ++i) {
    c.push_back(std::make_unique<RawConnection>(port));
    EXPECT_TRUE(c.back()->ok());
    if (!first_bytes.empty()) EXPECT_TRUE(c.back()->send(first_bytes));
  }
  return c;
}

// Slowloris: a head that never ends, one more byte on every connection every 300 ms.
class Slowloris {
 public:
  explicit Slowloris(int port)
      : conns_(connect(port, 8, "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")) {
    thread_ = std::thread([this] {
      for (bool any = true; any && !stop_;) {
        any = false;
        for (auto& c : conns_) any = c->send("a") || any;
        std::this_thread::sleep_for(milliseconds(300));  // the attack's own pace
      }
    });
  }
  ~Slowloris() {
    stop_ = true;
    thread_.join();
  }
  Connections& connections() { return conns_; }

 private:
  Connections conns_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

const std::string kLongPoll =
    "GET /streams/cam0/latest?after=0&wait_ms=5000 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";

// The holders as first measured: 8 slowloris heads, 200 silent connections, 16 long polls.
struct Holders {
  explicit Holders(int port) : slow(port), idle(connect(port, 200)), polls(connect(port, 16, kLongPoll)) {}
  Slowloris slow;
  Connections idle, polls;
};

TEST(HttpPool, HealthAnswersUnderSlowlorisIdleConnectionsAndLongPolls) {
  FqdProcess fqd({"--config", write_temp_file("http_pool.toml", config(""))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  Holders h(port);
  for (int probe = 0; probe < 5; ++probe)
    EXPECT_EQ(get_status(port, "/healthz", seconds(1)), 200) << "probe " << probe;

  for (auto& c : h.slow.connections()) EXPECT_EQ(status_of(c->receive(seconds(5))), 408);
  for (auto& c : h.polls) EXPECT_EQ(status_of(c->receive(seconds(8))), 204);  // waited, then nothing newer
  for (auto& c : h.idle) EXPECT_TRUE(c->closed_by_peer(seconds(6)));
  const std::string m = http_get(fqd.endpoint("http"), "/metrics");
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"head_timeout\"}"), 8) << m;
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpPool, ConnectionsAndLongPollsPastTheirBoundsGet503) {
  FqdProcess fqd(
      {"--config", write_temp_file("http_caps.toml", config("max_connections = 24\nmax_long_polls = 4\n"))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  Connections polls = connect(port, 4, kLongPoll);
  // The four must be waiting in fqd before the next two come (on a loaded machine its HTTP
  // threads read the four requests a while after they were sent).
  std::this_thread::sleep_for(seconds(1));
  // Two more polls while four wait: answered at once.
  for (int i = 0; i < 2; ++i)
    EXPECT_EQ(get_status(port, "/streams/cam0/latest?after=0&wait_ms=5000", seconds(2)), 503);
  Connections idle = connect(port, 20);  // 24 open now
  // fqd accepts in the order the connections came; on a loaded machine its accept loop may
  // trail the 20 by a while, so the 25th gets up to 10 s for its refusal.
  RawConnection over(port);
  EXPECT_TRUE(over.send("GET /streams HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
  EXPECT_EQ(status_of(over.receive(seconds(10))), 503);
  // A health probe past the bound is answered on the lane kept for it.
  EXPECT_EQ(get_status(port, "/healthz", seconds(2)), 200);
  idle.clear();  // the holders leave: room again
  int health = 0;
  for (int i = 0; i < 50 && health != 200; ++i) {
    health = get_status(port, "/healthz", seconds(1));
    if (health != 200) std::this_thread::sleep_for(milliseconds(100));  // fqd notices the closes
  }
  EXPECT_EQ(health, 200);
  const std::string m = http_get(fqd.endpoint("http"), "/metrics");
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"too_many_long_polls\"}"), 2) << m;
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"too_many_connections\"}"), 1) << m;
  EXPECT_EQ(fqd.stop(), 0);
}

// 300 connections held (the default bound is 256): a liveness probe with a 1 s timeout still
// gets 200, 8 times of 8 (it failed every one before the health lane), and the rest past the
// bound get 503.
TEST(HttpPool, HealthAnswersWithEveryConnectionSlotTaken) {
  FqdProcess fqd({"--config", write_temp_file("http_full.toml", config(""))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  Connections held = connect(port, 300);
  std::this_thread::sleep_for(seconds(1));  // fqd has accepted them all
  for (int probe = 0; probe < 8; ++probe)
    EXPECT_EQ(get_status(port, "/healthz", seconds(1)), 200) << "probe " << probe;
  EXPECT_EQ(get_status(port, "/streams", seconds(2)), 503);
  held.clear();
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpPool, SigtermEndsEveryConnectionWithinTheGrace) {
  FqdProcess fqd({"--config", write_temp_file("http_stop.toml", config(""))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  const Holders h(port);
  ASSERT_EQ(get_status(port, "/healthz", seconds(1)), 200);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(fqd.stop(), 0);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(took, 1.0 + 1.0) << "SIGTERM took " << took << " s (caps.stop_grace_s = 1)";
}

}  // namespace
}  // namespace fq::test
