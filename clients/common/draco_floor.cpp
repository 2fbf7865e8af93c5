#include "clients/common/draco_floor.h"

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>

#include "common/sample_stats.h"
#include "common/thread_cpu.h"
#include "wire/frame_chunk.h"

namespace fq::client {

namespace wd = fq::wire::detail;

FloorChunks::FloorChunks() = default;
FloorChunks::FloorChunks(FloorChunks&&) noexcept = default;
FloorChunks::~FloorChunks() = default;

FloorChunks floor_chunks(const MeshView& mesh, uint32_t chunks, const wire::CodecOptions& opt) {
  FloorChunks f;
  f.box = wd::bounding_box(mesh, opt.threads);
  const auto parts = wd::split_parts(mesh, f.box, std::min(chunks, mesh.num_triangles), opt.threads);
  wd::ChunkScratch scratch;
  for (const auto& part : parts) {
    f.meshes.push_back(std::make_unique<draco::Mesh>());
    f.sequential.push_back(wd::build_chunk(mesh, nullptr, false, opt, part, scratch, *f.meshes.back()));
  }
  return f;
}

bool floor_encode(const FloorChunks& f, const wire::CodecOptions& opt, std::vector<std::string>& out) {
  out.assign(f.meshes.size(), {});
  std::vector<uint8_t> ok(f.meshes.size(), 0);
  wd::for_each_chunk(f.meshes.size(), opt.threads, [&](size_t i, size_t) {
    ok[i] = wd::encode_chunk(*f.meshes[i], f.sequential[i] != 0, opt, f.box, out[i]).ok();
  });
  return std::all_of(ok.begin(), ok.end(), [](uint8_t b) { return b != 0; });
}

bool floor_decode(const std::vector<std::string>& encoded, int threads) {
  std::vector<uint8_t> ok(encoded.size(), 0);
  wd::for_each_chunk(encoded.size(), threads, [&](size_t i, size_t) {
    draco::DecoderBuffer buf;
    buf.Init(encoded[i].data(), encoded[i].size());
    draco::Decoder dec;
    ok[i] = dec.DecodeMeshFromBuffer(&buf).ok();
  });
  return std::all_of(ok.begin(), ok.end(), [](uint8_t b) { return b != 0; });
}

FloorCpu floor_cpu(const MeshView& mesh, uint32_t chunks, const wire::CodecOptions& opt, int rounds) {
  const FloorChunks f = floor_chunks(mesh, chunks, opt);
  std::vector<double> encode, decode;
  std::vector<std::string> encoded;
  for (int r = 0; r < std::max(rounds, 1); ++r) {
    CpuAccount enc{0}, dec{0};
    bool ok = true;
    {
      const CpuScope scope(enc);
      ok = floor_encode(f, opt, encoded);
    }
    {
      const CpuScope scope(dec);
      ok = ok && floor_decode(encoded, opt.threads);
    }
    if (!ok) return {};
    encode.push_back(double(enc.load()) * 1e-6);
    decode.push_back(double(dec.load()) * 1e-6);
  }
  return {median(encode), median(decode)};
}

}  // namespace fq::client
