// fqd as a well-behaved service: flag overrides and usage errors (exit 2), the version and what
// is off in the first log lines, the JSON log format, an audit line per settings change, a
// warning when a stream is mostly late, systemd readiness (NOTIFY_SOCKET) and --shard.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <sstream>

#include "common/version.h"
#include "daemon/service/stream_shard.h"
#include "tests/daemon/fqd_process.h"

namespace fq::test {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(ServiceFlags, OverridesRunAndUsageErrorsExit2) {
  const std::string config = write_temp_file("flags.toml", ops_config());
  // Before the flags existed, CLI11 ended this with "The following arguments were not
  // expected" and exit 109, which systemd's RestartPreventExitStatus=2 restarted in a loop.
  FqdProcess fqd(
      {"--config", config, "--engine", "cpu", "--http-listen", "127.0.0.1:0", "--log-format", "json"});
  ASSERT_FALSE(fqd.endpoint("http").empty()) << "--http-listen did not open an HTTP listener";
  EXPECT_EQ(fqd.stop(), 0);
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--no-such-flag"},
                                              {"--engine", "gpu"},
                                              {"--http-listen", "8080"},
                                              {"--log-format", "xml"},
                                              {"--log-level", "loud"},
                                              {"--shard", "3/3"},
                                              {"stray"}}) {
    std::vector<std::string> args{"--config", config, "--check-config"};
    args.insert(args.end(), bad.begin(), bad.end());
    const ToolRun r = run_tool(FQD_PATH, args);
    EXPECT_EQ(r.status, 2) << bad[0] << ": " << r.output;
    EXPECT_FALSE(r.output.empty()) << bad[0];
  }
  EXPECT_EQ(run_tool(FQD_PATH, {"--help"}).status, 0);
  const ToolRun version = run_tool(FQD_PATH, {"--version"});
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.output, version_line("fqd") + "\n");
}

TEST(ServiceFlags, FirstLinesSayVersionAndWhatIsOff) {
  const std::string log = testing::TempDir() + "/fqd_first_lines.log";
  const std::string config = write_temp_file("first_lines.toml", ops_config("[stats]\ninterval_s = 0\n"));
  FqdProcess fqd({"--config", config, "--log-level", "info"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("ingest").empty());
  EXPECT_EQ(fqd.stop(), 0);
  const std::vector<std::string> lines = lines_of(read_text_file(log));
  ASSERT_GE(lines.size(), 4u) << read_text_file(log);
  EXPECT_NE(lines[0].find(version_line("fqd") + " starting, pid "), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("configuration from --config (" + config + ")"), std::string::npos) << lines[0];
  const std::string head = lines[1] + "\n" + lines[2] + "\n" + lines[3];
  for (const char* off : {"HTTP off", "security off", "[stats] lines off"})
    EXPECT_NE(head.find(off), std::string::npos) << off << " not in\n" << head;
  const std::string text = read_text_file(log);
  EXPECT_NE(
      text.find(built_with_cuda() ? "fqd: CUDA off: engine.kind = cpu" : "fqd: CUDA absent: this build"),
      std::string::npos)
      << text;
}

TEST(ServiceFlags, JsonLogLinesParse) {
  const std::string log = testing::TempDir() + "/fqd_json.log";
  const std::string config = write_temp_file("json_log.toml", ops_config());
  FqdProcess fqd({"--config", config, "--log-level", "info", "--log-format", "json"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("control").empty());
  // A stream id with a quote and a backslash must not break the line's JSON.
  ASSERT_EQ(
      run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "set", "--create", "cam\"0\\", "sigma_s=2"})
          .status,
      0);
  EXPECT_EQ(fqd.stop(), 0);
  const std::vector<std::string> lines = lines_of(read_text_file(log));
  ASSERT_GE(lines.size(), 3u);
  bool audit = false;
  for (const std::string& l : lines) {
    const nlohmann::json j = nlohmann::json::parse(l, nullptr, false);
    ASSERT_TRUE(j.is_object()) << l;
    EXPECT_TRUE(j.contains("time") && j.contains("level") && j.contains("msg")) << l;
    audit = audit || j.value("msg", "") == "cam\"0\\x5c sigma_s 1.5 -> 2 (control)";
  }
  EXPECT_EQ(nlohmann::json::parse(lines[0]).at("msg").get<std::string>().rfind(version_line("fqd"), 0), 0u)
      << lines[0];
  EXPECT_TRUE(audit) << read_text_file(log);
}

