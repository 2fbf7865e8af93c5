// Who may use fqd's HTTP listener: TLS with a bearer token (curl round trips with the token, its
// login cookie, without it and with a wrong one), [security] on requiring authentication for
// the streams, results and viewer, the Host allow-list (DNS rebinding), a warning for a public
// listener without TLS or token, and a second fqd on the same port exiting 1.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "common/curve_keys.h"
#include "daemon/http/http_front.h"
#include "tests/daemon/fqd_process.h"
#include "tests/daemon/http_metrics.h"
#include "tests/daemon/raw_http.h"

namespace fq::test {
namespace {

const std::string kToken = "9f2c1e0b7a6d5c4b3a29f8e7d6c5b4a3";

std::string http_section(const std::string& extra) {
  return http_without_viewer() + extra + "[streams.cam0]\nbudget_ms = 60000\n";
}

// A self-signed certificate for 127.0.0.1 (openssl, Debian's openssl package).
void make_certificate(std::string& cert, std::string& key) {
  cert = testing::TempDir() + "/fq_http_cert.pem";
  key = testing::TempDir() + "/fq_http_key.pem";
  const ToolRun r =
      run_tool("/usr/bin/openssl",
               {"req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=127.0.0.1",
                "-addext", "subjectAltName=IP:127.0.0.1,DNS:localhost", "-keyout", key, "-out", cert});
  ASSERT_EQ(r.status, 0) << r.output;
}

// curl's status code for `url` (with `args` before it), as text ("000" when none came).
std::string curl_status(const std::vector<std::string>& args, const std::string& url) {
  std::vector<std::string> all = {"-s", "-o", "/dev/null", "-w", "%{http_code}", "--max-time", "10"};
  all.insert(all.end(), args.begin(), args.end());
  all.push_back(url);
  return run_tool("/usr/bin/curl", all).output;
}

int status_with_host(int port, const std::string& path, const std::string& host) {
  RawConnection c(port);
  if (!c.ok() || !c.send("GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n"))
    return 0;
  return status_of(c.receive());
}

TEST(HttpAuth, TlsAndTokenRoundTripWithCurl) {
  std::string cert, key;
  make_certificate(cert, key);
  const std::string token_file = write_temp_file("fq_token", kToken + "\n");
  FqdProcess fqd({"--config",
                  write_temp_file("http_tls.toml", ops_config(http_section(
                                                       "tls_cert_file = \"" + cert + "\"\ntls_key_file = \"" +
                                                       key + "\"\ntoken_file = \"" + token_file + "\"\n")))});
  const std::string base = fqd.endpoint("http");
  ASSERT_EQ(base.rfind("https://127.0.0.1:", 0), 0u) << base;
  const std::vector<std::string> tls = {"--cacert", cert};
  auto with = [&](std::vector<std::string> more) {
    more.insert(more.begin(), tls.begin(), tls.end());
    return more;
  };
  EXPECT_EQ(curl_status(with({"-H", "Authorization: Bearer " + kToken}), base + "/streams"), "200");
  EXPECT_EQ(curl_status(with({"-H", "Authorization: Bearer " + kToken}), base + "/metrics"), "200");
  EXPECT_EQ(curl_status(tls, base + "/streams"), "401");
  EXPECT_EQ(curl_status(tls, base + "/streams/cam0/latest"), "401");
  EXPECT_EQ(curl_status(tls, base + "/"), "401");
  EXPECT_EQ(curl_status(with({"-H", "Authorization: Bearer " + kToken + "x"}), base + "/streams"), "401");
  EXPECT_EQ(curl_status(tls, base + "/healthz"), "200");  // probes need no token
  // The viewer's way in: /login sets the cookie the page's requests then carry.
  const std::string jar = testing::TempDir() + "/fq_cookies";
  EXPECT_EQ(curl_status(with({"-c", jar}), base + "/login?token=" + kToken), "303");
  EXPECT_EQ(curl_status(with({"-b", jar}), base + "/streams"), "200");
  EXPECT_EQ(curl_status(with({"-c", jar + "2"}), base + "/login?token=wrong"), "401");
  // Plain HTTP on the TLS port gets nothing.
  const int port = http_port(base);
  EXPECT_EQ(get_status(port, "/healthz", std::chrono::seconds(10)), 0);
  const std::string m = run_tool("/usr/bin/curl", {"-s", "--cacert", cert, "-H",
                                                   "Authorization: Bearer " + kToken, base + "/metrics"})
                            .output;
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"unauthenticated\"}"), 5) << m;
  EXPECT_GE(metric_value(m, "fq_http_refused_total{reason=\"tls\"}"), 1) << m;
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpAuth, CurveOnRequiresAuthenticationForStreamsResultsAndTheViewer) {
  CurveKeyPair server, client;
  ASSERT_TRUE(make_curve_key_pair(server).ok());
  ASSERT_TRUE(make_curve_key_pair(client).ok());
  const std::string server_key = testing::TempDir() + "/fq_http_server.key";
  const std::string client_pub = testing::TempDir() + "/fq_http_client.pub";
  ASSERT_TRUE(write_curve_key_file(server_key, server).ok());
  ASSERT_TRUE(write_curve_key_file(client_pub, {client.public_key, ""}).ok());
  const std::string security =
      "[security]\ncurve_key_file = \"" + server_key + "\"\nclient_keys_file = \"" + client_pub + "\"\n";
  {
    const std::string log = testing::TempDir() + "/fq_http_curve.log";
    FqdProcess fqd({"--config", write_temp_file("http_curve.toml", ops_config(security + http_section("")))},
                   "", "2>" + log);
    const int port = http_port(fqd.endpoint("http"));
    ASSERT_GT(port, 0);
    for (const char* path : {"/streams", "/streams/cam0/latest", "/", "/index.html", "/login?token=x"})
      EXPECT_EQ(get_status(port, path), path == std::string("/login?token=x") ? 401 : 403) << path;
    EXPECT_EQ(get_status(port, "/metrics"), 200);
    EXPECT_EQ(get_status(port, "/healthz"), 200);
    EXPECT_EQ(fqd.stop(), 0);
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(text.find("http.token_file is not set"), std::string::npos) << text;
  }
  const std::string token_file = write_temp_file("fq_token_curve", kToken + "\n");
  FqdProcess fqd({"--config", write_temp_file("http_curve_token.toml",
                                              ops_config(security + http_section("token_file = \"" +
                                                                                 token_file + "\"\n")))});
  const int port = http_port(fqd.endpoint("http"));
  EXPECT_EQ(get_status(port, "/streams"), 401);
  EXPECT_EQ(
      get_status(port, "/streams", std::chrono::seconds(10), "Authorization: Bearer " + kToken + "\r\n"),
      200);
  EXPECT_EQ(fqd.stop(), 0);
}

