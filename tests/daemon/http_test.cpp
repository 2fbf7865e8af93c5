// fqd's HTTP listener against fqd as a child process fed by fqpub: /metrics parsed by
// prometheus_client's text parser agrees with `fqctl counters --json`, /healthz, /streams,
// /streams/ID/latest (real Draco chunks, faces and labels), and the viewer's install hint when web_root is
// empty.
#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "io/mesh_io.h"
#include "io/ply_reader.h"
#include "tests/daemon/fqd_process.h"
#include "tests/daemon/raw_http.h"
#include "tests/support/test_meshes.h"
#include "wire/frame_codec.h"

namespace fq::test {
namespace {

httplib::Client client(const FqdProcess& fqd) {
  httplib::Client c(fqd.endpoint("http"));
  c.set_read_timeout(30, 0);
  return c;
}

nlohmann::json fqctl_counters(const FqdProcess& fqd) {
  const ToolRun r = run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "counters", "--json"});
  EXPECT_EQ(r.status, 0) << r.output;
  return nlohmann::json::parse(r.output, nullptr, false);
}

// The Draco chunks of a /streams/ID/latest body, after its first `offset` bytes (faces and
// labels), split by X-Fq-Chunk-Sizes; empty when the sizes do not add up to the body.
std::vector<std::string_view> chunks_of(const httplib::Response& r, size_t at) {
  std::vector<std::string_view> chunks;
  const std::string sizes = r.get_header_value("X-Fq-Chunk-Sizes");
  for (size_t s = 0; s < sizes.size();) {
    const size_t comma = sizes.find(',', s);
    const size_t n = std::stoul(sizes.substr(s, comma - s));
    if (at + n > r.body.size()) return {};
    chunks.emplace_back(r.body.data() + at, n);
    at += n;
    s = comma == std::string::npos ? sizes.size() : comma + 1;
  }
  if (at != r.body.size()) return {};
  return chunks;
}

// Waits until every one of `sent` frames of `stream` is accounted for.
nlohmann::json settled(const FqdProcess& fqd, uint64_t sent, const std::string& stream = "cam0") {
  nlohmann::json c;
  for (int i = 0; i < 600; ++i) {
    const nlohmann::json all = fqctl_counters(fqd);  // kept: the loop refers into it
    for (const nlohmann::json& s : all.at("streams"))
      if (s.at("stream") == stream) c = s;
    if (!c.is_null() && c.at("frames_out").get<uint64_t>() + c.at("errors").get<uint64_t>() +
                                c.at("superseded").get<uint64_t>() + c.at("dropped_stale").get<uint64_t>() ==
                            sent)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // polling fqd, not ordering
  }
  return c;
}

TEST(Http, MetricsParseAndAgreeWithFqctl) {
  // Two engines of one name, whose series must still be told apart.
  std::string config = ops_config(http_without_viewer());
  config.replace(config.find("cpu_threads = 1"), 15, "cpu_threads = 1\ncpu_engines = 2");
  FqdProcess fqd({"--config", write_temp_file("http_metrics.toml", config)});
  ASSERT_FALSE(fqd.endpoint("http").empty()) << "fqd did not report an http endpoint";
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 10).status, 0);
  // A stream id with the characters the text format escapes in label values.
  const std::string odd = "cam \"1\"\\x";
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), odd, 2).status, 0);
  const nlohmann::json ctl = settled(fqd, 10);
  const nlohmann::json ctl_odd = settled(fqd, 2, odd);
  EXPECT_GT(ctl.at("frames_out").get<int>(), 0);
  ASSERT_EQ(ctl_odd.at("stream"), odd);

  const ToolRun parsed = run_tool("/usr/bin/python3", {METRICS_CHECK_PY, fqd.endpoint("http") + "/metrics"});
  ASSERT_EQ(parsed.status, 0) << parsed.output;
  const nlohmann::json m = nlohmann::json::parse(parsed.output);
  EXPECT_EQ(m.at("families").at("fq_stage_latency_seconds"), "histogram");
  EXPECT_EQ(m.at("families").at("fq_frames_in"), "counter");
  EXPECT_EQ(m.at("families").at("fq_engine_info"), "gauge");
  const nlohmann::json& prom = m.at("streams").at("cam0");
  for (const char* k : {"frames_in", "frames_out", "superseded", "dropped_stale", "late", "errors",
                        "bad_send_time", "preempted", "preempted_others"}) {
    EXPECT_EQ(prom.at(k), ctl.at(k)) << k;
    EXPECT_EQ(m.at("streams").at(odd).at(k), ctl_odd.at(k)) << k;
  }
  ASSERT_FALSE(ctl.at("stages").empty());
  for (const auto& [stage, p] : ctl.at("stages").items())
    EXPECT_EQ(prom.at("stages").at(stage), p.at("count")) << stage;

  // /streams is the same JSON as fqctl's, plus the engines.
  httplib::Client c = client(fqd);
  auto streams = c.Get("/streams");
  ASSERT_TRUE(streams);
  EXPECT_EQ(streams->status, 200);
  const nlohmann::json sj = nlohmann::json::parse(streams->body);
  EXPECT_EQ(sj.at("streams"), fqctl_counters(fqd).at("streams"));
  EXPECT_EQ(sj.at("engines"), nlohmann::json::array({"cpu", "cpu"}));
  EXPECT_EQ(fqd.stop(), 0);
}

