// The built fqbench in codec mode, run as a user would, on the bundled sample: its JSON has
// every key with sane values (timings are not asserted: this machine may be loaded).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace {

/// stdout of the shell command `cmd`, and its exit code.
std::string run(const std::string& cmd, int& exit_code) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return out;
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  const int status = pclose(p);
  exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

std::string fqbench(const std::string& args) {
  std::string cmd = "'";
  cmd.append(FQBENCH_BIN).append("' ").append(args);
  return cmd;
}

TEST(FqbenchCodec, JsonHasOursAndTheFloorWithSaneValues) {
  int code = -1;
  const std::string out = run(fqbench("--codec '" + std::string(FQ_DATA_DIR) +
                                      "/fandisk.ply' --chunks 4 --threads 2 --speed 10 --repeat 3 --json"),
                              code);
  ASSERT_EQ(code, 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j.at("vertices"), 6475);
  EXPECT_EQ(j.at("triangles"), 12946);
  EXPECT_EQ(j.at("chunks"), 4);
  EXPECT_EQ(j.at("threads"), 2);
  EXPECT_EQ(j.at("speed"), 10);
  for (const char* key :
       {"encode_ms", "decode_ms", "floor_encode_ms", "floor_decode_ms", "encode_cpu_ms", "decode_cpu_ms",
        "floor_encode_cpu_ms", "floor_decode_cpu_ms", "result_encode_ms", "result_encode_cpu_ms"}) {
    const double ms = j.at(key).get<double>();
    EXPECT_TRUE(std::isfinite(ms) && ms > 0.0 && ms < 60000.0) << key << " = " << ms;
  }
  EXPECT_DOUBLE_EQ(j.at("encode_ratio").get<double>(),
                   j.at("encode_ms").get<double>() / j.at("floor_encode_ms").get<double>());
  EXPECT_DOUBLE_EQ(j.at("decode_ratio").get<double>(),
                   j.at("decode_ms").get<double>() / j.at("floor_decode_ms").get<double>());
  // fqd's MESH result of the decoded frame, on the input's chunks, against the same floor.
  EXPECT_DOUBLE_EQ(j.at("floor_result_encode_ms").get<double>(), j.at("floor_encode_ms").get<double>());
  EXPECT_DOUBLE_EQ(j.at("result_encode_ratio").get<double>(),
                   j.at("result_encode_ms").get<double>() / j.at("floor_encode_ms").get<double>());
  // Ours carries the vertex ids on top of the same chunks: a little more, never less.
  EXPECT_GE(j.at("bytes").get<double>(), j.at("floor_bytes").get<double>());
  EXPECT_LT(j.at("bytes").get<double>(), 1.2 * j.at("floor_bytes").get<double>());
}

TEST(FqbenchCodec, TableByDefaultAndAClearErrorForAMissingMesh) {
  int code = -1;
  const std::string table =
      run(fqbench("--codec '" + std::string(FQ_DATA_DIR) + "/fandisk.ply' --chunks 2 --threads 1 --repeat 1"),
          code);
  EXPECT_EQ(code, 0);
  EXPECT_NE(table.find("| encode wall ms |"), std::string::npos) << table;
  EXPECT_NE(table.find("| decode wall ms |"), std::string::npos) << table;
  EXPECT_NE(table.find("| result encode wall ms (input's chunks) |"), std::string::npos) << table;
  const std::string missing = run(fqbench("--codec no-such-mesh.ply --mesh-dir /nonexistent 2>&1"), code);
  EXPECT_EQ(code, 1);
  EXPECT_NE(missing.find("no-such-mesh.ply"), std::string::npos) << missing;
}

}  // namespace
