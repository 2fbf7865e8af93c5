// The command-line clients end to end: fqpub -> fqd -> fqsub, all three as child processes
// on ephemeral ports; fqsub checks every result and writes coloured PLYs.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "io/mesh_io.h"
#include "tests/daemon/child_process.h"
#include "tests/daemon/daemon_harness.h"

namespace fq::test {
namespace {

const std::string kConfig = child_fqd_config(R"(compute = "filter_and_cluster"
)");

TEST(Clients, FqpubToFqdToFqsubGivesCheckedColouredPlys) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "fq_clients_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::ofstream(dir / "fqd.toml") << kConfig;
  const Mesh mesh = noisy_sphere();
  ASSERT_TRUE(io::write_mesh((dir / "sphere.ply").string(), mesh.view(), nullptr, 0).ok());

  Child fqd = spawn(FQD_PATH, {"--config", (dir / "fqd.toml").string(), "--print-endpoints"});
  ASSERT_GT(fqd.pid, 0);
  char line[1024] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, fqd.out), nullptr) << "fqd printed no endpoints";
  const nlohmann::json ep = nlohmann::json::parse(line);

  Child sub =
      spawn(FQSUB_PATH, {"--endpoint", ep.at("publish"), "--stream", "cam", "--count", "3", "--idle-timeout",
                         "30", "--write-every", "1", "--out", (dir / "out").string(), "--faces",
                         (dir / "sphere.ply").string(), "--json", "--quiet"});
  // 20 frames over 2 s: the subscription is active long before the last ones.
  Child pub =
      spawn(FQPUB_PATH, {(dir / "sphere.ply").string(), "--endpoint", ep.at("ingest"), "--stream", "cam",
                         "--fps", "10", "--count", "20", "--noise", "0.1", "--quiet", "--json"});
  ASSERT_GT(sub.pid, 0);
  ASSERT_GT(pub.pid, 0);
  const nlohmann::json summary = nlohmann::json::parse(read_all(sub.out));
  EXPECT_EQ(wait_exit(sub.pid), 0);
  const nlohmann::json sent = nlohmann::json::parse(read_all(pub.out));
  EXPECT_EQ(sent.at("frames_sent"), 20);
  EXPECT_EQ(sent.at("fqd_connected"), true);
  EXPECT_EQ(wait_exit(pub.pid), 0);
  kill(fqd.pid, SIGTERM);
  EXPECT_EQ(wait_exit(fqd.pid), 0);

  EXPECT_EQ(summary.at("results"), 3);
  EXPECT_EQ(summary.at("bad"), 0);
  EXPECT_EQ(summary.at("errors"), 0);
  const std::string ply = summary.at("last_ply");
  ASSERT_FALSE(ply.empty());
  Mesh back;
  ASSERT_TRUE(io::read_mesh(ply, back).ok());
  EXPECT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(back.num_triangles(), mesh.num_triangles());
  std::ifstream in(ply, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("property uint label"), std::string::npos);
  EXPECT_NE(text.find("property uchar red"), std::string::npos);
  for (FILE* f : {fqd.out, sub.out, pub.out}) std::fclose(f);
}

TEST(Clients, FqsubCtrlCExitsZeroWithItsSummaryAndSortableNames) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "fq_clients_ctrl_c_test";
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::ofstream(dir / "fqd.toml") << kConfig;
  ASSERT_TRUE(io::write_mesh((dir / "sphere.ply").string(), noisy_sphere().view(), nullptr, 0).ok());
  Child fqd = spawn(FQD_PATH, {"--config", (dir / "fqd.toml").string(), "--print-endpoints"});
  char line[1024] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, fqd.out), nullptr) << "fqd printed no endpoints";
  const nlohmann::json ep = nlohmann::json::parse(line);
  // No --count: it runs until Ctrl-C.
  Child sub = spawn(FQSUB_PATH,
                    {"--endpoint", ep.at("publish"), "--stream", "cam", "--write-every", "1", "--out",
                     (dir / "out").string(), "--faces", (dir / "sphere.ply").string(), "--json", "--quiet"});
  Child pub = spawn(FQPUB_PATH, {(dir / "sphere.ply").string(), "--endpoint", ep.at("ingest"), "--stream",
                                 "cam", "--fps", "10", "--count", "12", "--quiet", "--json"});
  EXPECT_EQ(wait_exit(pub.pid), 0);
  // Wait (polling the folder) for results to be written, then Ctrl-C.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  auto files = [&] { return std::distance(fs::directory_iterator(dir / "out"), fs::directory_iterator{}); };
  while (files() < 2 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(sub.pid, SIGINT);
  const nlohmann::json summary = nlohmann::json::parse(read_all(sub.out), nullptr, false);
  EXPECT_EQ(wait_exit(sub.pid), 0);  // stopped by the user: not an error
  ASSERT_TRUE(summary.is_object());
  EXPECT_GE(summary.at("results").get<int>(), 2);
  EXPECT_EQ(summary.at("bad"), 0);
  for (const auto& f : fs::directory_iterator(dir / "out"))
    EXPECT_TRUE(std::regex_match(f.path().filename().string(), std::regex(R"(cam_\d{10}\.ply)")))
        << f.path().filename();
  kill(fqd.pid, SIGTERM);
  EXPECT_EQ(wait_exit(fqd.pid), 0);
  for (FILE* f : {fqd.out, sub.out, pub.out}) std::fclose(f);
}

