// Encode/decode time of the chunked frame codec on the shared meshes (a benchmark, not a test),
// in the two result forms: "mesh" (encode_frame / decode_frame: positions and connectivity)
// and "positions" (encode_positions / decode_positions: the positions alone).
// Prints a Markdown table (median of --repeats runs per row); see --help.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include "common/sample_stats.h"
#include "common/tool_main.h"
#include "tests/wire/wire_test_meshes.h"
#include "wire/frame_codec.h"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// CPU time of the whole process (all threads), in ms: less sensitive to a loaded machine than wall time.
double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

using fq::median;

bool encode(const std::string& form, const fq::Mesh& m, uint32_t chunks, const fq::wire::CodecOptions& o,
            std::vector<std::string>& out) {
  if (form == "mesh") return fq::wire::encode_frame(m.view(), nullptr, chunks, o, out).ok();
  return fq::wire::encode_positions(m.positions.data(), m.num_vertices(), chunks, o, out).ok();
}

/// Decodes into `out`, which lives across the repeats as fqd's pooled meshes do (a fresh mesh
/// each time would time page faults of its first touch, not the codec).
bool decode(const std::string& form, const std::vector<std::string_view>& chunks, const fq::Mesh& m,
            const fq::wire::CodecOptions& o, fq::Mesh& out) {
  if (form == "mesh") return fq::wire::decode_frame(chunks, m.num_vertices(), o, out, nullptr).ok();
  return fq::wire::decode_positions(chunks, m.num_vertices(), o, out.positions).ok();
}

void bench(const std::string& name, const std::string& form, const fq::Mesh& m,
           const fq::wire::CodecOptions& o, const std::vector<uint32_t>& chunk_counts, int repeats) {
  for (uint32_t chunks : chunk_counts) {
    std::vector<double> enc_ms, dec_ms, enc_cpu, dec_cpu;
    size_t bytes = 0;
    fq::Mesh out;
    for (int r = 0; r < repeats; ++r) {
      std::vector<std::string> encoded;
      auto t0 = Clock::now();
      double c0 = cpu_ms();
      if (!encode(form, m, chunks, o, encoded)) std::exit(1);
      enc_ms.push_back(ms_since(t0));
      enc_cpu.push_back(cpu_ms() - c0);
      bytes = 0;
      for (const auto& c : encoded) bytes += c.size();
      std::vector<std::string_view> views(encoded.begin(), encoded.end());
      t0 = Clock::now();
      c0 = cpu_ms();
      if (!decode(form, views, m, o, out)) std::exit(1);
      dec_ms.push_back(ms_since(t0));
      dec_cpu.push_back(cpu_ms() - c0);
    }
    std::printf("| %s | %s | %u | %u | %u | %d | %d | %.1f | %.1f | %.1f | %.1f | %zu |\n", name.c_str(),
                form.c_str(), m.num_vertices(), m.num_triangles(), chunks, o.threads, o.encode_speed,
                median(enc_ms), median(enc_cpu), median(dec_ms), median(dec_cpu), bytes);
  }
}

int run(int argc, char** argv) {
  CLI::App app{"Encode/decode time of the chunked Draco frame codec on the shared meshes"};
  fq::wire::CodecOptions o;
  o.threads = 2;
  int repeats = 5;
  std::vector<uint32_t> chunk_counts{1, 2, 4};
  std::vector<std::string> meshes{"bunny.ply", "igea.ply"};
  std::vector<std::string> forms{"mesh", "positions"};
  app.add_option("--threads", o.threads, "codec threads")->check(CLI::Range(1, 256));
  app.add_option("--speed", o.encode_speed, "Draco encode and decode speed")->check(CLI::Range(0, 10));
  app.add_option("--bits", o.position_bits, "position quantization bits")->check(CLI::Range(1, 30));
  app.add_option("--repeats", repeats, "runs per row (median reported)")->check(CLI::Range(1, 1000));
  app.add_option("--chunks", chunk_counts, "chunk counts")->check(CLI::Range(1u, fq::wire::kMaxChunks));
  app.add_option("--form", forms, "result forms: mesh, positions")
      ->check(CLI::IsMember({"mesh", "positions"}))
      ->capture_default_str();
  app.add_option("meshes", meshes, "PLY files in FQ_MESH_DIR");
  CLI11_PARSE(app, argc, argv);
  o.decode_speed = o.encode_speed;
  std::printf(
      "| mesh | form | V | F | chunks | threads | speed | encode wall ms | encode CPU ms | decode wall ms | "
      "decode CPU ms | bytes |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& file : meshes) {
    const auto m = fq::test_wire::load_shared_mesh(file);
    if (!m) {
      std::fprintf(stderr, "%s not found (set FQ_MESH_DIR)\n", file.c_str());
      return 1;
    }
    for (const auto& form : forms) bench(file, form, *m, o, chunk_counts, repeats);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fq::tool_main("fq_frame_codec_bench", run, argc, argv); }
