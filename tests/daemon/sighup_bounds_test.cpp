// SIGHUP against fqd as a child process: a file with more stream tables than caps.max_streams
// is refused whole (the running streams kept), and a 64 MiB bad value reaches the log as a
// bounded prefix, not as one 64 MiB line.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <sstream>

#include "tests/daemon/fqd_process.h"

namespace fq::test {
namespace {

std::string budget(const FqdProcess& fqd, const std::string& stream) {
  const ToolRun r = run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "params", stream});
  const size_t at = r.output.find("budget_ms = ");
  return r.status != 0 || at == std::string::npos
             ? "?"
             : r.output.substr(at + 12, r.output.find('\n', at) - at - 12);
}

size_t longest_line(const std::string& text) {
  std::istringstream in(text);
  size_t longest = 0;
  for (std::string line; std::getline(in, line);) longest = std::max(longest, line.size());
  return longest;
}

TEST(SighupBounds, TablesPastMaxStreamsAndAHugeBadValueAreRefusedInABoundedLine) {
  const std::string log = testing::TempDir() + "/fqd_sighup_bounds.log";
  const std::string caps = "[caps]\nmax_streams = 3\n";
  const std::string file =
      write_temp_file("sighup_bounds.toml", ops_config(caps + "[streams.cam0]\nbudget_ms = 500\n"));
  FqdProcess fqd({"--config", file}, "", "2>'" + log + "'");
  ASSERT_FALSE(fqd.endpoint("control").empty()) << read_text_file(log);
  EXPECT_EQ(budget(fqd, "cam0"), "500");

  // Four tables against max_streams = 3: before, all four became pinned streams.
  std::string four = caps;
  for (int i = 0; i < 4; ++i) four += "[streams.cam" + std::to_string(i) + "]\nbudget_ms = 50\n";
  write_temp_file("sighup_bounds.toml", ops_config(four));
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log).find("4 [streams.*] tables, over caps.max_streams = 3") != std::string::npos;
  })) << read_text_file(log);
  EXPECT_EQ(budget(fqd, "cam0"), "500") << "the running config is kept";
  EXPECT_EQ(budget(fqd, "cam3"), "?");

  // A 64 MiB value: before, the whole of it went into the reload's log line.
  write_temp_file("sighup_bounds.toml",
                  ops_config(caps + "[streams.cam0]\ncompute = \"" + std::string(64u << 20, 'x') + "\"\n"));
  ASSERT_EQ(kill(fqd.pid(), SIGHUP), 0);
  EXPECT_TRUE(eventually([&] {
    return read_text_file(log).find("...(67108864 bytes)") != std::string::npos;
  })) << read_text_file(log).substr(0, 4096);
  EXPECT_LT(std::filesystem::file_size(log), 64u << 10);
  EXPECT_LT(longest_line(read_text_file(log)), 1024u);
  EXPECT_EQ(budget(fqd, "cam0"), "500");
  EXPECT_TRUE(fqd.alive());
  EXPECT_EQ(fqd.stop(), 0);
}

}  // namespace
}  // namespace fq::test
