// `fqd --check-config` and the start alike refuse, with exit status 2 (which the systemd unit
// does not restart) and a line naming the file, line and key, what would otherwise stop fqd at
// start: a malformed endpoint, a file the configuration names that cannot be read, a viewer
// folder that does not exist.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "tests/daemon/fqd_process.h"
#include "tests/daemon/test_keys.h"

namespace fq::test {
namespace {

// ops_config() with its control endpoint replaced.
std::string with_control(const std::string& endpoint) {
  std::string text = ops_config();
  const std::string control = "control = \"tcp://127.0.0.1:*\"";
  return text.replace(text.find(control), control.size(), "control = \"" + endpoint + "\"");
}

TEST(CheckConfig, ExitsTwoNamingTheKeyOfEachThingThatWouldStopTheStart) {
  const TestKeys keys;
  const std::string token = write_temp_file("check_token", "0123456789abcdef0123\n");
  const std::string security = "[security]\ncurve_key_file = \"" + keys.server_key +
                               "\"\nclient_keys_file = \"" + keys.client_pub + "\"\n";
  const std::string good = write_temp_file(
      "check_good.toml", ops_config(security + http_without_viewer() + "token_file = \"" + token + "\"\n"));
  const ToolRun ok = run_tool(FQD_PATH, {"--config", good, "--check-config"});
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_EQ(ok.output, good + ": configuration is valid\n");

  const std::string gone = testing::TempDir() + "/check_config_gone";
  struct Case {
    std::string name, text, key, value;
  };
  const Case cases[] = {
      {"bad_endpoint", with_control("tcp://nohost:abc"), "endpoints.control", "tcp://nohost:abc"},
      {"no_token", ops_config(http_without_viewer() + "token_file = \"" + gone + "\"\n"), "http.token_file",
       gone},
      {"no_server_key",
       ops_config("[security]\ncurve_key_file = \"" + gone + "\"\nclient_keys_file = \"" + keys.client_pub +
                  "\"\n"),
       "security.curve_key_file", gone},
      {"no_client_keys",
       ops_config("[security]\ncurve_key_file = \"" + keys.server_key + "\"\nclient_keys_file = \"" + gone +
                  "\"\n"),
       "security.client_keys_file", gone},
      {"no_web_root", ops_config("[http]\nweb_root = \"" + gone + "\"\n"), "http.web_root", gone},
  };
  for (const Case& c : cases) {
    const std::string file = write_temp_file("check_" + c.name + ".toml", c.text);
    // file:line: key value: what
    const std::regex line("fqd: invalid configuration: " + file + ":[0-9]+: " + c.key + " " + c.value +
                          ": \\S");
    const ToolRun check = run_tool(FQD_PATH, {"--config", file, "--check-config"});
    EXPECT_EQ(check.status, 2) << c.name << ": " << check.output;
    EXPECT_TRUE(std::regex_search(check.output, line)) << c.name << ": " << check.output;
    // The start gives the same line and status, not 1 (which systemd would restart in a loop).
    const ToolRun start = run_tool(FQD_PATH, {"--config", file}, 60);
    EXPECT_EQ(start.status, 2) << c.name << ": " << start.output;
    EXPECT_TRUE(std::regex_search(start.output, line)) << c.name << ": " << start.output;
  }
}

TEST(CheckConfig, EveryProblemIsALineOfItsOwn) {
  const std::string gone = testing::TempDir() + "/check_config_gone";
  std::string text = with_control("tcp://127.0.0.1");
  text += http_without_viewer() + "token_file = \"" + gone + ".token\"\ntls_cert_file = \"" + gone +
          ".crt\"\ntls_key_file = \"" + gone + ".key\"\n";
  const ToolRun r =
      run_tool(FQD_PATH, {"--config", write_temp_file("check_many.toml", text), "--check-config"});
  EXPECT_EQ(r.status, 2) << r.output;
  size_t lines = 0;
  for (size_t at = 0; (at = r.output.find("fqd: invalid configuration: ", at)) != std::string::npos; ++at)
    ++lines;
  EXPECT_EQ(lines, 4u) << r.output;
  for (const char* key : {"endpoints.control", "http.token_file", "http.tls_cert_file", "http.tls_key_file"})
    EXPECT_NE(r.output.find(key), std::string::npos) << key << " not in\n" << r.output;
}

}  // namespace
}  // namespace fq::test

namespace fq::test {
namespace {

// systemd's LoadCredential=: the configuration names `credential:NAME`, fqd finds the file in
// $CREDENTIALS_DIRECTORY; check and start alike.
TEST(CheckConfig, ACredentialIsReadFromCredentialsDirectory) {
  const TestKeys keys;
  const std::string dir = testing::TempDir() + "/check_credentials";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(keys.server_key, dir + "/curve_key",
                             std::filesystem::copy_options::overwrite_existing);
  std::ofstream(dir + "/http_token") << "0123456789abcdef0123\n";
  const std::string file = write_temp_file(
      "check_credentials.toml",
      ops_config("[security]\ncurve_key_file = \"credential:curve_key\"\nclient_keys_file = \"" +
                 keys.client_pub + "\"\n" + http_without_viewer() +
                 "token_file = \"credential:http_token\"\n"));
  const std::string set = "CREDENTIALS_DIRECTORY=" + dir;
  const ToolRun ok = run_tool("/usr/bin/env", {set, FQD_PATH, "--config", file, "--check-config"});
  EXPECT_EQ(ok.status, 0) << ok.output;
  {
    FqdProcess fqd({"--config", file}, "CREDENTIALS_DIRECTORY=" + shell_words(dir, {}));
    EXPECT_FALSE(fqd.endpoint("control").empty()) << "fqd did not start with its credentials";
  }
  // Without the variable: exit 2 naming the key and the credential.
  const ToolRun unset =
      run_tool("/usr/bin/env", {"-u", "CREDENTIALS_DIRECTORY", FQD_PATH, "--config", file, "--check-config"});
  EXPECT_EQ(unset.status, 2) << unset.output;
  EXPECT_NE(unset.output.find("security.curve_key_file credential:curve_key: names a credential, but "
                              "$CREDENTIALS_DIRECTORY is not set"),
            std::string::npos)
      << unset.output;
  // A credential missing from the directory: exit 2 naming the file, at check and at start.
  std::filesystem::remove(dir + "/http_token");
  for (const bool check : {true, false}) {
    std::vector<std::string> args{set, FQD_PATH, "--config", file};
    if (check) args.emplace_back("--check-config");
    const ToolRun missing = run_tool("/usr/bin/env", args, 60);
    EXPECT_EQ(missing.status, 2) << missing.output;
    EXPECT_NE(missing.output.find("http.token_file " + dir + "/http_token: cannot be read"),
              std::string::npos)
        << missing.output;
  }
}

}  // namespace
}  // namespace fq::test
