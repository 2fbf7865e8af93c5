// fqd's service conventions: the config lookup order (--config, $FQ_CONFIG, /etc/fq/fqd.toml,
// built-in defaults) from any working directory, SIGHUP reloading the file (all of it or, for a
// bad file or a restart-only change, nothing; it never stops fqd), and the periodic [stats] log line.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "daemon/config/config.h"
#include "daemon/service/config_lookup.h"
#include "tests/daemon/fqd_process.h"

namespace fq::test {
namespace {

TEST(ConfigLookup, FlagThenEnvironmentThenSystemFileThenDefaults) {
  const std::string system = write_temp_file("lookup_system.toml", "");
  const std::string missing = testing::TempDir() + "/no_such_fqd.toml";
  EXPECT_EQ(daemon::find_config("a.toml", "b.toml", system).path, "a.toml");
  EXPECT_EQ(daemon::find_config("", "b.toml", system).path, "b.toml");
  EXPECT_EQ(daemon::find_config("", "b.toml", system).from, "$FQ_CONFIG");
  EXPECT_EQ(daemon::find_config("", "", system).path, system);
  EXPECT_EQ(daemon::find_config("", nullptr, system).path, system);
  const daemon::ConfigSource none = daemon::find_config("", nullptr, missing);
  EXPECT_EQ(none.path, "");
  EXPECT_EQ(none.from, "built-in defaults");
}

TEST(ConfigLookup, NoFileNeededFromAnyDirectory) {
  const std::string expected = std::filesystem::exists(daemon::kSystemConfigPath)
                                   ? std::string(daemon::kSystemConfigPath)
                                   : "built-in defaults";
  const ToolRun r = run_tool(
      "/bin/sh", {"-c", "cd / && unset FQ_CONFIG && exec " + shell_words(FQD_PATH, {"--check-config"})});
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output, expected + ": configuration is valid\n");
  const ToolRun bad = run_tool("/bin/sh", {"-c", "cd / && FQ_CONFIG=/no/such/fqd.toml exec " +
                                                     shell_words(FQD_PATH, {"--check-config"})});
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("/no/such/fqd.toml"), std::string::npos) << bad.output;
}

TEST(ConfigLookup, FqConfigServesFromAnotherDirectory) {
  const std::string config = write_temp_file("lookup_env.toml", ops_config());
  FqdProcess fqd({}, "cd / && export FQ_CONFIG='" + config + "' &&");
  ASSERT_FALSE(fqd.endpoint("ingest").empty()) << "fqd did not start from / with $FQ_CONFIG";
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 2).status, 0);
  EXPECT_TRUE(eventually([&] {
    const ToolRun r =
        run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "counters", "cam0", "--json"});
    return r.status == 0 && nlohmann::json::parse(r.output).at("streams").at(0).at("frames_out") == 2;
  }));
  EXPECT_EQ(fqd.stop(), 0);
}

std::string sigma_s(const FqdProcess& fqd, const std::string& stream) {
  const ToolRun r = run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "params", stream});
  const size_t at = r.output.find("sigma_s = ");
  return r.status != 0 || at == std::string::npos
             ? "?"
             : r.output.substr(at + 10, r.output.find('\n', at) - at - 10);
}

TEST(Service, SighupReloadsStreamSettingsAndSurvivesABadFile) {
  const std::string log = testing::TempDir() + "/fqd_sighup.log";
  const std::string config =
      write_temp_file("sighup.toml", ops_config("[streams.cam0.filter]\nsigma_s = 2.5\n"));
  FqdProcess fqd({"--config", config, "--log-level", "info"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("control").empty());
  EXPECT_EQ(sigma_s(fqd, "cam0"), "2.5");

  write_temp_file("sighup.toml",
                  ops_config("[streams.cam0.filter]\nsigma_s = 4\n[streams.cam9]\nbudget_ms = 50\n"));
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] { return sigma_s(fqd, "cam0") == "4"; })) << read_text_file(log);
  EXPECT_EQ(sigma_s(fqd, "cam9"), "1.5");  // newly configured stream, defaults' sigma_s

  write_temp_file("sighup.toml", "this is [not toml");
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log).find("not reloaded, settings unchanged") != std::string::npos;
  })) << read_text_file(log);
  EXPECT_TRUE(fqd.alive());
  EXPECT_EQ(sigma_s(fqd, "cam0"), "4");
  EXPECT_EQ(fqd.stop(), 0);
}

std::string http_status(const FqdProcess& fqd, const std::string& path, const std::string& token) {
  return run_tool("/usr/bin/curl", {"-s", "-o", "/dev/null", "-w", "%{http_code}", "-H",
                                    "Authorization: Bearer " + token, fqd.endpoint("http") + path})
      .output;
}

bool lists(const FqdProcess& fqd, const std::string& stream) {
  const ToolRun r = run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "streams"});
  return r.output.find(stream + "\n") != std::string::npos;
}

