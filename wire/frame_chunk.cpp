// One chunk of a frame as a draco::Mesh, and its encoding on the frame's quantization grid.
#include "wire/frame_chunk.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/metadata/metadata_encoder.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>
#include <type_traits>

#include "wire/draco_sequential.h"
#include "wire/vertex_id_runs.h"

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

/// Marks the vertices of `size` corners in `seen` (one bit per frame vertex). Four interleaved
/// streams over the corners: neighbouring corners hit the same word, and one stream's
/// read-modify-writes would wait on each other.
void mark_corners(uint64_t* seen, const uint32_t* c, size_t size) {
  const size_t q = size / 4;
  for (size_t i = 0; i < q; ++i) {
    seen[c[i] >> 6] |= uint64_t{1} << (c[i] & 63);
    seen[c[q + i] >> 6] |= uint64_t{1} << (c[q + i] & 63);
    seen[c[2 * q + i] >> 6] |= uint64_t{1} << (c[2 * q + i] & 63);
    seen[c[3 * q + i] >> 6] |= uint64_t{1} << (c[3 * q + i] & 63);
  }
  for (size_t i = 4 * q; i < size; ++i) seen[c[i] >> 6] |= uint64_t{1} << (c[i] & 63);
}

/// Marks the vertices of `part` in scratch.seen; returns how many vertices the chunk has.
uint32_t mark_part(const fq::MeshView& mesh, const Part& part, ChunkScratch& scratch) {
  const size_t words = (size_t(mesh.num_vertices) + 63) / 64;
  scratch.seen.resize(words, 0);
  uint64_t* seen = scratch.seen.data();
  for (const TriangleRun& r : part.runs)
    mark_corners(seen, mesh.triangles + 3 * size_t(r.first), 3 * size_t(r.count));
  size_t n = 0;
  for (size_t w = 0; w < words; ++w) n += size_t(std::popcount(seen[w]));
  return static_cast<uint32_t>(n);
}

/// Walks the chunk's points: its vertices in ascending global id (the marked bits in order),
/// calling fn(i, g) for point i = vertex g and setting scratch.local[g] = i. Ascending ids keep
/// the input's vertex order, usually spatially coherent, for Draco's sequential coder, and make
/// the ids a few long runs. Clears the bitmap for the next chunk (ORing it into scratch.used
/// first). One pass: the points' data is gathered by `fn` as they are numbered.
template <class Fn>
void for_each_point(const fq::MeshView& mesh, ChunkScratch& scratch, Fn&& fn) {
  if (scratch.local_size < mesh.num_vertices) {
    scratch.local.reset(new uint32_t[mesh.num_vertices]);
    scratch.local_size = mesh.num_vertices;
  }
  uint64_t* seen = scratch.seen.data();
  uint32_t* local = scratch.local.get();
  uint32_t i = 0;
  for (size_t w = 0; w < scratch.seen.size(); ++w) {
    if (seen[w] == 0) continue;
    for (uint64_t bits = seen[w]; bits != 0; bits &= bits - 1, ++i) {
      const auto g = static_cast<uint32_t>(w * 64 + size_t(std::countr_zero(bits)));
      local[g] = i;
      fn(i, g);
    }
    if (scratch.used != nullptr) scratch.used[w].fetch_or(seen[w], std::memory_order_relaxed);
    seen[w] = 0;  // all zero again for the next chunk
  }
}

/// Calls fn(first corner) for each triangle of `part`, in order.
template <class Fn>
void for_each_triangle(const fq::MeshView& mesh, const Part& part, Fn&& fn) {
  for (const TriangleRun& r : part.runs) {
    const uint32_t* f = mesh.triangles + 3 * size_t(r.first);
    for (uint32_t k = 0; k < r.count; ++k, f += 3) fn(f);
  }
}

/// Whether a triangle of `part` repeats a vertex.
bool repeats_a_vertex(const fq::MeshView& mesh, const Part& part) {
  for (const TriangleRun& r : part.runs) {
    const uint32_t* f = mesh.triangles + 3 * size_t(r.first);
    for (uint32_t k = 0; k < r.count; ++k, f += 3)
      if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) return true;
  }
  return false;
}

/// A sequential chunk's geometry metadata: its id runs and, with labels, the label
/// attribute's name (what build_chunk gives draco::Encoder).
draco::GeometryMetadata chunk_metadata(const std::vector<uint8_t>& runs, bool labelled) {
  draco::GeometryMetadata metadata;
  metadata.AddEntryBinary(kVertexIdRunsEntry, runs);
  if (labelled) {
    auto label_metadata = std::make_unique<draco::AttributeMetadata>();
    label_metadata->AddEntryString("name", kLabelAttribute);
    label_metadata->set_att_unique_id(1);  // the second attribute
    metadata.AddAttributeMetadata(std::move(label_metadata));
  }
  return metadata;
}

/// A sequential chunk's attributes, in build_chunk's order: positions, then the labels.
std::vector<AttributeSpec> chunk_attributes(bool labelled) {
  std::vector<AttributeSpec> specs = {{draco::GeometryAttribute::POSITION, draco::DT_FLOAT32, 3,
                                       draco::SEQUENTIAL_ATTRIBUTE_ENCODER_QUANTIZATION}};
  if (labelled)
    specs.push_back({draco::GeometryAttribute::GENERIC, draco::DT_UINT32, 1,
                     draco::SEQUENTIAL_ATTRIBUTE_ENCODER_INTEGER});
  return specs;
}

}  // namespace

