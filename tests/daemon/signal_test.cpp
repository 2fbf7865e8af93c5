// fqd as a child process: it reports its ephemeral ports, serves frames, and exits 0 on
// SIGTERM and SIGINT; a bad config makes it exit non-zero with a message.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "tests/daemon/child_process.h"
#include "tests/daemon/daemon_harness.h"

namespace fq::test {
namespace {

Child spawn_fqd(const std::vector<std::string>& args) { return spawn(FQD_PATH, args); }

std::string write_config(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

const std::string kConfig = child_fqd_config();

class DaemonSignal : public testing::TestWithParam<int> {};

TEST_P(DaemonSignal, ServesFramesThenExitsZeroOnSignal) {
  const std::string config = write_config("fqd_signal_test.toml", kConfig);
  Child child = spawn_fqd({"--config", config, "--print-endpoints"});
  ASSERT_GT(child.pid, 0);
  char line[1024] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, child.out), nullptr) << "fqd printed no endpoints";
  const nlohmann::json j = nlohmann::json::parse(line);
  const daemon::BoundEndpoints ep{j.at("ingest"), j.at("publish"), j.at("control")};
  EXPECT_EQ(ep.ingest.find(":*"), std::string::npos) << "port not resolved: " << ep.ingest;
  {
    DaemonHarness h(ep);
    const Mesh mesh = noisy_sphere();
    client::FrameSpec spec;
    spec.stream_id = "cam";
    for (uint64_t i = 0; i < 3; ++i) {
      h.send(mesh, spec, i);
      EXPECT_EQ(h.receive_decoded("cam").header.sequence(), i);
    }
  }
  ASSERT_EQ(kill(child.pid, GetParam()), 0);
  EXPECT_EQ(wait_exit(child.pid), 0);
  std::fclose(child.out);
}

TEST_P(DaemonSignal, FramesReceivedBeforeTheSignalAreFinished) {
  // Frames are finished within caps.stop_grace_s (then stopped): a grace no loaded machine
  // runs out of, so that all three must come out as results. One engine per stream and no
  // engine time limit: with one engine the fairness rule would stop a frame that has run a
  // second while a stream none of whose frames has run waits (counted preempted), and a
  // loaded machine may pass the default 10 s limit; neither is what this test is about.
  std::string text = kConfig;
  const std::string threads = "cpu_threads = 1\n";
  text.replace(text.find(threads), threads.size(), threads + "cpu_engines = 3\n");
  const std::string config =
      write_config("fqd_drain_test.toml", text + "[caps]\nstop_grace_s = 300\nengine_time_limit_s = 0\n");
  Child child = spawn_fqd({"--config", config, "--print-endpoints"});
  ASSERT_GT(child.pid, 0);
  char line[1024] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, child.out), nullptr) << "fqd printed no endpoints";
  const nlohmann::json j = nlohmann::json::parse(line);
  DaemonHarness h(daemon::BoundEndpoints{j.at("ingest"), j.at("publish"), j.at("control")});
  // One slow frame on each of three streams (so none supersedes another), all received by
  // fqd before the signal: each must still come out as a result.
  const Mesh mesh = noisy_sphere(9, 5);
  const std::vector<std::string> streams{"a", "b", "c"};
  for (const std::string& id : streams) {
    client::FrameSpec spec;
    spec.stream_id = id;
    spec.compute = wire::FILTER_AND_CLUSTER;
    h.send(mesh, spec, 42);
  }
  for (const std::string& id : streams) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    wire::ControlRequest q;
    q.mutable_get_counters()->set_stream_id(id);
    while (!h.control(q).ok() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));  // until fqd has received it
  }
  ASSERT_EQ(kill(child.pid, GetParam()), 0);
  for (const std::string& id : streams) {
    const client::ReceivedResult r = h.receive_decoded(id);
    EXPECT_EQ(r.header.sequence(), 42u);
    EXPECT_EQ(r.mesh.num_vertices(), mesh.num_vertices());
  }
  EXPECT_EQ(wait_exit(child.pid), 0);
  std::fclose(child.out);
}

INSTANTIATE_TEST_SUITE_P(Signals, DaemonSignal, testing::Values(SIGTERM, SIGINT),
                         [](const testing::TestParamInfo<int>& i) {
                           return i.param == SIGTERM ? "SIGTERM" : "SIGINT";
                         });

TEST(DaemonProcess, BadConfigExitsNonZero) {
  const std::string config = write_config("fqd_bad.toml", "[engine]\nkind = \"gpu\"\n");
  Child child = spawn_fqd({"--config", config});
  ASSERT_GT(child.pid, 0);
  EXPECT_EQ(wait_exit(child.pid), 2);
  std::fclose(child.out);
}

}  // namespace
}  // namespace fq::test
