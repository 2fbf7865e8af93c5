// Writes the fuzzers' seed corpora from real frames: headers and Draco chunks of the
// bundled fandisk (several chunk counts and Draco speeds), the symbol streams of its
// sequential chunks and the example configuration.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "clients/common/frame_sender.h"
#include "io/mesh_io.h"
#include "wire/frame_codec.h"
#include "wire/header_codec.h"
#include "wire/sequential_layout.h"

namespace fs = std::filesystem;

static void put(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

/// fuzz_symbol_decode's input for the positions' symbols of a sequential chunk: two bytes that
/// ask for its values (3 components, at most 4095 points), then the stream and what follows it.
/// Empty for a chunk of another layout.
static std::string symbol_seed(const std::string& chunk) {
  fq::wire::detail::SequentialPlan plan;
  std::vector<uint32_t> ids;
  if (!fq::wire::detail::plan_sequential_chunk(chunk, fq::wire::kMaxAttributeValue, plan, ids)) return {};
  const uint32_t groups = std::min<uint32_t>(plan.layout.points, 4095);
  uint32_t first = (groups & 15) << 4;
  while (first % 3 != 2) ++first;  // components: 1 + first % 3
  return std::string{char(first), char(groups >> 4)} + chunk.substr(plan.values_at + 3);
}

int main(int argc, char** argv) {
  if (argc != 4) return 2;  // make_seeds MESH CONFIG OUTDIR
  const fs::path out = argv[3];
  for (const char* d : {"headers", "frame_decode", "config", "symbol_decode"})
    fs::create_directories(out / d);
  std::ifstream cfg(argv[2]);
  put(out / "config" / "fqd.toml", std::string(std::istreambuf_iterator<char>(cfg), {}));
  fq::Mesh m;
  if (!fq::io::read_mesh(argv[1], m).ok()) return 1;
  int n = 0;
  for (uint32_t chunks : {1u, 4u}) {
    for (int speed : {0, 5, 10}) {
      fq::client::FrameSpec spec;
      spec.stream_id = "seed";
      spec.chunks = chunks;
      spec.encode_speed = spec.decode_speed = speed;
      std::vector<std::string> parts;
      if (!fq::client::build_frame(m.view(), spec, uint64_t(n), parts).ok()) return 1;
      put(out / "headers" / ("frame" + std::to_string(n)), parts[1]);
      for (size_t i = 2; i < parts.size(); ++i) {
        const std::string name = std::to_string(n) + "_" + std::to_string(i);
        put(out / "frame_decode" / ("chunk" + name), std::string(1, '\0') + parts[i]);
        if (const std::string seed = symbol_seed(parts[i]); !seed.empty())
          put(out / "symbol_decode" / ("positions" + name), seed);
      }
      ++n;
    }
  }
  for (uint32_t chunks : {1u, 3u}) {  // POSITIONS results, as fqd publishes them
    std::vector<std::string> parts;
    if (!fq::wire::encode_positions(m.positions.data(), m.num_vertices(), chunks, fq::wire::CodecOptions{},
                                    parts)
             .ok())
      return 1;
    for (size_t i = 0; i < parts.size(); ++i)
      put(out / "frame_decode" / ("positions" + std::to_string(chunks) + "_" + std::to_string(i)),
          std::string(1, '\0') + parts[i]);
  }
  fq::wire::ResultHeader r;
  r.set_version(fq::wire::kWireVersion);
  r.set_stream_id("seed");
  r.set_sequence(7);
  put(out / "headers" / "result", r.SerializeAsString());
  fq::wire::ControlRequest q;
  q.set_version(fq::wire::kWireVersion);
  q.mutable_get_counters()->set_stream_id("seed");
  put(out / "headers" / "control", q.SerializeAsString());
  return 0;
}
