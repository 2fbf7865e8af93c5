// fqd's HTTP listener against requests built to cost it memory: heads with endless header
// lines or one endless line, and bodies (fqd takes none). Each is refused before the bytes are
// kept, fqd's RSS stays flat, the refusals are counted on /metrics, and /healthz still answers.
#include <gtest/gtest.h>

#include <string>

#include "tests/daemon/daemon_harness.h"
#include "tests/daemon/fqd_process.h"
#include "tests/daemon/http_metrics.h"
#include "tests/daemon/raw_http.h"

namespace fq::test {
namespace {

constexpr size_t kMiB = 1 << 20;

// Sends `head` and then `filler` repeated until `total` bytes went out or fqd stopped reading.
void flood(int port, const std::string& head, const std::string& filler, size_t total) {
  RawConnection c(port);
  ASSERT_TRUE(c.ok());
  std::string block;
  while (block.size() < kMiB) block += filler;
  if (!c.send(head)) return;
  for (size_t sent = 0; sent < total && c.send(block); sent += block.size()) {
  }
  c.receive(std::chrono::seconds(2));
}

TEST(HttpLimits, HeadsOverTheBoundsAreRefusedBeforeTheyAreKept) {
  FqdProcess fqd({"--config", write_temp_file("http_heads.toml", ops_config(http_without_viewer()))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  ASSERT_EQ(get_status(port, "/healthz"), 200);
  const size_t rss0 = rss_bytes(fqd.pid());

  // 64 MiB of header lines, then one 64 MiB header line: 1.8 GB of RSS, kept, before the bound.
  flood(port, "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n", "a:b\r\n", 64 * kMiB);
  flood(port, "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Long: ", "aaaaaaaa", 64 * kMiB);
  const size_t rss1 = rss_bytes(fqd.pid());
  EXPECT_LT(rss1, rss0 + 8 * kMiB) << "fqd RSS " << rss0 / kMiB << " -> " << rss1 / kMiB << " MiB";

  // A client that waits for the answer gets 431 and a closed connection.
  std::string many = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  for (int i = 0; i < 64; ++i) many += "X-" + std::to_string(i) + ": v\r\n";
  RawConnection a(port);
  ASSERT_TRUE(a.send(many + "\r\n"));
  const std::string too_many = a.receive();
  EXPECT_EQ(status_of(too_many), 431) << too_many;
  EXPECT_NE(too_many.find("http.max_headers"), std::string::npos) << too_many;
  RawConnection b(port);
  ASSERT_TRUE(
      b.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Big: " + std::string(20000, 'x') + "\r\n\r\n"));
  EXPECT_EQ(status_of(b.receive()), 431);
  // Exactly at the bounds is served: 63 headers besides Host, a head of 16 KiB less a little.
  std::string at_bound = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n";
  for (int i = 0; i < 62; ++i) at_bound += "X-" + std::to_string(i) + ": v\r\n";
  RawConnection c(port);
  ASSERT_TRUE(c.send(at_bound + "\r\n"));
  EXPECT_EQ(status_of(c.receive()), 200);

  EXPECT_EQ(get_status(port, "/healthz"), 200);
  const std::string m = http_get(fqd.endpoint("http"), "/metrics");
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"head_too_large\"}"), 2) << m;
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"too_many_headers\"}"), 2) << m;
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpLimits, BodiesAreRefusedUnread) {
  FqdProcess fqd({"--config", write_temp_file("http_bodies.toml", ops_config(http_without_viewer()))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  const size_t rss0 = rss_bytes(fqd.pid());

  // Announced: the answer comes before a byte of the body is sent.
  RawConnection announced(port);
  ASSERT_TRUE(
      announced.send("POST /streams HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 1073741824\r\n\r\n"));
  const std::string answer = announced.receive(std::chrono::seconds(10));
  EXPECT_EQ(status_of(answer), 413) << answer;
  EXPECT_TRUE(announced.closed_by_peer(std::chrono::seconds(5)));
  // Sent anyway, in length-delimited and in chunked form: fqd does not read it.
  flood(port, "POST /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 268435456\r\n\r\n", "x",
        256 * kMiB);
  flood(port, "POST /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: chunked\r\n\r\n",
        "100000\r\n" + std::string(0x100000, 'y') + "\r\n", 256 * kMiB);
  EXPECT_EQ(get_status(port, "/healthz", std::chrono::seconds(10), "Content-Length: 3\r\n"), 413);
  const size_t rss1 = rss_bytes(fqd.pid());
  EXPECT_LT(rss1, rss0 + 8 * kMiB) << "fqd RSS " << rss0 / kMiB << " -> " << rss1 / kMiB << " MiB";

  EXPECT_EQ(get_status(port, "/healthz"), 200);
  EXPECT_GE(
      metric_value(http_get(fqd.endpoint("http"), "/metrics"), "fq_http_refused_total{reason=\"body\"}"), 4);
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpLimits, StreamIdsInPathsAreCheckedAsOnEveryDoor) {
  FqdProcess fqd({"--config", write_temp_file("http_ids.toml", ops_config(http_without_viewer()))});
  const int port = http_port(fqd.endpoint("http"));
  ASSERT_GT(port, 0);
  auto body_of = [&](const std::string& path) {
    RawConnection c(port);
    EXPECT_TRUE(c.send("GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n"));
    return c.receive();
  };
  const std::string newline = body_of("/streams/cam%0A%5Bcritical%5D/latest");
  EXPECT_EQ(status_of(newline), 404);
  EXPECT_NE(newline.find("cam\\x0a[critical]"), std::string::npos) << newline;
  const std::string longer = body_of("/streams/" + std::string(200, 'x') + "/latest");
  EXPECT_EQ(status_of(longer), 404);
  EXPECT_NE(longer.find("caps.max_stream_id_bytes"), std::string::npos) << longer;
  EXPECT_EQ(fqd.stop(), 0);
}

}  // namespace
}  // namespace fq::test