TEST(Http, HealthLatestResultAndViewerHint) {
  FqdProcess fqd({"--config", write_temp_file("http_health.toml", ops_config(http_without_viewer()))});
  ASSERT_FALSE(fqd.endpoint("http").empty());
  httplib::Client c = client(fqd);
  auto health = c.Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
  EXPECT_EQ(health->body, "ok\n");
  auto index = c.Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 404);
  EXPECT_NE(index->body.find("scripts/web-deps.sh"), std::string::npos) << index->body;
  EXPECT_EQ(c.Get("/streams/nosuch/latest")->status, 404);

  // The first ask marks the stream watched; results published after it are kept.
  ASSERT_EQ(publish_fandisk(fqd.endpoint("ingest"), "cam0", 1).status, 0);
  settled(fqd, 1);
  EXPECT_EQ(c.Get("/streams/cam0/latest?wait_ms=0")->status, 204);
  std::thread pub([&] { publish_fandisk(fqd.endpoint("ingest"), "cam0", 20, 10); });
  auto latest = c.Get("/streams/cam0/latest?after=0&wait_ms=5000");
  for (int i = 0; i < 10 && latest && latest->status == 204; ++i)
    latest = c.Get("/streams/cam0/latest?after=0&wait_ms=5000");
  pub.join();
  ASSERT_TRUE(latest);
  ASSERT_EQ(latest->status, 200);
  // The default POSITIONS form: [faces][labels][point-cloud chunks], the faces being the
  // input frame's and the labels the header's, one per vertex.
  Mesh input;
  ASSERT_TRUE(io::read_ply(std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply", input).ok());
  EXPECT_EQ(latest->get_header_value("X-Fq-Form"), "positions");
  EXPECT_EQ(latest->get_header_value("X-Fq-Vertex-Count"), std::to_string(input.num_vertices()));
  EXPECT_GT(std::stoi(latest->get_header_value("X-Fq-Cluster-Count")), 0);
  const size_t face_bytes = std::stoul(latest->get_header_value("X-Fq-Faces-Bytes"));
  const size_t label_bytes = std::stoul(latest->get_header_value("X-Fq-Labels-Bytes"));
  EXPECT_EQ(face_bytes, input.triangles.size() * 4);
  EXPECT_EQ(label_bytes, input.num_vertices() * 4u);
  ASSERT_GE(latest->body.size(), face_bytes + label_bytes);
  std::vector<uint32_t> words((face_bytes + label_bytes) / 4);
  std::memcpy(words.data(), latest->body.data(), face_bytes + label_bytes);
  EXPECT_LT(*std::max_element(words.begin(), words.begin() + face_bytes / 4), input.num_vertices());
  const uint32_t clusters = std::stoul(latest->get_header_value("X-Fq-Cluster-Count"));
  EXPECT_LT(*std::max_element(words.begin() + face_bytes / 4, words.end()), clusters);
  const std::vector<std::string_view> chunks = chunks_of(*latest, face_bytes + label_bytes);
  EXPECT_FALSE(chunks.empty());
  std::vector<float> positions;
  EXPECT_TRUE(wire::decode_positions(chunks, input.num_vertices(), {}, positions).ok());
  const uint64_t index_seen = std::stoull(latest->get_header_value("X-Fq-Index"));
  // A viewer holding this result's faces (faces=ID) is not sent them again: a stream's faces
  // do not change from frame to frame.
  const std::string faces_id = latest->get_header_value("X-Fq-Faces-Id");
  EXPECT_NE(faces_id, "0");
  std::thread more([&] { publish_fandisk(fqd.endpoint("ingest"), "cam0", 20, 10); });
  auto newer = c.Get("/streams/cam0/latest?after=" + std::to_string(index_seen) + "&faces=" + faces_id +
                     "&wait_ms=5000");
  for (int i = 0; i < 10 && newer && newer->status == 204; ++i)
    newer = c.Get("/streams/cam0/latest?after=" + std::to_string(index_seen) + "&faces=" + faces_id +
                  "&wait_ms=5000");
  more.join();
  ASSERT_TRUE(newer);
  ASSERT_EQ(newer->status, 200);
  EXPECT_GT(std::stoull(newer->get_header_value("X-Fq-Index")), index_seen);
  EXPECT_EQ(newer->get_header_value("X-Fq-Faces-Id"), faces_id);
  EXPECT_EQ(newer->get_header_value("X-Fq-Faces-Bytes"), "0");
  EXPECT_EQ(newer->get_header_value("X-Fq-Labels-Bytes"), std::to_string(label_bytes));

  // The MESH form: chunked Draco meshes as published, no faces beside them, labels still first.
  ASSERT_EQ(
      run_tool(FQCTL_PATH, {"--control", fqd.endpoint("control"), "set", "cam0", "result_form=mesh"}).status,
      0);
  std::thread meshes([&] { publish_fandisk(fqd.endpoint("ingest"), "cam0", 20, 10); });
  uint64_t after = std::stoull(newer->get_header_value("X-Fq-Index"));
  std::optional<httplib::Response> mesh;
  for (int i = 0; i < 40; ++i) {
    auto r = c.Get("/streams/cam0/latest?after=" + std::to_string(after) + "&wait_ms=5000");
    if (!r || r->status != 200) continue;
    after = std::stoull(r->get_header_value("X-Fq-Index"));
    if (r->get_header_value("X-Fq-Form") == "mesh") {
      mesh = *r;
      break;
    }
  }
  meshes.join();
  ASSERT_TRUE(mesh) << "no MESH-form result after result_form=mesh";
  EXPECT_EQ(mesh->get_header_value("X-Fq-Faces-Id"), "0");
  EXPECT_EQ(mesh->get_header_value("X-Fq-Faces-Bytes"), "0");
  EXPECT_EQ(mesh->get_header_value("X-Fq-Labels-Bytes"), std::to_string(label_bytes));
  Mesh decoded;
  EXPECT_TRUE(
      wire::decode_frame(chunks_of(*mesh, label_bytes), input.num_vertices(), {}, decoded, nullptr).ok());
  EXPECT_EQ(decoded.triangles.size(), input.triangles.size());
  EXPECT_EQ(fqd.stop(), 0);
}

// Resident memory of a process (VmRSS), in bytes; 0 where /proc does not say.
size_t resident_bytes(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stoul(line.substr(6)) * 1024;
  return 0;
}

// Viewers that ask for a large result and read slowly (here: not at all) are served from the
// kept result itself: before, each request built its own copy of the body and held it until the
// last byte left, so 64 slow readers of a 25 MB result held 3 GB.
TEST(Http, SlowReadersOfALargeResultShareItsBody) {
  std::string toml =
      ops_config(http_without_viewer() + "[streams.cam0]\nbudget_ms = 60000\ncompute = \"filter\"\n");
  toml.replace(toml.find("kind = \"cpu\""), 12,
               "kind = \"copy\"");  // the body's size is the point, not the filter
  FqdProcess fqd({"--config", write_temp_file("http_slow_readers.toml", toml)});
  ASSERT_FALSE(fqd.endpoint("http").empty());
  httplib::Client c = client(fqd);
  // A grid of 490,000 vertices: its faces are 11.8 MB of the 12 MB body.
  const std::string mesh = testing::TempDir() + "/fq_slow_readers_grid.ply";
  ASSERT_TRUE(io::write_mesh(mesh, make_plane_grid(700, 700).view(), nullptr, 0).ok());
  EXPECT_EQ(c.Get("/streams/cam0/latest?wait_ms=0")->status, 204);  // now watched: the next result is kept
  ASSERT_EQ(run_tool(FQPUB_PATH, {mesh, "--endpoint", fqd.endpoint("ingest"), "--stream", "cam0", "--count",
                                  "1", "--quiet"})
                .status,
            0);
  settled(fqd, 1);
  auto whole = c.Get("/streams/cam0/latest?after=0");
  ASSERT_TRUE(whole);
  ASSERT_EQ(whole->status, 200);
  const size_t body = whole->body.size();
  ASSERT_GT(body, size_t(10) << 20);
  const size_t before = resident_bytes(fqd.pid());
  ASSERT_GT(before, 0u);
  std::vector<std::unique_ptr<RawConnection>> readers;
  for (int i = 0; i < 8; ++i) {
    readers.push_back(std::make_unique<RawConnection>(http_port(fqd.endpoint("http"))));
    ASSERT_TRUE(readers.back()->send("GET /streams/cam0/latest?after=0 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the readers' requests reach their threads
  const size_t during = resident_bytes(fqd.pid());
  // Eight copies would add 8 × body; what the sockets hold is the kernel's, not resident.
  EXPECT_LT(during, before + 2 * body)
      << "resident " << before << " -> " << during << " bytes, body " << body;
  // And a reader that reads gets the whole body.
  auto again = c.Get("/streams/cam0/latest?after=0");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->body, whole->body);
}

}  // namespace
}  // namespace fq::test
