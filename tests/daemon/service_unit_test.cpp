// The pieces of fqd's service behaviour that need no process: the settings audit, the late
// warning, the "off" lines, the stream shard hash, /proc/self/stat and the viewer's default folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "daemon/config/service_config.h"
#include "daemon/control/late_warning.h"
#include "daemon/control/settings_audit.h"
#include "daemon/http/web_root.h"
#include "daemon/pipeline/process_stats.h"
#include "daemon/service/startup_report.h"
#include "daemon/service/stream_shard.h"

namespace fq::daemon {
namespace {

TEST(SettingsAudit, NamesEachChangedKeyWithOldAndNewValue) {
  StreamSettings before, after;
  EXPECT_TRUE(settings_changes(before, after).empty());
  after.params.filtering.sigma_s = 3.0f;
  after.params.filtering.method = FilterMethod::kBilateral;
  after.budget_ms = 33;
  after.output.chunks = 4;
  const std::vector<std::string> changes = settings_changes(before, after);
  const std::vector<std::string> expected{"mode qf+ -> bf", "sigma_s 1.5 -> 3", "budget_ms 100 -> 33",
                                          "chunks same -> 4"};
  EXPECT_EQ(changes, expected);
}

TEST(LateWarning, OnlyWhenMostResultsOfTheIntervalWereLate) {
  StreamSnapshot now;
  now.stream_id = "cam0";
  now.counters.frames_out = 10;
  now.counters.late = 9;
  now.stages["engine"].p50_ms = 250;
  now.stages["receive_to_publish"].p99_ms = 300;
  StreamCounters before;
  before.frames_out = 1;
  before.late = 0;
  const auto w = late_warning(now, before, 60, 100);
  ASSERT_TRUE(w);
  EXPECT_EQ(*w,
            "stream cam0: 9 of 9 results late in the last 60 s (budget 100 ms, receive->publish p99 300 ms, "
            "engine p50 250 ms, wait p50 0 ms): the engine alone takes longer than the budget: raise "
            "budget_ms, lower the sigmas or use a GPU engine");
  before.late = 5;  // 4 of 9: not mostly
  EXPECT_FALSE(late_warning(now, before, 60, 100));
  before = {};
  before.frames_out = 8;  // 2 results: too few to judge
  EXPECT_FALSE(late_warning(now, before, 60, 100));
}

TEST(StartupReport, SaysWhatIsOff) {
  DaemonConfig c;
  std::vector<std::string> off = off_lines(c);
  ASSERT_EQ(off.size(), 2u);
  EXPECT_EQ(off[0].rfind("fqd: HTTP off", 0), 0u);
  EXPECT_EQ(off[1].rfind("fqd: security off", 0), 0u);
  c.http.listen = "127.0.0.1:0";
  c.stats.interval_s = 0;
  off = off_lines(c);
  ASSERT_EQ(off.size(), 2u);
  EXPECT_EQ(off[1].rfind("fqd: [stats] lines off", 0), 0u);
  EXPECT_EQ(cuda_line(c.engine, {"cuda:0 NVIDIA H100"}), "");
  EXPECT_NE(cuda_line(c.engine, {"cpu"}).find("CUDA"), std::string::npos);
}

TEST(StreamShard, Fnv1aAndParsing) {
  // FNV-1a 32-bit reference values.
  EXPECT_EQ(stream_hash(""), 0x811c9dc5u);
  EXPECT_EQ(stream_hash("a"), 0xe40c292cu);
  EXPECT_EQ(stream_hash("foobar"), 0xbf9cf968u);
  uint32_t k = 9, n = 9;
  ASSERT_TRUE(parse_shard("2/3", k, n).ok());
  EXPECT_EQ(k, 2u);
  EXPECT_EQ(n, 3u);
  ASSERT_TRUE(parse_shard("fqd-eu-1/4", k, n).ok());
  EXPECT_EQ(k, 1u);
  for (const char* bad : {"3/3", "1", "a/2", "1/0", "-1/2", "1/2x", "/2"})
    EXPECT_FALSE(parse_shard(bad, k, n).ok()) << bad;
}

TEST(StreamShard, EveryStreamInExactlyOneShard) {
  SubIngestConfig all;
  all.connect = {"tcp://producer:7000"};
  for (int i = 0; i < 50; ++i) all.streams.push_back("cam" + std::to_string(i));
  size_t total = 0;
  for (uint32_t k = 0; k < 4; ++k) {
    SubIngestConfig mine = all;
    const std::vector<std::string> kept = keep_shard(mine, k, 4);
    EXPECT_FALSE(kept.empty());
    for (const std::string& id : kept) EXPECT_EQ(shard_of(id, 4), k);
    total += kept.size();
  }
  EXPECT_EQ(total, all.streams.size());
  SubIngestConfig one;
  one.connect = {"tcp://producer:7000"};
  one.streams = {"cam0"};
  EXPECT_TRUE(keep_shard(one, (shard_of("cam0", 2) + 1) % 2, 2).empty());
  EXPECT_TRUE(one.connect.empty()) << "a shard without streams must not subscribe to all of them";
}

}  // namespace
}  // namespace fq::daemon

