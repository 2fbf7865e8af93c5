// One chunk of a frame as a draco::Mesh, and its encoding on the frame's quantization grid.
#include "proto/frame_chunk.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>
#include <type_traits>

#include "proto/vertex_id_runs.h"

namespace fq::wire::detail {
namespace {

/// Adds a per-point GENERIC uint32 attribute named `name` (attribute metadata) with the values
/// values[global[i]] (or global[i] itself when values is null).
void add_uint_attribute(draco::Mesh& m, const char* name, const std::vector<uint32_t>& global,
                        const uint32_t* values) {
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_UINT32, false, sizeof(uint32_t), 0);
  const int id = m.AddAttribute(ga, true, static_cast<uint32_t>(global.size()));
  auto* out = reinterpret_cast<uint32_t*>(m.attribute(id)->buffer()->data());
  for (size_t i = 0; i < global.size(); ++i) out[i] = values ? values[global[i]] : global[i];
  auto md = std::make_unique<draco::AttributeMetadata>();
  md->AddEntryString("name", name);
  m.AddAttributeMetadata(id, std::move(md));
}

/// The chunk's vertices in ascending global id, with scratch.local[g] = their index. Ascending
/// ids keep the input's vertex order, usually spatially coherent, for Draco's sequential coder,
/// and make the ids a few long runs. A bitmap of the frame's vertices (V / 8 bytes, cache
/// resident) marks the chunk's ones; reading it back in order sorts them without a sort.
std::vector<uint32_t> chunk_vertices(const fq::MeshView& mesh, std::span<const uint32_t> corners,
                                     ChunkScratch& scratch) {
  const size_t words = (size_t(mesh.num_vertices) + 63) / 64;
  scratch.seen.resize(words, 0);
  if (scratch.local_size < mesh.num_vertices) {
    scratch.local.reset(new uint32_t[mesh.num_vertices]);
    scratch.local_size = mesh.num_vertices;
  }
  uint64_t* seen = scratch.seen.data();
  // Four interleaved streams over the corners: neighbouring corners hit the same word, and one
  // stream's read-modify-writes would wait on each other.
  const size_t q = corners.size() / 4;
  const uint32_t* c = corners.data();
  for (size_t i = 0; i < q; ++i) {
    seen[c[i] >> 6] |= uint64_t{1} << (c[i] & 63);
    seen[c[q + i] >> 6] |= uint64_t{1} << (c[q + i] & 63);
    seen[c[2 * q + i] >> 6] |= uint64_t{1} << (c[2 * q + i] & 63);
    seen[c[3 * q + i] >> 6] |= uint64_t{1} << (c[3 * q + i] & 63);
  }
  for (size_t i = 4 * q; i < corners.size(); ++i) seen[c[i] >> 6] |= uint64_t{1} << (c[i] & 63);
  std::vector<uint32_t> global;
  global.reserve(corners.size() / 6 + 16);
  for (size_t w = 0; w < words; ++w) {
    if (seen[w] == 0) continue;
    for (uint64_t bits = seen[w]; bits != 0; bits &= bits - 1) {
      const auto g = static_cast<uint32_t>(w * 64 + size_t(std::countr_zero(bits)));
      scratch.local[g] = static_cast<uint32_t>(global.size());
      global.push_back(g);
    }
    if (scratch.used != nullptr) scratch.used[w].fetch_or(seen[w], std::memory_order_relaxed);
    seen[w] = 0;  // all zero again for the next chunk
  }
  return global;
}

}  // namespace

bool build_chunk(const fq::MeshView& mesh, const uint32_t* labels, bool with_ids, const CodecOptions& o,
                 std::span<const uint32_t> corners, ChunkScratch& scratch, draco::Mesh& m) {
  const std::vector<uint32_t> global = chunk_vertices(mesh, corners, scratch);
  const uint32_t* local = scratch.local.get();
  const size_t faces = corners.size() / 3;
  m.SetNumFaces(faces);
  bool repeated_index = false;
  for (size_t t = 0; t < faces; ++t) {
    const uint32_t* f = corners.data() + 3 * t;
    repeated_index |= f[0] == f[1] || f[1] == f[2] || f[2] == f[0];
    m.SetFace(
        draco::FaceIndex(static_cast<uint32_t>(t)),
        {draco::PointIndex(local[f[0]]), draco::PointIndex(local[f[1]]), draco::PointIndex(local[f[2]])});
  }
  const auto n = static_cast<uint32_t>(global.size());
  m.set_num_points(n);
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
  draco::PointAttribute* pos = m.attribute(m.AddAttribute(ga, true, n));
  auto* xyz = reinterpret_cast<float*>(pos->buffer()->data());  // n packed triples (identity mapping)
  for (uint32_t i = 0; i < n; ++i) std::memcpy(xyz + 3 * size_t(i), mesh.positions + 3 * size_t(global[i]), 3 * sizeof(float));
  const bool sequential = repeated_index || o.encode_speed == 10;
  // Geometry metadata first: AddAttributeMetadata creates (and AddMetadata would replace) it.
  if (with_ids && sequential) {
    std::vector<uint8_t> runs;
    encode_id_runs(global, runs);
    auto md = std::make_unique<draco::GeometryMetadata>();
    md->AddEntryBinary(kVertexIdRunsEntry, runs);
    m.AddMetadata(std::move(md));
  }
  if (with_ids && !sequential) add_uint_attribute(m, kVertexIdAttribute, global, nullptr);
  if (labels) add_uint_attribute(m, kLabelAttribute, global, labels);
  return sequential;
}

namespace {

template <class Geometry>
fq::Status encode_with_grid(const Geometry& g, int method, const CodecOptions& o, const Box& box,
                            std::string& out) {
  draco::Encoder enc;
  enc.SetSpeedOptions(o.encode_speed, o.decode_speed);
  enc.SetEncodingMethod(method);
  const float extent = box.max_extent();
  enc.SetAttributeExplicitQuantization(draco::GeometryAttribute::POSITION, o.position_bits, 3, box.lo,
                                       extent > 0.f ? extent : 1.f);
  draco::EncoderBuffer buf;
  draco::Status s;
  if constexpr (std::is_same_v<Geometry, draco::Mesh>)
    s = enc.EncodeMeshToBuffer(g, &buf);
  else
    s = enc.EncodePointCloudToBuffer(g, &buf);
  if (!s.ok()) return {fq::StatusCode::kInternal, "Draco encoding failed: " + s.error_msg_string()};
  out.assign(buf.data(), buf.size());
  return {};
}

}  // namespace

fq::Status encode_on_grid(const draco::Mesh& m, int method, const CodecOptions& o, const Box& box,
                          std::string& out) {
  return encode_with_grid(m, method, o, box, out);
}

fq::Status encode_on_grid(const draco::PointCloud& pc, int method, const CodecOptions& o, const Box& box,
                          std::string& out) {
  return encode_with_grid(pc, method, o, box, out);
}

fq::Status encode_chunk(const draco::Mesh& m, bool sequential, const CodecOptions& o, const Box& box,
                        std::string& out) {
  // Edgebreaker drops faces with a repeated vertex; the sequential coder keeps every face as
  // is, and keeps point order (which kVertexIdRunsEntry relies on). Draco picks it at speed 10
  // anyway; naming it makes that explicit.
  return encode_on_grid(m, sequential ? draco::MESH_SEQUENTIAL_ENCODING : draco::MESH_EDGEBREAKER_ENCODING, o,
                        box, out);
}

}  // namespace fq::wire::detail