// Each TLS handshake costs fqd a private-key operation; before, one address could ask for them as
// fast as it connected. Connections that send no handshake at all fail it, so the ones past the
// rate are told apart by their reason (tls_rate: closed before the handshake).
TEST(HttpAuth, TlsHandshakesFromOneAddressAreRateLimited) {
  std::string cert, key;
  make_certificate(cert, key);
  FqdProcess fqd(
      {"--config", write_temp_file("http_tls_rate.toml",
                                   ops_config(http_section("tls_cert_file = \"" + cert +
                                                           "\"\ntls_key_file = \"" + key + "\"\n")))});
  const std::string base = fqd.endpoint("http");
  const int port = http_port(base);
  ASSERT_GT(port, 0);
  constexpr int kConnections = 300;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kConnections; ++i) {
    RawConnection c(port);
    c.send("not a ClientHello\r\n");
    EXPECT_TRUE(c.closed_by_peer(std::chrono::seconds(10)));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The bucket refills (at most 2 s from empty), then a real client gets through.
  std::this_thread::sleep_for(std::chrono::milliseconds(
      static_cast<int>(1000 * daemon::kTlsHandshakeBurst / daemon::kTlsHandshakesPerSecond)));
  std::string m;
  ASSERT_TRUE(eventually([&] {
    m = run_tool("/usr/bin/curl", {"-s", "--cacert", cert, base + "/metrics"}).output;
    return metric_value(m, "fq_http_refused_total{reason=\"tls_rate\"}") > 0;
  })) << m;
  const double failed = metric_value(m, "fq_http_refused_total{reason=\"tls\"}");
  const double limited = metric_value(m, "fq_http_refused_total{reason=\"tls_rate\"}");
  EXPECT_GE(failed + limited, kConnections) << m;
  EXPECT_GT(limited, 0) << m;
  EXPECT_LE(failed, daemon::kTlsHandshakeBurst + daemon::kTlsHandshakesPerSecond * seconds + 1)
      << seconds << " s";
  std::printf("%d connections in %.2f s: %.0f handshakes tried, %.0f refused before one\n", kConnections,
              seconds, failed, limited);
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpAuth, HostHeadersOutsideTheAllowListAreRefused) {
  {
    FqdProcess fqd({"--config", write_temp_file("http_hosts.toml", ops_config(http_section("")))});
    const int port = http_port(fqd.endpoint("http"));
    ASSERT_GT(port, 0);
    EXPECT_EQ(status_with_host(port, "/streams", "127.0.0.1:" + std::to_string(port)), 200);
    EXPECT_EQ(status_with_host(port, "/streams", "localhost"), 200);
    EXPECT_EQ(status_with_host(port, "/streams", "[::1]:80"), 200);
    // A rebinding page's own name: refused, also for /metrics.
    EXPECT_EQ(status_with_host(port, "/streams", "attacker.example:" + std::to_string(port)), 421);
    EXPECT_EQ(status_with_host(port, "/metrics", "attacker.example"), 421);
    EXPECT_EQ(status_with_host(port, "/healthz", "attacker.example"), 200);
    EXPECT_GE(metric_value(http_get(fqd.endpoint("http"), "/metrics"),
                           "fq_http_refused_total{reason=\"bad_host\"}"),
              2);
    EXPECT_EQ(fqd.stop(), 0);
  }
  FqdProcess fqd(
      {"--config", write_temp_file("http_hosts_list.toml",
                                   ops_config(http_section(
                                       "allowed_hosts = [\"fq.example.com\", \"*.fq.example.org\"]\n")))});
  const int port = http_port(fqd.endpoint("http"));
  EXPECT_EQ(status_with_host(port, "/streams", "fq.example.com:8080"), 200);
  EXPECT_EQ(status_with_host(port, "/streams", "cam.fq.example.org"), 200);
  EXPECT_EQ(status_with_host(port, "/streams", "fq.example.org"), 421);
  EXPECT_EQ(status_with_host(port, "/streams", "127.0.0.1"), 421);
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(HttpAuth, APublicListenerWithoutTlsOrTokenIsWarnedAbout) {
  const std::string log = testing::TempDir() + "/fq_http_public.log";
  FqdProcess fqd(
      {"--config", write_temp_file("http_public.toml", ops_config(http_without_viewer("0.0.0.0:0")))}, "",
      "2>" + log);
  ASSERT_FALSE(fqd.endpoint("http").empty());
  EXPECT_EQ(fqd.stop(), 0);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("without TLS"), std::string::npos) << text;
  EXPECT_NE(text.find("without a token"), std::string::npos) << text;
}

TEST(HttpAuth, ASecondFqdOnTheSamePortExitsWithStatus1) {
  FqdProcess first({"--config", write_temp_file("http_first.toml", ops_config(http_section("")))});
  const int port = http_port(first.endpoint("http"));
  ASSERT_GT(port, 0);
  const std::string log = testing::TempDir() + "/fq_http_second.log";
  FqdProcess second(
      {"--config", write_temp_file("http_second.toml",
                                   ops_config(http_without_viewer("127.0.0.1:" + std::to_string(port))))},
      "", "2>" + log);
  EXPECT_TRUE(second.endpoint("http").empty());
  EXPECT_EQ(second.stop(), 1);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("cannot listen on http 127.0.0.1:" + std::to_string(port)), std::string::npos) << text;
  // Every request still reaches the first.
  for (int i = 0; i < 12; ++i) EXPECT_EQ(get_status(port, "/healthz"), 200);
  EXPECT_EQ(first.stop(), 0);
}

}  // namespace
}  // namespace fq::test