namespace fq::daemon {
namespace {

TEST(ProcessStats, ParsesProcStatAfterTheCommandName) {
  // A command name with spaces and a ')' of its own; fields as the kernel writes them.
  std::string stat =
      "4242 (fq d) x) S 1 4242 4242 0 -1 4194560 1000 0 0 0 250 50 0 0 20 0 17 0 360000 "
      "123456789 2048";
  for (int i = 0; i < 27; ++i) stat += " 0";
  const ProcessStats s = parse_proc_stat(stat, 100, 4096, 1.7e9);
  ASSERT_TRUE(s.ok);
  EXPECT_DOUBLE_EQ(s.cpu_seconds, 3.0);  // (250 + 50) ticks at 100 a second
  EXPECT_EQ(s.threads, 17u);
  EXPECT_DOUBLE_EQ(s.start_time_seconds, 1.7e9 + 3600.0);
  EXPECT_EQ(s.virtual_bytes, 123456789u);
  EXPECT_EQ(s.resident_bytes, 2048u * 4096u);
  EXPECT_FALSE(parse_proc_stat("garbage", 100, 4096, 0).ok);
  EXPECT_TRUE(process_metrics_text(ProcessStats{}).empty());
  const std::string text = process_metrics_text(s);
  EXPECT_NE(text.find("# TYPE process_cpu_seconds_total counter\nprocess_cpu_seconds_total 3\n"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace fq::daemon

namespace fq::daemon {
namespace {

TEST(WebRoot, DefaultFindsTheViewerInstalledBesideFqd) {
  EXPECT_EQ(installed_web_root("/opt/fq/bin/fqd"), "/opt/fq/share/fq/web");
  if (std::filesystem::exists("web/index.html"))
    GTEST_SKIP() << "run from a source tree: its web/ comes first";
  const std::filesystem::path prefix = std::filesystem::path(testing::TempDir()) / "web_root_prefix";
  std::filesystem::remove_all(prefix);
  std::filesystem::create_directories(prefix / "bin");
  std::filesystem::create_directories(prefix / "share/fq/web");
  HttpConfig http;
  resolve_default_web_root(http, (prefix / "bin/fqd").string());
  EXPECT_EQ(http.web_root, "web") << "no viewer installed yet: the default stays";
  std::ofstream((prefix / "share/fq/web/index.html").string()) << "<html>";
  resolve_default_web_root(http, (prefix / "bin/fqd").string());
  EXPECT_EQ(http.web_root, (prefix / "share/fq/web").lexically_normal().string());
  HttpConfig configured;
  configured.web_root = "/srv/viewer";
  resolve_default_web_root(configured, (prefix / "bin/fqd").string());
  EXPECT_EQ(configured.web_root, "/srv/viewer") << "a web_root from the file stays";
}

}  // namespace
}  // namespace fq::daemon
