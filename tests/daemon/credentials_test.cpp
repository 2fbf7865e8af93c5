// `credential:NAME` in a configuration (daemon/service/credentials.h): the file NAME in the directory
// systemd's LoadCredential= fills ($CREDENTIALS_DIRECTORY), resolved for every file key and then
// checked like any path; without the directory, or with a NAME that is a path, a problem line.
#include "daemon/service/credentials.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "daemon/service/config_check.h"

namespace fq::daemon {
namespace {

const char* kText = R"([http]
listen = "127.0.0.1:0"
token_file = "credential:http_token"
tls_cert_file = "/etc/fq/tls.crt"
tls_key_file = "credential:tls_key"
)";

DaemonConfig parsed(const std::string& text) {
  DaemonConfig c;
  const Status s = parse_config(text, "fqd.toml", c);
  EXPECT_TRUE(s.ok()) << s.message();
  return c;
}

TEST(Credentials, ResolvedUnderTheDirectoryAndOtherPathsKept) {
  DaemonConfig c = parsed(kText);
  c.security.curve_key_file = "credential:curve_key";
  c.security.control_keys_file = "credential:operators";
  resolve_credentials(c, "/run/credentials/fqd.service");
  EXPECT_EQ(c.http.token_file, "/run/credentials/fqd.service/http_token");
  EXPECT_EQ(c.security.curve_key_file, "/run/credentials/fqd.service/curve_key");
  EXPECT_EQ(c.security.control_keys_file, "/run/credentials/fqd.service/operators");
  EXPECT_EQ(c.http.tls_key_file, "/run/credentials/fqd.service/tls_key");
  EXPECT_EQ(c.http.tls_cert_file, "/etc/fq/tls.crt");  // a plain path stays one
  EXPECT_EQ(credential_problem(c.http.token_file), "");
}

TEST(Credentials, WithoutTheDirectoryOrWithAPathTheCheckNamesTheKeyAndValue) {
  DaemonConfig c = parsed(kText);
  c.http.tls_cert_file.clear();  // the token alone
  c.http.tls_key_file.clear();
  resolve_credentials(c, nullptr);
  EXPECT_EQ(c.http.token_file, "credential:http_token");
  std::vector<std::string> problems = config_problems(c);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].rfind("fqd.toml:3: http.token_file credential:http_token: names a credential, but "
                              "$CREDENTIALS_DIRECTORY is not set",
                              0),
            0u)
      << problems[0];
  c.http.token_file = "credential:../etc/shadow";
  resolve_credentials(c, "/run/credentials/fqd.service");
  EXPECT_EQ(c.http.token_file, "credential:../etc/shadow");  // never outside the directory
  problems = config_problems(c);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("is no credential name"), std::string::npos) << problems[0];
}

TEST(Credentials, AResolvedFileIsReadByTheSameCheck) {
  const std::string dir = testing::TempDir() + "/credentials_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/http_token") << "0123456789abcdef0123\n";
  DaemonConfig c = parsed(kText);
  c.http.tls_cert_file.clear();  // the token alone
  c.http.tls_key_file.clear();
  resolve_credentials(c, dir.c_str());
  EXPECT_TRUE(config_problems(c).empty());
  std::filesystem::remove(dir + "/http_token");
  const std::vector<std::string> problems = config_problems(c);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("http.token_file " + dir + "/http_token: cannot be read"), std::string::npos)
      << problems[0];
}

}  // namespace
}  // namespace fq::daemon