bool sequential_chunk(const fq::MeshView& mesh, const CodecOptions& o, const Part& part) {
  // Draco's sequential coder at speed 10, or when a face repeats a vertex (edgebreaker would
  // drop it); only then does it keep point order, which the id runs rely on.
  return o.encode_speed == 10 || repeats_a_vertex(mesh, part);
}

bool build_chunk(const fq::MeshView& mesh, const uint32_t* labels, bool with_ids, const CodecOptions& o,
                 const Part& part, ChunkScratch& scratch, draco::Mesh& m) {
  const bool sequential = sequential_chunk(mesh, o, part);
  const uint32_t n = mark_part(mesh, part, scratch);
  m.set_num_points(n);
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
  draco::PointAttribute* pos = m.attribute(m.AddAttribute(ga, true, n));
  auto* xyz = reinterpret_cast<float*>(pos->buffer()->data());  // n packed triples (identity mapping)
  IdRunWriter runs;
  std::vector<uint32_t> global;
  global.reserve(n);
  const bool write_runs = with_ids && sequential;
  for_each_point(mesh, scratch, [&](uint32_t i, uint32_t g) {
    global.push_back(g);
    std::memcpy(xyz + 3 * size_t(i), mesh.positions + 3 * size_t(g), 3 * sizeof(float));
    if (write_runs) runs.add(g);
  });
  const uint32_t* local = scratch.local.get();
  const auto point_of = [local](uint32_t g) { return draco::PointIndex(local[g]); };
  m.SetNumFaces(part.triangles);
  uint32_t face = 0;
  for_each_triangle(mesh, part, [&](const uint32_t* f) {
    m.SetFace(draco::FaceIndex(face++), {point_of(f[0]), point_of(f[1]), point_of(f[2])});
  });
  // Geometry metadata first: AddAttributeMetadata creates (and AddMetadata would replace) it.
  if (write_runs) {
    auto md = std::make_unique<draco::GeometryMetadata>();
    md->AddEntryBinary(kVertexIdRunsEntry, runs.finish());
    m.AddMetadata(std::move(md));
  }
  if (with_ids && !sequential) add_uint_attribute(m, kVertexIdAttribute, global, nullptr);
  if (labels) add_uint_attribute(m, kLabelAttribute, global, labels);
  return sequential;
}

fq::Status write_sequential_chunk(const fq::MeshView& mesh, const uint32_t* labels, const Part& part,
                                  const CodecOptions& o, const Box& box, ChunkScratch& scratch,
                                  std::string& out) {
  const uint32_t n = mark_part(mesh, part, scratch);
  const PositionQuantizer quantize(box, o.position_bits);
  SequentialScratch& coder = scratch.coder;
  coder.quantized.resize(3 * size_t(n));
  coder.label_values.resize(labels != nullptr ? n : 0);
  int32_t* q = coder.quantized.data();
  int32_t* l = coder.label_values.data();
  ValueBounds position_bounds, label_bounds;
  IdRunWriter runs;
  // One pass numbers the points, quantizes their positions (what Draco's quantization
  // transform would compute from a gathered copy), finds the wrap bounds and codes the ids.
  for_each_point(mesh, scratch, [&](uint32_t i, uint32_t g) {
    const float* p = mesh.positions + 3 * size_t(g);
    for (int a = 0; a < 3; ++a) {
      const int32_t v = quantize(p[a], a);
      q[3 * size_t(i) + size_t(a)] = v;
      position_bounds.add(v);
    }
    runs.add(g);
    if (labels != nullptr) {
      l[i] = static_cast<int32_t>(labels[g]);  // below kMaxAttributeValue: checked by the caller
      label_bounds.add(l[i]);
    }
  });
  const draco::GeometryMetadata metadata = chunk_metadata(runs.finish(), labels != nullptr);
  draco::EncoderBuffer& buf = coder.buffer;
  buf.Clear();  // keeps its capacity
  buf.buffer()->reserve(256 + 6 * size_t(part.triangles) + 8 * size_t(n));
  write_header(buf, true, true);
  if (!draco::MetadataEncoder().EncodeGeometryMetadata(&buf, &metadata))
    return {fq::StatusCode::kInternal, "Draco could not encode the chunk's metadata"};
  const uint32_t* local = scratch.local.get();
  write_connectivity(buf, part.triangles, n, [&](auto&& put) {
    for_each_triangle(mesh, part, [&](const uint32_t* f) {
      put(local[f[0]]);
      put(local[f[1]]);
      put(local[f[2]]);
    });
  });
  write_attribute_specs(buf, chunk_attributes(labels != nullptr));
  const int level = symbol_compression_level(o);
  if (!write_delta_values(q, n, 3, position_bounds, level, coder.symbols, buf) ||
      (labels != nullptr && !write_delta_values(l, n, 1, label_bounds, level, coder.symbols, buf)))
    return {fq::StatusCode::kInternal, "Draco's symbol coder failed"};
  quantize.write_parameters(buf);  // the labels' integer coder has no parameters
  out.assign(buf.data(), buf.size());
  return {};
}

ScratchPool<ChunkScratch>& chunk_scratch() {
  static ScratchPool<ChunkScratch> pool;
  return pool;
}

namespace {

template <class Geometry>
fq::Status encode_with_grid(const Geometry& g, int method, const CodecOptions& o, const Box& box,
                            std::string& out) {
  draco::Encoder enc;
  enc.SetSpeedOptions(o.encode_speed, o.decode_speed);
  enc.SetEncodingMethod(method);
  enc.SetAttributeExplicitQuantization(draco::GeometryAttribute::POSITION, o.position_bits, 3, box.lo,
                                       grid_range(box));
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