TEST(ServiceFlags, EveryControlAndReloadChangeIsAudited) {
  const std::string log = testing::TempDir() + "/fqd_audit.log";
  const std::string config =
      write_temp_file("audit.toml", ops_config("[streams.cam0.filter]\nsigma_s = 1.5\n"));
  FqdProcess fqd({"--config", config, "--log-level", "info"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("control").empty());
  const ToolRun set = run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "set", "cam0", "sigma_s=3",
                                            "mode=bf", "result_form=mesh"});
  ASSERT_EQ(set.status, 0) << set.output;
  write_temp_file("audit.toml", ops_config("[streams.cam0]\nbudget_ms = 50\n"));
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] { return read_text_file(log).find("(reload)") != std::string::npos; }));
  EXPECT_EQ(fqd.stop(), 0);
  const std::string text = read_text_file(log);
  for (const char* line : {"cam0 sigma_s 1.5 -> 3 (control)", "cam0 mode qf+ -> bf (control)",
                           "cam0 result_form positions -> mesh (control)", "cam0 sigma_s 3 -> 1.5 (reload)",
                           "cam0 budget_ms 60000 -> 50 (reload)"})
    EXPECT_NE(text.find(line), std::string::npos) << line << " not in\n" << text;
  EXPECT_EQ(text.find("sigma_r"), std::string::npos) << "an unchanged key was logged:\n" << text;
}

TEST(ServiceFlags, MostlyLateStreamWarns) {
  const std::string log = testing::TempDir() + "/fqd_late.log";
  // The CPU engine filters clean fandisk in 20-40 ms on the 2-core development machine: every
  // result is over a 10 ms budget, while frames 333 ms apart find the engine free after a decode of
  // about 1 ms (not dropped stale).
  const std::string config = write_temp_file(
      "late.toml",
      ops_config("[streams.cam0]\ncompute = \"filter\"\nbudget_ms = 10\n[stats]\ninterval_s = 2\n"));
  FqdProcess fqd({"--config", config, "--log-level", "info"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("ingest").empty());
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 12, 3).status, 0);
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log).find("results late in the last") != std::string::npos;
  })) << read_text_file(log);
  EXPECT_EQ(fqd.stop(), 0);
  const std::string text = read_text_file(log);
  const size_t at = text.find("stream cam0: ");
  ASSERT_NE(at, std::string::npos) << text;
  EXPECT_NE(text.rfind("[warning]", at), std::string::npos) << text;
  EXPECT_NE(text.find("(budget 10 ms", at), std::string::npos) << text;
}

// A datagram socket standing in for systemd's notify socket.
class NotifySocket {
 public:
  NotifySocket() : path_(testing::TempDir() + "/fqd_notify_" + std::to_string(getpid())) {
    unlink(path_.c_str());
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path_.c_str(), sizeof addr.sun_path - 1);
    bound_ = bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
    timeval tv{30, 0};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~NotifySocket() {
    close(fd_);
    unlink(path_.c_str());
  }
  bool bound() const { return bound_; }
  const std::string& path() const { return path_; }
  /// The next datagram ("" after 30 s without one).
  std::string next() {
    char buf[4096];
    const ssize_t n = recv(fd_, buf, sizeof buf, 0);
    return n > 0 ? std::string(buf, static_cast<size_t>(n)) : "";
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool bound_ = false;
};

TEST(ServiceFlags, NotifiesSystemdReadyReloadingStopping) {
  NotifySocket notify;
  ASSERT_TRUE(notify.bound());
  const std::string config = write_temp_file("notify.toml", ops_config());
  FqdProcess fqd({"--config", config}, "NOTIFY_SOCKET='" + notify.path() + "'");
  ASSERT_FALSE(fqd.endpoint("ingest").empty());
  const std::string ready = notify.next();
  EXPECT_EQ(ready.rfind("READY=1\nSTATUS=serving {", 0), 0u) << ready;
  EXPECT_NE(ready.find(fqd.endpoint("ingest")), std::string::npos) << ready;
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_EQ(notify.next(), "RELOADING=1");
  EXPECT_EQ(notify.next(), "READY=1");
  EXPECT_EQ(fqd.stop(), 0);
  EXPECT_EQ(notify.next(), "STOPPING=1");
}

TEST(ServiceFlags, ShardKeepsTheStreamsThatHashToIt) {
  std::string streams;
  for (int i = 0; i < 8; ++i) streams += std::string(i ? ", " : "") + "\"cam" + std::to_string(i) + "\"";
  const std::string config = write_temp_file(
      "shard.toml", ops_config("[ingest]\nconnect = [\"tcp://127.0.0.1:1\"]\nstreams = [" + streams + "]\n"));
  const ToolRun map = run_tool(FQD_PATH, {"--config", config, "--shard-map", "3"});
  ASSERT_EQ(map.status, 0) << map.output;
  std::string expected, mine;
  for (int i = 0; i < 8; ++i) {
    const std::string id = "cam" + std::to_string(i);
    expected += id + " " + std::to_string(daemon::shard_of(id, 3)) + "\n";
    if (daemon::shard_of(id, 3) == 1) mine += (mine.empty() ? "" : ", ") + id;
  }
  EXPECT_EQ(map.output, expected);
  const std::string log = testing::TempDir() + "/fqd_shard.log";
  FqdProcess fqd({"--config", config, "--log-level", "info", "--shard", "fqd-1/3"}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("ingest").empty()) << read_text_file(log);
  EXPECT_EQ(fqd.stop(), 0);
  EXPECT_NE(read_text_file(log).find("shard fqd-1/3: serves [" + mine + "]"), std::string::npos)
      << read_text_file(log);
}

}  // namespace
}  // namespace fq::test
