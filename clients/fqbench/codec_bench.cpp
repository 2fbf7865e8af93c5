// The floor (clients/common/draco_floor.h) is what a chunked codec built on Draco's own coder
// pays, on the same chunks and threads. fq writes its sequentially coded chunks itself
// (wire/draco_sequential.h: the same bytes draco::Encoder writes, without a draco::Mesh copy),
// so its encode can come in under this floor; the bytes column shows what the ids add.
#include "clients/fqbench/codec_bench.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "clients/common/draco_floor.h"
#include "clients/fqbench/bench_stats.h"
#include "io/mesh_io.h"
#include "wire/frame_chunk.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"

namespace fq::bench {
namespace {

size_t total_bytes(const std::vector<std::string>& parts) {
  size_t n = 0;
  for (const auto& p : parts) n += p.size();
  return n;
}

using client::floor_decode;
using client::floor_encode;
using client::FloorChunks;

struct Samples {
  std::vector<double> encode, decode, result_encode, floor_encode, floor_decode;  // wall ms
  std::vector<double> encode_cpu, decode_cpu, result_encode_cpu, floor_encode_cpu, floor_decode_cpu;
  size_t bytes = 0, floor_bytes = 0, chunks = 0;
};

/// One round: ours (encode, decode of what we encoded, and fqd's MESH result of the decoded
/// frame: encode_frame_as on the input's chunks), then the floor on the same chunks.
/// `back` lives across rounds, as fqd's pooled meshes do: decode_frame reuses its buffers.
bool one_round(const Mesh& mesh, const FloorChunks& f, uint32_t chunks, const wire::CodecOptions& opt,
               Mesh& back, Samples& s) {
  bool ok = true;
  std::vector<std::string> ours, result, floor;
  std::vector<uint32_t> counts;
  time_step([&] { return wire::encode_frame(mesh.view(), nullptr, chunks, opt, ours).ok(); }, ok, s.encode,
            s.encode_cpu);
  const std::vector<std::string_view> views(ours.begin(), ours.end());
  time_step([&] { return wire::decode_frame(views, mesh.num_vertices(), opt, back, nullptr, &counts).ok(); },
            ok, s.decode, s.decode_cpu);
  ok = ok && back.num_vertices() == mesh.num_vertices() && back.num_triangles() == mesh.num_triangles();
  time_step([&] { return ok && wire::encode_frame_as(back.view(), nullptr, counts, opt, result).ok(); }, ok,
            s.result_encode, s.result_encode_cpu);
  time_step([&] { return floor_encode(f, opt, floor); }, ok, s.floor_encode, s.floor_encode_cpu);
  time_step([&] { return floor_decode(floor, opt.threads); }, ok, s.floor_decode, s.floor_decode_cpu);
  s.bytes = total_bytes(ours);
  s.floor_bytes = total_bytes(floor);
  s.chunks = ours.size();
  return ok;
}

std::string resolve_path(const CodecBenchOptions& o) {
  if (std::filesystem::exists(o.mesh)) return o.mesh;
  return o.mesh_dir + "/" + o.mesh;
}

double median(const std::vector<double>& v) { return spread_of(v).median; }
double p90(const std::vector<double>& v) { return spread_of(v).p90; }

/// One measured quantity: fq's median against the floor's on the same chunks.
struct Compared {
  const char* key;    ///< JSON: key_ms, floor_key_ms, key_ratio
  const char* label;  ///< table row
  double fq, floor;
};

void print(const CodecBenchOptions& o, const Mesh& m, const Samples& s) {
  const Compared rows[] = {
      {"encode", "encode wall ms", median(s.encode), median(s.floor_encode)},
      {"decode", "decode wall ms", median(s.decode), median(s.floor_decode)},
      {"result_encode", "result encode wall ms (input's chunks)", median(s.result_encode),
       median(s.floor_encode)},
      {"encode_p90", "encode wall ms, p90", p90(s.encode), p90(s.floor_encode)},
      {"decode_p90", "decode wall ms, p90", p90(s.decode), p90(s.floor_decode)},
      {"encode_cpu", "encode CPU ms", median(s.encode_cpu), median(s.floor_encode_cpu)},
      {"decode_cpu", "decode CPU ms", median(s.decode_cpu), median(s.floor_decode_cpu)},
      {"result_encode_cpu", "result encode CPU ms", median(s.result_encode_cpu), median(s.floor_encode_cpu)}};
  if (o.json) {
    nlohmann::json j = {{"mesh", o.mesh},
                        {"vertices", m.num_vertices()},
                        {"triangles", m.num_triangles()},
                        {"chunks", s.chunks},
                        {"threads", o.threads},
                        {"speed", o.speed},
                        {"position_bits", o.position_bits},
                        {"repeat", o.repeat},
                        {"bytes", s.bytes},
                        {"floor_bytes", s.floor_bytes}};
    for (const Compared& r : rows) {
      const std::string key = r.key;
      j[key + "_ms"] = r.fq;
      j["floor_" + key + "_ms"] = r.floor;
      j[key + "_ratio"] = r.fq / r.floor;
    }
    std::printf("%s\n", j.dump().c_str());
    return;
  }
  std::printf("\n%s (%u V, %u F): %zu chunks, %d threads, Draco speed %d, %d-bit positions; median of %d\n\n",
              o.mesh.c_str(), m.num_vertices(), m.num_triangles(), s.chunks, o.threads, o.speed,
              o.position_bits, o.repeat);
  std::printf("| | fq | floor (plain Draco, positions only) | fq / floor |\n|---|---:|---:|---:|\n");
  for (const Compared& r : rows)
    std::printf("| %s | %.2f | %.2f | %.2f |\n", r.label, r.fq, r.floor, r.fq / r.floor);
  std::printf("| bytes | %zu | %zu | %.2f |\n", s.bytes, s.floor_bytes,
              double(s.bytes) / double(s.floor_bytes));
}

}  // namespace

int run_codec_bench(const CodecBenchOptions& o) {
  Mesh mesh;
  const std::string path = resolve_path(o);
  if (const Status st = io::read_mesh(path, mesh); !st.ok()) {
    std::fprintf(stderr, "fqbench: %s: %s\n", path.c_str(), st.message().c_str());
    return 1;
  }
  wire::CodecOptions opt;
  opt.threads = o.threads;
  opt.encode_speed = opt.decode_speed = o.speed;
  opt.position_bits = o.position_bits;
  const FloorChunks f = client::floor_chunks(mesh.view(), o.chunks, opt);
  Samples warm, s;
  Mesh back;
  if (!one_round(mesh, f, o.chunks, opt, back, warm)) {
    std::fprintf(stderr, "fqbench: the codec failed on %s\n", path.c_str());
    return 1;
  }
  for (int r = 0; r < o.repeat; ++r) {
    if (!one_round(mesh, f, o.chunks, opt, back, s)) {
      std::fprintf(stderr, "fqbench: the codec failed on %s\n", path.c_str());
      return 1;
    }
  }
  print(o, mesh, s);
  return 0;
}

}  // namespace fq::bench
