// fqd's host CPU by stage: after frames went through, every stage's account has grown, all of
// fqd's threads together used at least the stages' sum, /metrics carries both families, and
// fqd's threads carry names that tell them from the embedding program's.
#include "daemon/pipeline/stage_cpu.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "daemon/pipeline/daemon_threads.h"
#include "tests/daemon/daemon_harness.h"

namespace fq::test {
namespace {

std::set<std::string> thread_names() {
  std::set<std::string> names;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream in(task.path() / "comm");
    std::string name;
    std::getline(in, name);
    names.insert(name);
  }
  return names;
}

TEST(StageCpu, EveryStageIsChargedAndTheThreadsCoverThem) {
  daemon::DaemonConfig c = test_config();
  DaemonHarness h(c);
  const daemon::CpuUsage before = h.daemon()->cpu_usage();
  client::FrameSpec spec;
  spec.stream_id = "cam";
  spec.compute = wire::FILTER_AND_CLUSTER;
  for (uint64_t i = 0; i < 4; ++i) {
    h.send(noisy_sphere(i + 1), spec, i);
    h.receive("cam");
  }
  const daemon::CpuUsage after = h.daemon()->cpu_usage();
  double staged = 0;
  for (size_t s = 0; s < after.stage_seconds.size(); ++s) {
    const char* name = daemon::cpu_stage_name(static_cast<daemon::CpuStage>(s));
    EXPECT_GT(after.stage_seconds[s], before.stage_seconds[s]) << name;
    staged += after.stage_seconds[s];
  }
  EXPECT_GE(after.threads_seconds, staged);
  const std::string metrics = h.daemon()->service_metrics();
  for (const char* stage : {"ingest", "decode", "engine", "track_ids", "encode", "publish"})
    EXPECT_NE(metrics.find("fq_stage_cpu_seconds_total{stage=\"" + std::string(stage) + "\"} "),
              std::string::npos)
        << stage;
  EXPECT_NE(metrics.find("# TYPE fq_stage_cpu_seconds_total counter"), std::string::npos);
  EXPECT_NE(metrics.find("\nfq_cpu_seconds_total "), std::string::npos);
}

TEST(DaemonThreads, NamedByRoleAndCountedAsFqds) {
  DaemonHarness h;
  const std::set<std::string> names = thread_names();
  for (const char* role :
       {"fqd-ingest", "fqd-decode", "fqd-engine", "fqd-encode", "fqd-publish", "fqd-control"})
    EXPECT_EQ(names.count(role), 1u) << role;
  const std::string zmq = std::to_string(daemon::kZmqThreadTag) + "/ZMQbg/";
  EXPECT_EQ(names.count(zmq + "IO/0"), 1u) << zmq << "IO/0";
  for (const std::string& n : names) {
    const bool ours = n.rfind("fqd-", 0) == 0 || n == "fq-pool" || n.rfind(zmq, 0) == 0;
    EXPECT_EQ(daemon::is_daemon_thread(n), ours) << n;
  }
  EXPECT_FALSE(daemon::is_daemon_thread("ZMQbg/IO/0"));  // the test's own context
  EXPECT_GT(daemon::daemon_threads_cpu_seconds(), 0.0);
}

}  // namespace
}  // namespace fq::test
