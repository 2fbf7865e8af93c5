// What the start reads or binds beyond the TOML text, checked before it (config_check.h): every
// endpoint parsed as ZeroMQ parses it, every file the configuration names opened and read, one
// line per problem naming the file, line and key.
#include "daemon/service/config_check.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/curve_keys.h"
#include "daemon/service/zmq_endpoint.h"

namespace fq::daemon {
namespace {

std::string temp_path(const std::string& name) { return testing::TempDir() + "/config_check_" + name; }

std::string write_file(const std::string& name, const std::string& text) {
  std::string path = temp_path(name);
  std::ofstream(path) << text;
  return path;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  return text;
}

// The problems of `text` read as the file check.toml.
std::vector<std::string> problems_of(const std::string& text) {
  DaemonConfig c;
  const Status s = parse_config(text, "check.toml", c);
  EXPECT_TRUE(s.ok()) << s.message();
  return config_problems(c);
}

TEST(ConfigCheck, EndpointsAreParsedAsZeroMqParsesThem) {
  for (const char* good :
       {"tcp://127.0.0.1:5555", "tcp://*:*", "tcp://*:0", "tcp://[::1]:5555", "tcp://lo:5555",
        "tcp://fq.example.org:5555", "ipc:///run/fq/ingest", "ipc://*", "inproc://fq"})
    EXPECT_EQ(endpoint_problem(good, EndpointUse::kBind), "") << good;
  for (const char* good :
       {"tcp://10.0.0.1:5555", "tcp://eth0;10.0.0.1:5555", "tcp://[::1]:1", "ipc:///run/fq/p"})
    EXPECT_EQ(endpoint_problem(good, EndpointUse::kConnect), "") << good;
  for (const char* bad : {"tcp://nohost:abc", "tcp://127.0.0.1", "tcp://:5555", "tcp://127.0.0.1:70000",
                          "tcp://127.0.0.1:", "tcp://127.0.0.1:-1", "tcp://[::1:5555", "localhost:5555",
                          "udp://127.0.0.1:5555", "ipc://", "inproc://"})
    EXPECT_NE(endpoint_problem(bad, EndpointUse::kBind), "") << bad;
  for (const char* bad : {"tcp://*:5555", "tcp://h:*", "tcp://h:0", "tcp://h"})
    EXPECT_NE(endpoint_problem(bad, EndpointUse::kConnect), "") << bad;
  EXPECT_NE(endpoint_problem("ipc:///" + std::string(120, 'x'), EndpointUse::kBind), "") << "over sun_path";
  EXPECT_EQ(endpoint_problem("tcp://nohost:abc", EndpointUse::kBind),
            "has port 'abc', not a number in 0..65535 or *");
}

TEST(ConfigCheck, EachBadEndpointIsALineWithItsKeyAndLine) {
  const std::vector<std::string> p = problems_of(
      "[endpoints]\ningest = \"tcp://nohost:abc\"\ncontrol = \"tcp://127.0.0.1\"\n"
      "[ingest]\nconnect = [\"tcp://a:1\",\n  \"tcp://*:2\"]\n");
  ASSERT_EQ(p.size(), 3u) << joined(p);
  EXPECT_EQ(p[0],
            "check.toml:2: endpoints.ingest tcp://nohost:abc: has port 'abc', not a number in 0..65535 or *");
  EXPECT_EQ(p[1].rfind("check.toml:3: endpoints.control tcp://127.0.0.1: has no port", 0), 0u) << p[1];
  EXPECT_EQ(p[2].rfind("check.toml:6: ingest.connect tcp://*:2: ", 0), 0u) << p[2];
  EXPECT_TRUE(problems_of("").empty()) << "the built-in endpoints are well-formed";
}

TEST(ConfigCheck, EveryFileTheConfigNamesIsOpenedAndRead) {
  CurveKeyPair server, client;
  ASSERT_TRUE(make_curve_key_pair(server).ok());
  ASSERT_TRUE(make_curve_key_pair(client).ok());
  const std::string key = temp_path("server.key"), pub = temp_path("clients.pub");
  ASSERT_TRUE(write_curve_key_file(key, server).ok());
  ASSERT_TRUE(write_curve_key_file(pub, {client.public_key, ""}).ok());
  const std::string token = write_file("token", "0123456789abcdef0123\n");
  const std::string web = temp_path("web");
  std::filesystem::create_directories(web);
  const std::vector<std::string> fine =
      problems_of("[security]\ncurve_key_file = \"" + key + "\"\nclient_keys_file = \"" + pub +
                  "\"\n[http]\n" + "token_file = \"" + token + "\"\nweb_root = \"" + web + "\"\n");
  EXPECT_TRUE(fine.empty()) << joined(fine);

  const std::string gone = temp_path("gone");
  const std::vector<std::string> p =
      problems_of("[security]\ncurve_key_file = \"" + gone + ".key\"\nclient_keys_file = \"" + gone +
                  ".pub\"\n[http]\n" + "token_file = \"" + gone + ".token\"\ntls_cert_file = \"" + gone +
                  ".crt\"\ntls_key_file = \"" + gone + ".pem\"\nweb_root = \"" + gone + "_web\"\n");
  const std::string missing = ": cannot be read: No such file or directory";
  const std::vector<std::string> expected = {
      "check.toml:2: security.curve_key_file " + gone + ".key" + missing,
      "check.toml:3: security.client_keys_file " + gone + ".pub" + missing,
      "check.toml:5: http.token_file " + gone + ".token" + missing,
      "check.toml:6: http.tls_cert_file " + gone + ".crt" + missing,
      "check.toml:7: http.tls_key_file " + gone + ".pem" + missing,
      "check.toml:8: http.web_root " + gone +
          "_web: cannot be opened as a folder: No such file or directory"};
  EXPECT_EQ(p, expected) << joined(p);
}

// What the start would refuse in a file that opens: a key file without its secret, CURVE on
// without client keys, a token too short, a folder where a file belongs, a certificate that is not one.
TEST(ConfigCheck, ContentsAreCheckedAsTheStartReadsThem) {
  CurveKeyPair server;
  ASSERT_TRUE(make_curve_key_pair(server).ok());
  const std::string pub = temp_path("only.pub");
  ASSERT_TRUE(write_curve_key_file(pub, {server.public_key, ""}).ok());
  const std::string short_token = write_file("short_token", "abc\n"),
                    not_pem = write_file("not.pem", "hello\n");
  const std::vector<std::string> p =
      problems_of("[security]\ncurve_key_file = \"" + pub + "\"\n[http]\ntoken_file = \"" + short_token +
                  "\"\ntls_cert_file = \"" + not_pem + "\"\ntls_key_file = \"" + testing::TempDir() + "\"\n");
  ASSERT_EQ(p.size(), 4u) << joined(p);
  EXPECT_EQ(p[0].rfind("check.toml:2: security.curve_key_file: key file " + pub + ": no secret key", 0), 0u)
      << p[0];
  EXPECT_EQ(p[1].rfind("check.toml:1: security.client_keys_file: is not set", 0), 0u) << p[1];
  EXPECT_EQ(
      p[2].rfind("check.toml:4: http.token_file " + short_token + ": the token (first line) must be", 0), 0u)
      << p[2];
  EXPECT_NE(p[3].find("check.toml:6: http.tls_key_file " + testing::TempDir()), std::string::npos) << p[3];
  EXPECT_NE(p[3].find("is a folder, not a file"), std::string::npos) << p[3];

  const std::vector<std::string> tls =
      problems_of("[http]\ntls_cert_file = \"" + not_pem + "\"\ntls_key_file = \"" + not_pem + "\"\n");
  ASSERT_EQ(tls.size(), 1u) << joined(tls);
  EXPECT_EQ(tls[0].rfind("check.toml:2: http.tls_cert_file " + not_pem + ": ", 0), 0u) << tls[0];
}

// security.control_keys_file: read like client_keys_file, and only with CURVE on.
TEST(ConfigCheck, TheControlKeyListIsReadAndNeedsCurve) {
  CurveKeyPair server, operator_key;
  ASSERT_TRUE(make_curve_key_pair(server).ok());
  ASSERT_TRUE(make_curve_key_pair(operator_key).ok());
  const std::string pair = temp_path("control_server.key"), ops = temp_path("operators.pub");
  ASSERT_TRUE(write_curve_key_file(pair, server).ok());
  ASSERT_TRUE(write_curve_key_file(ops, {operator_key.public_key, ""}).ok());
  const std::string none = write_file("no_keys.pub", "# nobody yet\n");
  const std::string security =
      "[security]\ncurve_key_file = \"" + pair + "\"\nclient_keys_file = \"" + ops + "\"\n";
  EXPECT_TRUE(problems_of(security + "control_keys_file = \"" + ops + "\"\n").empty());
  std::vector<std::string> p = problems_of(security + "control_keys_file = \"" + none + "\"\n");
  ASSERT_EQ(p.size(), 1u) << joined(p);
  EXPECT_EQ(p[0].rfind("check.toml:4: security.control_keys_file " + none + ": lists no client key", 0), 0u)
      << p[0];
  p = problems_of("[security]\ncontrol_keys_file = \"" + ops + "\"\n");
  ASSERT_EQ(p.size(), 1u) << joined(p);
  EXPECT_EQ(
      p[0].rfind("check.toml:2: security.control_keys_file: is set but security.curve_key_file is not", 0),
      0u)
      << p[0];
}

// fqd serves how to install the viewer when its default folder has none; only a folder the
// file names must exist.
TEST(ConfigCheck, OnlyAViewerFolderTheFileNamesMustExist) {
  DaemonConfig defaults;
  defaults.http.web_root = "/no/such/fq/viewer";
  EXPECT_TRUE(config_problems(defaults).empty());
  EXPECT_EQ(defaults.where("http.web_root"), "built-in defaults");
}

}  // namespace
}  // namespace fq::daemon
