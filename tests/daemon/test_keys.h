// CURVE key files for tests that run fqd with [security]: fqd's pair, an allowed client's and a
// stranger's, in a folder of their own (removed with the object).
#pragma once

#include <filesystem>
#include <string>

#include "daemon/config/config.h"

namespace fq::test {

struct TestKeys {
  TestKeys();
  ~TestKeys();
  TestKeys(const TestKeys&) = delete;
  TestKeys& operator=(const TestKeys&) = delete;

  /// `base` with [security] on: fqd's key, the client's public key allowed.
  daemon::DaemonConfig secured(daemon::DaemonConfig base) const;

  std::filesystem::path dir;
  std::string server_key, server_pub, client_key, client_pub, stranger_key, stranger_pub;
};

}  // namespace fq::test
