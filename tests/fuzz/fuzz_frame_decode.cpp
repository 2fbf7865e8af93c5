// libFuzzer target: one ingest chunk through what fqd does with it — the decoded-size
// budget read from the Draco header, then the frame decoder and the mesh checks — and through
// what a consumer does with a POSITIONS result (decode_positions). The first byte picks the
// vertex count the frame header claims (0 = infer, else a small count).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/mesh_checks.h"
#include "wire/draco_budget.h"
#include "wire/frame_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint32_t vertex_count = data[0] < 128 ? 0u : uint32_t(data[0]) * 64u;
  const std::string_view chunk(reinterpret_cast<const char*>(data + 1), size - 1);
  fq::wire::ChunkBudget budget;
  budget.max_points = 1u << 20;  // as fqd's caps, scaled to the fuzzer's memory limit
  if (!fq::wire::check_chunk_budget(chunk, budget).ok()) return 0;
  fq::wire::CodecOptions o;
  o.threads = 1;
  fq::Mesh mesh;
  std::vector<uint32_t> labels;
  if (fq::wire::decode_frame({chunk}, vertex_count, o, mesh, &labels).ok()) (void)fq::check_mesh(mesh.view());
  // The same bytes as a POSITIONS result, as a consumer decodes one.
  std::vector<float> positions;
  (void)fq::wire::decode_positions({chunk}, vertex_count, o, positions);
  return 0;
}
