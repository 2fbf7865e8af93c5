// /login against fqd as a child process: guesses are rate-limited per source address (429 with
// Retry-After) and each failure is logged at a bounded rate; the cookie it sets is a session id
// kept by fqd, not the bearer token, and a forged one is refused.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "daemon/http/http_access.h"
#include "tests/daemon/fqd_process.h"
#include "tests/daemon/raw_http.h"

namespace fq::test {
namespace {

const std::string kToken = "0f1e2d3c4b5a69788796a5b4c3d2e1f0";

std::string get(int port, const std::string& path, const std::string& headers = "") {
  RawConnection c(port);
  if (!c.ok() ||
      !c.send("GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers + "Connection: close\r\n\r\n"))
    return {};
  return c.receive();
}

// The value of header `name` in a raw response ("" when absent).
std::string header_of(const std::string& response, const std::string& name) {
  const size_t at = response.find("\r\n" + name + ": ");
  if (at == std::string::npos) return {};
  const size_t from = at + name.size() + 4;
  return response.substr(from, response.find("\r\n", from) - from);
}

class HttpLogin : public testing::Test {
 protected:
  void SetUp() override {
    log_ = testing::TempDir() + "/fqd_login.log";
    const std::string token_file = write_temp_file("login_token", kToken + "\n");
    fqd_ = std::make_unique<FqdProcess>(
        std::vector<std::string>{
            "--config", write_temp_file("login.toml", ops_config(http_without_viewer() + "token_file = \"" +
                                                                 token_file + "\"\n"))},
        "", "2>'" + log_ + "'");
    port_ = http_port(fqd_->endpoint("http"));
    ASSERT_GT(port_, 0) << read_text_file(log_);
  }
  std::string log_;
  std::unique_ptr<FqdProcess> fqd_;
  int port_ = 0;
};

// Before, the cookie was the bearer token itself: whoever read it from a browser's store or a
// proxy's log held the token for good.
TEST_F(HttpLogin, TheCookieIsASessionNotTheTokenAndAForgedOneIsRefused) {
  const std::string login = get(port_, "/login?token=" + kToken);
  ASSERT_EQ(status_of(login), 303) << login;
  const std::string cookie = header_of(login, "Set-Cookie");
  const std::string pair = cookie.substr(0, cookie.find(';'));
  ASSERT_EQ(pair.rfind("fq_session=", 0), 0u) << cookie;
  const std::string session = pair.substr(pair.find('=') + 1);
  EXPECT_EQ(session.size(), 64u) << "32 random bytes in hex";
  EXPECT_EQ(cookie.find(kToken), std::string::npos) << cookie;
  EXPECT_EQ(status_of(get(port_, "/streams", "Cookie: " + pair + "\r\n")), 200);
  EXPECT_EQ(status_of(get(port_, "/streams", "Cookie: fq_session=" + std::string(64, 'a') + "\r\n")), 401);
  EXPECT_EQ(status_of(get(port_, "/streams", "Cookie: fq_session=" + kToken + "\r\n")), 401);
  EXPECT_EQ(status_of(get(port_, "/streams", "Cookie: fq_token=" + kToken + "\r\n")), 401);
  EXPECT_EQ(status_of(get(port_, "/streams", "Authorization: Bearer " + kToken + "\r\n")), 200);
  // A second login is another session; the first stays good.
  const std::string again = header_of(get(port_, "/login?token=" + kToken), "Set-Cookie");
  EXPECT_NE(again.substr(0, again.find(';')), pair);
  EXPECT_EQ(status_of(get(port_, "/streams", "Cookie: " + pair + "\r\n")), 200);
}

// Before, one address could try tokens as fast as fqd answered (about 2,000 a second here).
TEST_F(HttpLogin, GuessesFromOneAddressAreBoundedAndEachFailureIsLogged) {
  const auto start = std::chrono::steady_clock::now();
  int wrong = 0, limited = 0;
  std::string retry_after;
  for (int i = 0; i < 60; ++i) {
    const std::string r = get(port_, "/login?token=guess" + std::to_string(i));
    const int status = status_of(r);
    if (status == 401) ++wrong;
    if (status == 429) {
      ++limited;
      retry_after = header_of(r, "Retry-After");
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(wrong + limited, 60);
  EXPECT_LE(wrong, daemon::kLoginBurst + daemon::kLoginPerSecond * seconds + 1) << seconds << " s";
  EXPECT_GT(limited, 0);
  ASSERT_FALSE(retry_after.empty());
  EXPECT_GE(std::stoi(retry_after), 1);
  // Refused before the token is compared: the right one waits its turn too.
  const int right = status_of(get(port_, "/login?token=" + kToken));
  EXPECT_EQ(right, 429);
  const std::string metrics = get(port_, "/metrics", "Authorization: Bearer " + kToken + "\r\n");
  EXPECT_NE(metrics.find("fq_http_refused_total{reason=\"login_rate\"} " +
                         std::to_string(limited + (right == 429 ? 1 : 0)) + "\n"),
            std::string::npos)
      << metrics;
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log_).find("failed /login from 127.0.0.1") != std::string::npos;
  })) << read_text_file(log_);
  std::printf("%d wrong guesses answered, %d refused with 429, in %.2f s\n", wrong, limited, seconds);
  EXPECT_EQ(fqd_->stop(), 0);
}

}  // namespace
}  // namespace fq::test