// Drops by reason: every frame stopped at a time limit no frame can meet comes as an error
// result fqsub counts as time_limit; --help says which reasons a subscriber cannot tell apart.
TEST(Clients, FqsubCountsDropsByReason) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "fq_clients_drops_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "fqd.toml") << kConfig + "[caps]\nengine_time_limit_s = 0.000001\n";
  ASSERT_TRUE(io::write_mesh((dir / "sphere.ply").string(), noisy_sphere().view(), nullptr, 0).ok());
  Child fqd = spawn(FQD_PATH, {"--config", (dir / "fqd.toml").string(), "--print-endpoints"});
  char line[1024] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, fqd.out), nullptr) << "fqd printed no endpoints";
  const nlohmann::json ep = nlohmann::json::parse(line);
  Child sub = spawn(FQSUB_PATH, {"--endpoint", ep.at("publish"), "--stream", "cam", "--count", "3",
                                 "--idle-timeout", "30", "--json", "--quiet"});
  Child pub = spawn(FQPUB_PATH, {(dir / "sphere.ply").string(), "--endpoint", ep.at("ingest"), "--stream",
                                 "cam", "--fps", "10", "--count", "20", "--quiet", "--json"});
  const nlohmann::json summary = nlohmann::json::parse(read_all(sub.out), nullptr, false);
  EXPECT_EQ(wait_exit(sub.pid), 1);  // error results
  EXPECT_EQ(wait_exit(pub.pid), 0);
  kill(fqd.pid, SIGTERM);
  EXPECT_EQ(wait_exit(fqd.pid), 0);
  ASSERT_TRUE(summary.is_object());
  EXPECT_EQ(summary.at("errors"), 3);
  EXPECT_EQ(summary.at("drops_by_reason").value("time_limit", 0), 3) << summary.dump();
  EXPECT_EQ(summary.at("drops"), summary.at("drops_by_reason").value("gap", 0) + 3) << summary.dump();
  for (FILE* f : {fqd.out, sub.out, pub.out}) std::fclose(f);

  Child help = spawn(FQSUB_PATH, {"--help"});
  const std::string text = read_all(help.out);
  EXPECT_EQ(wait_exit(help.pid), 0);
  EXPECT_NE(text.find("fqsub cannot tell these apart"), std::string::npos) << text;
  for (const char* reason : {"gap", "preempted", "time_limit", "stopping"})
    EXPECT_NE(text.find(std::string("  ") + reason + " "), std::string::npos) << reason;
  std::fclose(help.out);
}

TEST(Clients, FqpubSaysWhenNoFqdIsConnected) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "fq_clients_no_fqd_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_TRUE(io::write_mesh((dir / "sphere.ply").string(), noisy_sphere().view(), nullptr, 0).ok());
  // An endpoint nobody listens on: ZeroMQ connects lazily, so only the missing handshake tells.
  Child pub =
      spawn(FQPUB_PATH, {(dir / "sphere.ply").string(), "--endpoint", "ipc://" + (dir / "nobody").string(),
                         "--fps", "20", "--count", "3", "--json"});
  const nlohmann::json summary = nlohmann::json::parse(read_all(pub.out), nullptr, false);
  EXPECT_EQ(wait_exit(pub.pid), 1);
  ASSERT_TRUE(summary.is_object());
  EXPECT_EQ(summary.at("fqd_connected"), false);
  EXPECT_EQ(summary.at("frames_sent_unconnected"), 3);
  std::fclose(pub.out);
}

}  // namespace
}  // namespace fq::test
