// The /metrics families an SRE alerts on, from fqd as a child process: admission refusals by
// reason (a misconfigured producer shows up), build info, each stream's budget, engine busy
// time and frames, queue depths and the process_* families; the whole page still parses
// with prometheus_client's parser.
#include <gtest/gtest.h>
#include <httplib.h>

#include <map>
#include <sstream>

#include "common/version.h"
#include "tests/daemon/fqd_process.h"

namespace fq::test {
namespace {

// "name{labels} value" lines into a map from "name{labels}" to the value.
std::map<std::string, double> samples(const std::string& text) {
  std::map<std::string, double> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const size_t space = line.rfind(' ');
    out[line.substr(0, space)] = std::stod(line.substr(space + 1));
  }
  return out;
}

TEST(ServiceMetrics, RefusalsBuildBudgetEnginesQueuesAndProcess) {
  const std::string config = write_temp_file(
      "service_metrics.toml", ops_config("[caps]\nallowed_streams = [\"cam*\"]\n[http]\nlisten = "
                                         "\"127.0.0.1:0\"\n[streams.cam0]\nbudget_ms = 30000\n"));
  FqdProcess fqd({"--config", config});
  ASSERT_FALSE(fqd.endpoint("http").empty());
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 3).status, 0);
  // Refused: the id is not in caps.allowed_streams. fqpub counts these frames sent; only
  // fqd knows, and before fq_refused_total only its log said so.
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "lobby", 2).status, 0);
  httplib::Client c(fqd.endpoint("http"));
  c.set_read_timeout(30, 0);
  std::map<std::string, double> m;
  EXPECT_TRUE(eventually([&] {
    auto r = c.Get("/metrics");
    if (!r || r->status != 200) return false;
    m = samples(r->body);
    const std::string cam0 = "{stream=\"cam0\"}";
    return m["fq_frames_out_total" + cam0] + m["fq_superseded_total" + cam0] == 3 &&
           m["fq_refused_total{reason=\"not_allowed\"}"] == 2;
  })) << "frames out "
      << m["fq_frames_out_total{stream=\"cam0\"}"] << ", refused "
      << m["fq_refused_total{reason=\"not_allowed\"}"];
  for (const char* reason : {"bad_stream_id", "malformed", "too_many_streams", "unauthenticated"})
    EXPECT_EQ(m.count("fq_refused_total{reason=\"" + std::string(reason) + "\"}"), 1u) << reason;
  const std::string build = "fq_build_info{version=\"" + std::string(version_string()) + "\",cuda=\"" +
                            (built_with_cuda() ? "compiled_in" : "absent") + "\"}";
  EXPECT_EQ(m[build], 1) << build;
  EXPECT_EQ(m["fq_stream_budget_seconds{stream=\"cam0\"}"], 30);
  EXPECT_GT(m["fq_engine_busy_seconds_total{engine=\"cpu\",index=\"0\"}"], 0);
  EXPECT_EQ(m["fq_engine_frames_total{engine=\"cpu\",index=\"0\"}"],
            m["fq_frames_out_total{stream=\"cam0\"}"]);
  for (const char* q : {"decode", "slots", "encode", "publish"})
    EXPECT_EQ(m.count("fq_queue_depth{queue=\"" + std::string(q) + "\"}"), 1u) << q;
  EXPECT_GT(m["process_cpu_seconds_total"], 0);
  EXPECT_GT(m["process_resident_memory_bytes"], 1e6);
  EXPECT_GT(m["process_virtual_memory_bytes"], m["process_resident_memory_bytes"]);
  EXPECT_GT(m["process_start_time_seconds"], 1.6e9);
  EXPECT_GT(m["process_open_fds"], 3);
  EXPECT_GE(m["process_max_fds"], m["process_open_fds"]);
  EXPECT_GT(m["process_threads"], 3);
  const ToolRun parsed = run_tool("/usr/bin/python3", {METRICS_CHECK_PY, fqd.endpoint("http") + "/metrics"});
  ASSERT_EQ(parsed.status, 0) << parsed.output;
  const nlohmann::json families = nlohmann::json::parse(parsed.output).at("families");
  EXPECT_EQ(families.at("fq_refused"), "counter");
  EXPECT_EQ(families.at("process_cpu_seconds"), "counter");
  EXPECT_EQ(families.at("fq_build_info"), "gauge");
  EXPECT_EQ(fqd.stop(), 0);
}

}  // namespace
}  // namespace fq::test