TEST(Service, SighupAppliesCapsAccessAndLogLevelLiveOrRefusesNamingTheSetting) {
  const std::string log = testing::TempDir() + "/fqd_sighup_live.log";
  const std::string t1 = "0123456789abcdef-first", t2 = "0123456789abcdef-second";
  const std::string http = http_without_viewer() + "token_file = \"";
  auto config = [&](const std::string& level, const std::string& allowed, int idle,
                    const std::string& token) {
    std::string text = ops_config("[caps]\nallowed_streams = [\"" + allowed +
                                  "\"]\nstream_idle_s = " + std::to_string(idle) + "\n" + http +
                                  write_temp_file("live_token", token) + "\"\n");
    return "log_level = \"" + level + "\"\n" + text.substr(text.find('\n', text.find("log_level")) + 1);
  };
  const std::string file = write_temp_file("sighup_live.toml", config("warn", "cam*", 0, t1));
  FqdProcess fqd({"--config", file}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("http").empty()) << read_text_file(log);
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 2).status, 0);
  EXPECT_TRUE(eventually([&] { return lists(fqd, "cam0"); }));

  // Live: the allow-list, the idle time, the token and the log level.
  write_temp_file("sighup_live.toml", config("info", "other*", 1, t2));
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] { return read_text_file(log).find("SIGHUP: reloaded") != std::string::npos; }))
      << read_text_file(log);
  EXPECT_EQ(http_status(fqd, "/streams", t1), "401");
  EXPECT_EQ(http_status(fqd, "/streams", t2), "200");
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam1", 1).status, 0);
  EXPECT_TRUE(eventually([&] {
    const ToolRun m = run_tool(
        "/usr/bin/curl", {"-s", "-H", "Authorization: Bearer " + t2, fqd.endpoint("http") + "/metrics"});
    return m.output.find("fq_refused_total{reason=\"not_allowed\"} 1") != std::string::npos;
  }));
  EXPECT_FALSE(lists(fqd, "cam1"));
  EXPECT_TRUE(eventually([&] { return !lists(fqd, "cam0"); }))
      << "cam0 did not expire after stream_idle_s = 1";
  EXPECT_NE(read_text_file(log).find("stream 'cam0' expired"), std::string::npos)
      << "an info line after log_level = info";

  // Restart-only: refused whole, naming it; the stream in the same file is not applied.
  write_temp_file("sighup_live.toml", config("info", "other*", 1, t2) +
                                          "[threads]\ndecode = 3\n[streams.other1]\nbudget_ms = 50\n");
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log).find("threads.decode changed, which takes effect only at a restart") !=
           std::string::npos;
  })) << read_text_file(log);
  EXPECT_FALSE(lists(fqd, "other1"));
  // Empty: refused.
  write_temp_file("sighup_live.toml", "# nothing here\n");
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] { return read_text_file(log).find("has no settings") != std::string::npos; }))
      << read_text_file(log);
  EXPECT_EQ(http_status(fqd, "/streams", t2), "200");
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(Service, SighupAfterTheFileWasRemovedKeepsRunning) {
  const std::string log = testing::TempDir() + "/fqd_sighup_gone.log";
  const std::string config = write_temp_file("sighup_gone.toml", ops_config());
  FqdProcess fqd({"--config", config, "--log-level", "info"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("control").empty());
  std::filesystem::remove(config);
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] { return read_text_file(log).find("not reloaded") != std::string::npos; }))
      << read_text_file(log);
  EXPECT_TRUE(fqd.alive());
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(Service, StatsLogLinePerActiveStream) {
  const std::string log = testing::TempDir() + "/fqd_stats.log";
  const std::string config = write_temp_file("stats.toml", ops_config("[stats]\ninterval_s = 0.2\n"));
  FqdProcess fqd({"--config", config, "--log-level", "info"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("ingest").empty());
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 6).status, 0);
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log).find("[stats] stream=cam0 fps=") != std::string::npos;
  })) << read_text_file(log);
  const std::string text = read_text_file(log);
  const size_t at = text.find("[stats] stream=cam0");
  const std::string line = text.substr(at, text.find('\n', at) - at);
  for (const char* field : {" p99=", "ms late=", " superseded=", " stale=", " errors="})
    EXPECT_NE(line.find(field), std::string::npos) << line;
  EXPECT_EQ(fqd.stop(), 0);
}

}  // namespace
}  // namespace fq::test

namespace fq::test {
namespace {

std::string config_error(const std::string& text) {
  daemon::DaemonConfig c;
  const Status s = daemon::parse_config(text, "t.toml", c);
  EXPECT_FALSE(s.ok()) << "accepted: " << text;
  return s.message();
}

TEST(ServiceConfig, HttpAndStatsKeysAreChecked) {
  daemon::DaemonConfig c;
  EXPECT_TRUE(c.http.listen.empty());  // no HTTP listener unless configured
  EXPECT_EQ(c.stats.interval_s, 60.0);
  ASSERT_TRUE(
      daemon::parse_config("[http]\nlisten = \"[::1]:0\"\n[stats]\ninterval_s = 0\n", "t.toml", c).ok());
  EXPECT_EQ(c.http.listen, "[::1]:0");
  EXPECT_EQ(c.stats.interval_s, 0.0);
  EXPECT_NE(config_error("[http]\nlisten = \"8080\"\n").find("http.listen"), std::string::npos);
  EXPECT_NE(config_error("[http]\nlisten = \"127.0.0.1:70000\"\n").find("http.listen"), std::string::npos);
  EXPECT_NE(config_error("[http]\nweb_root = \"\"\n").find("http.web_root"), std::string::npos);
  EXPECT_NE(config_error("[http]\nlisen = \"127.0.0.1:1\"\n").find("lisen"), std::string::npos);
  EXPECT_NE(config_error("[stats]\ninterval_s = -1\n").find("stats.interval_s"), std::string::npos);
}

}  // namespace
}  // namespace fq::test
