#include "tests/daemon/test_keys.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>

#include "common/curve_keys.h"

namespace fq::test {

TestKeys::TestKeys() {
  static std::atomic<int> made{0};
  dir = std::filesystem::temp_directory_path() /
        ("fq_keys_" + std::to_string(::getpid()) + "_" + std::to_string(made++));
  std::filesystem::create_directories(dir);
  auto pair = [&](const std::string& name, std::string& key, std::string* pub) {
    CurveKeyPair p;
    EXPECT_TRUE(make_curve_key_pair(p).ok());
    key = (dir / (name + ".key")).string();
    EXPECT_TRUE(write_curve_key_file(key, p).ok());
    if (pub) {
      *pub = (dir / (name + ".pub")).string();
      EXPECT_TRUE(write_curve_key_file(*pub, {p.public_key, ""}).ok());
    }
  };
  pair("server", server_key, &server_pub);
  pair("client", client_key, &client_pub);
  pair("stranger", stranger_key, &stranger_pub);
}

TestKeys::~TestKeys() {
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
}

daemon::DaemonConfig TestKeys::secured(daemon::DaemonConfig c) const {
  c.security.curve_key_file = server_key;
  c.security.client_keys_file = client_pub;
  return c;
}

}  // namespace fq::test
