// clients/examples/consume.py, the consumer written without fq's code (python3-zmq,
// python3-protobuf, Google's draco_decoder), against fqd and fqpub as child processes on
// fandisk: its PLY must be the full filtered mesh, equal to fq's own decode of that result.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "tests/daemon/child_process.h"
#include "tests/daemon/daemon_harness.h"

namespace fq::test {
namespace {

const std::string kConfig = child_fqd_config(R"(compute = "filter_and_cluster"
[defaults.output]
chunks = 3
)");

/// The `uint label` of every vertex of a PLY whose vertex element is `float x, y, z, uint label`
/// (consume.py's layout, checked here), binary little-endian.
std::vector<uint32_t> read_labels(const std::string& path, uint32_t vertices) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string layout =
      "element vertex " + std::to_string(vertices) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty uint label\nelement face";
  const size_t body = text.find("end_header\n");
  if (text.find("format binary_little_endian 1.0") == std::string::npos ||
      text.find(layout) == std::string::npos || body == std::string::npos ||
      text.size() < body + 11 + size_t(vertices) * 16) {
    ADD_FAILURE() << path << ": not the expected vertex layout";
    return {};
  }
  std::vector<uint32_t> labels(vertices);
  for (uint32_t v = 0; v < vertices; ++v) std::memcpy(&labels[v], &text[body + 11 + size_t(v) * 16 + 12], 4);
  return labels;
}

TEST(ConsumeExample, PythonConsumerRebuildsTheFilteredMeshWithLabels) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(testing::TempDir()) / "fq_consume_example_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "fqd.toml") << kConfig;
  const std::string input = std::string(FQ_SOURCE_DIR) + "/data/fandisk.ply";
  Mesh mesh;
  ASSERT_TRUE(io::read_mesh(input, mesh).ok());

  Child fqd = spawn(FQD_PATH, {"--config", (dir / "fqd.toml").string(), "--print-endpoints"});
  ASSERT_GT(fqd.pid, 0);
  char line[1024] = {0};
  ASSERT_NE(std::fgets(line, sizeof line, fqd.out), nullptr) << "fqd printed no endpoints";
  const nlohmann::json ep = nlohmann::json::parse(line);
  DaemonHarness h(daemon::BoundEndpoints{ep.at("ingest"), ep.at("publish"), ep.at("control")});

  Child consume =
      spawn(FQ_PYTHON3, {CONSUME_PY, "--endpoint", ep.at("publish"), "--stream", "fandisk", "--faces", input,
                         "--out", (dir / "out").string(), "--count", "1", "--timeout", "120", "--proto-dir",
                         FQ_PB2_DIR, "--draco-decoder", DRACO_DECODER});
  // 30 frames over 3 s: consume.py's subscription is active long before the last ones. The
  // paper's filter: the default qf+ keeps a clean input such as this one as it is.
  Child pub = spawn(FQPUB_PATH, {input, "--endpoint", ep.at("ingest"), "--stream", "fandisk", "--fps", "10",
                                 "--count", "30", "--mode", "qf", "--quiet"});
  ASSERT_GT(consume.pid, 0);
  ASSERT_GT(pub.pid, 0);
  const std::string report = read_all(consume.out);
  EXPECT_EQ(wait_exit(consume.pid, 180), 0);
  ASSERT_FALSE(report.empty()) << "consume.py wrote no result";
  const nlohmann::json got = nlohmann::json::parse(report);
  const uint64_t sequence = got.at("sequence");

  // fq's own decode of the same published result.
  client::ReceivedResult ours = h.receive("fandisk");
  while (ours.header.sequence() < sequence) ours = h.receive("fandisk");
  ASSERT_EQ(ours.header.sequence(), sequence);
  ASSERT_EQ(ours.header.form(), wire::POSITIONS);
  ASSERT_EQ(ours.header.chunk_count(), 3u);
  ASSERT_TRUE(client::decode_result(ours, 2, &mesh.triangles).ok());
  EXPECT_EQ(wait_exit(pub.pid), 0);
  kill(fqd.pid, SIGTERM);
  EXPECT_EQ(wait_exit(fqd.pid), 0);

  Mesh back;
  ASSERT_TRUE(io::read_mesh(got.at("ply"), back).ok());
  ASSERT_EQ(back.num_vertices(), mesh.num_vertices());
  EXPECT_EQ(back.num_triangles(), mesh.num_triangles());
  EXPECT_EQ(back.triangles, mesh.triangles);
  // Both decoders dequantize the same Draco data: equal to well within one quantization step.
  float lo = mesh.positions[0], hi = mesh.positions[0];
  for (float v : mesh.positions) lo = std::min(lo, v), hi = std::max(hi, v);
  const float step = (hi - lo) / 65535.f;
  float worst = 0.f;
  for (size_t i = 0; i < back.positions.size(); ++i)
    worst = std::max(worst, std::abs(back.positions[i] - ours.mesh.positions[i]));
  EXPECT_LE(worst, 0.5f * step);
  float moved = 0.f;
  for (size_t i = 0; i < back.positions.size(); ++i)
    moved = std::max(moved, std::abs(back.positions[i] - mesh.positions[i]));
  EXPECT_GT(moved, 10.f * step) << "the filtered positions equal the input's";
  ASSERT_GT(ours.header.cluster_count(), 0u);
  EXPECT_EQ(got.at("labels"), mesh.num_vertices());
  EXPECT_EQ(read_labels(got.at("ply"), mesh.num_vertices()), ours.labels);
  for (FILE* f : {fqd.out, consume.out, pub.out}) std::fclose(f);
}

}  // namespace
}  // namespace fq::test
