// The built fqstreambench, run as a user would on the bundled sample with the copy engine:
// its JSON says what fqd's host CPU per frame was, by stage, beside plain Draco's decode +
// encode of the same frame, what the benchmark's own producers and consumer used, and how late
// the host woke a sleeping thread while it ran. CPU times are checked for consistency, not for
// speed: this machine may be loaded.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/daemon/child_process.h"

namespace fq::test {
namespace {

TEST(StreambenchCpu, JsonHasFqdsCpuByStageBesideTheFloor) {
  const Child c = spawn(FQSTREAMBENCH_BIN, {"fandisk.ply",
                                            "--mesh-dir",
                                            FQ_DATA_DIR,
                                            "--engine",
                                            "copy",
                                            "--streams",
                                            "2",
                                            "--fps",
                                            "20",
                                            "-d",
                                            "2",
                                            "--warmup",
                                            "0.5",
                                            "--chunks",
                                            "2",
                                            "--phases",
                                            "spread",
                                            "--compute",
                                            "filter_and_cluster",
                                            "--json"});
  const std::string out = read_all(c.out);
  ASSERT_EQ(wait_exit(c.pid), 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j.at("engine"), "copy");
  EXPECT_EQ(j.at("phases"), "spread");
  const nlohmann::json& fqd = j.at("fqd");
  ASSERT_GT(fqd.at("frames_out").get<uint64_t>(), 0u);
  const double cpu = fqd.at("cpu_ms_per_frame").get<double>();
  EXPECT_TRUE(std::isfinite(cpu) && cpu > 0) << cpu;
  double staged = 0;
  for (const char* stage : {"ingest", "decode", "engine", "track_ids", "encode", "publish", "other"}) {
    const double ms = fqd.at("stage_cpu_ms_per_frame").at(stage).get<double>();
    EXPECT_TRUE(std::isfinite(ms) && ms >= 0) << stage << " = " << ms;
    staged += ms;
  }
  for (const char* stage : {"decode", "encode"})
    EXPECT_GT(fqd.at("stage_cpu_ms_per_frame").at(stage).get<double>(), 0) << stage;
  EXPECT_NEAR(staged, cpu, 1e-6 * cpu);  // "other" is what the stages leave of the total
  const double floor = fqd.at("floor_cpu_ms_per_frame").get<double>();
  EXPECT_GT(fqd.at("floor_decode_cpu_ms").get<double>(), 0);
  EXPECT_GT(fqd.at("floor_encode_cpu_ms").get<double>(), 0);
  EXPECT_DOUBLE_EQ(floor,
                   fqd.at("floor_decode_cpu_ms").get<double>() + fqd.at("floor_encode_cpu_ms").get<double>());
  EXPECT_DOUBLE_EQ(fqd.at("cpu_over_floor").get<double>(), cpu / floor);
  EXPECT_GT(j.at("bench").at("producers_cpu_ms_per_frame").get<double>(), 0);
  EXPECT_GT(j.at("bench").at("collector_cpu_ms_per_frame").get<double>(), 0);
  // How quiet the host was over the 2 s of sending: a wake-up at most every millisecond.
  const nlohmann::json& host = j.at("host");
  EXPECT_GT(host.at("wakeups").get<uint64_t>(), 10u);
  EXPECT_LE(host.at("wakeups").get<uint64_t>(), 2100u);
  const nlohmann::json& late = host.at("wakeup_late_ms");
  EXPECT_LE(late.at("p50").get<double>(), late.at("p99").get<double>());
  EXPECT_LE(late.at("p99").get<double>(), late.at("max").get<double>());
  EXPECT_LE(host.at("wakeups_late_over_5ms").get<uint64_t>(), host.at("wakeups").get<uint64_t>());
  EXPECT_GE(host.at("steal_share").get<double>(), 0.0);
}

}  // namespace
}  // namespace fq::test
