// decode_frame: decode the chunks concurrently (the codec's own sequential chunks directly,
// any other Draco mesh through Draco's decoder), then merge them by global vertex id.
#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <exception>
#include <memory>
#include <span>
#include <string>

#include "common/scratch_pool.h"
#include "wire/draco_sequential.h"
#include "wire/draco_sequential_read.h"
#include "wire/frame_chunk.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"
#include "wire/vertex_id_runs.h"

namespace fq::wire {
namespace {

/// One decoded chunk, per Draco point: read by Draco into `mesh`, or (the codec's own
/// sequential chunks) directly into `direct`.
struct Chunk {
  fq::Status status;
  std::unique_ptr<draco::Mesh> mesh;  ///< kept: xyz may point into its position buffer
  detail::SequentialChunk direct;     ///< when read without Draco's decoder (mesh is null)
  const float* xyz = nullptr;         ///< 3 per point, in mesh, direct or positions
  uint32_t points = 0;
  std::vector<float> positions;  ///< only when Draco's positions needed converting
  std::vector<uint32_t> ids;     ///< fq_vid per point; empty when the chunk has none
  std::vector<uint32_t> labels;  ///< fq_label per point; empty when the chunk has none
  uint32_t faces = 0;            ///< read from mesh's faces where they are used (no copy)

  /// Empty for the next frame; the vectors keep their capacity.
  void reset() {
    status = {};
    mesh.reset();
    xyz = nullptr;
    points = faces = 0;
    positions.clear();
    ids.clear();
    labels.clear();
  }
};

/// A frame's decoded chunks, borrowed for the frame and kept for the next: a stream's next
/// frame of about the same size decodes without allocating (on a virtual machine the first
/// touch of each fresh page is a fault, which cost more than the decoding itself). Each holds
/// what the largest frame it decoded needed, up to kKeptChunkBytes; release_memory() frees them.
constexpr size_t kKeptChunkBytes = size_t(256) << 20;
ScratchPool<std::vector<Chunk>>& decoded_chunks() {
  static ScratchPool<std::vector<Chunk>> pool;
  return pool;
}

/// Calls fn(f, k, point index) for every corner k of every face f of a decoded chunk.
template <class Fn>
void for_each_corner(const Chunk& c, Fn&& fn) {
  if (c.mesh == nullptr) {
    const uint32_t* p = c.direct.corners.data();
    for (uint32_t f = 0; f < c.faces; ++f, p += 3) {
      for (int k = 0; k < 3; ++k) fn(f, k, p[k]);
    }
    return;
  }
  for (uint32_t f = 0; f < c.faces; ++f) {
    const auto& face = c.mesh->face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) fn(f, k, face[k].value());
  }
}

fq::Status face_out_of_range(uint32_t f) {
  return invalid_input("face " + std::to_string(f) + " out of range");
}

/// Values of the single-component integer attribute named `name` (false when it is malformed).
bool read_uint_attribute(const draco::Mesh& m, const char* name, bool& present, std::vector<uint32_t>& out) {
  const int id = m.GetAttributeIdByMetadataEntry("name", name);
  present = id >= 0;
  if (!present) return true;
  const draco::PointAttribute* pa = m.attribute(id);
  if (pa->num_components() != 1 || pa->data_type() != draco::DT_UINT32) return false;
  out.resize(m.num_points());
  for (uint32_t p = 0; p < m.num_points(); ++p) {
    if (!pa->ConvertValue<uint32_t>(pa->mapped_index(draco::PointIndex(p)), 1, &out[p])) return false;
  }
  return true;
}

/// Positions of every point into c.xyz: Draco's own buffer when it decoded them as packed float
/// triples with an identity point mapping (what the codec's own chunks give), a conversion per
/// point into c.positions otherwise.
fq::Status read_positions(const draco::Mesh& m, Chunk& c) {
  const draco::PointAttribute* pos = m.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (pos == nullptr || pos->num_components() != 3) return invalid_input("no 3D position attribute");
  c.points = m.num_points();
  constexpr int64_t kPackedXyz = int64_t{3} * int64_t{sizeof(float)};
  if (pos->is_mapping_identity() && pos->data_type() == draco::DT_FLOAT32 &&
      pos->byte_stride() == kPackedXyz && pos->size() >= m.num_points() && m.num_points() > 0) {
    c.xyz = reinterpret_cast<const float*>(pos->GetAddress(draco::AttributeValueIndex(0)));
    return {};
  }
  c.positions.resize(3 * size_t(m.num_points()));
  for (uint32_t p = 0; p < m.num_points(); ++p) {
    if (!pos->ConvertValue<float>(pos->mapped_index(draco::PointIndex(p)), 3, &c.positions[3 * size_t(p)])) {
      return invalid_input("unreadable position of point " + std::to_string(p));
    }
  }
  c.xyz = c.positions.data();
  return {};
}

/// Global vertex ids: the "fq_vid" attribute, or the runs of a sequentially coded chunk.
fq::Status read_ids(const draco::Mesh& m, bool sequential, std::vector<uint32_t>& ids) {
  bool has = false;
  if (!read_uint_attribute(m, kVertexIdAttribute, has, ids)) {
    return invalid_input(std::string(kVertexIdAttribute) + " is not a single uint32 per point");
  }
  std::vector<uint8_t> runs;
  if (has || m.GetMetadata() == nullptr || !m.GetMetadata()->GetEntryBinary(kVertexIdRunsEntry, &runs))
    return {};
  // Runs name points in Draco's point order, which only the sequential coder keeps.
  if (!sequential)
    return invalid_input(std::string(kVertexIdRunsEntry) + " in a chunk not sequentially coded");
  if (!detail::decode_id_runs(runs.data(), runs.size(), m.num_points(), kMaxAttributeValue, ids)) {
    return invalid_input(std::string(kVertexIdRunsEntry) + " is malformed or does not match the " +
                         std::to_string(m.num_points()) + " points");
  }
  return {};
}

fq::Status read_mesh(const draco::Mesh& m, bool sequential, Chunk& c) {
  if (m.num_faces() == 0) return invalid_input("mesh has no faces");
  if (auto s = read_positions(m, c); !s.ok()) return s;
  if (auto s = read_ids(m, sequential, c.ids); !s.ok()) return s;
  bool has = false;
  if (!read_uint_attribute(m, kLabelAttribute, has, c.labels)) {
    return invalid_input(std::string(kLabelAttribute) + " is not a single uint32 per point");
  }
  // The faces are read (and their indices checked) where they are mapped to global ids: a
  // copy here was a pass of its own over 12 bytes a triangle.
  c.faces = m.num_faces();
  return {};
}

void decode_chunk(std::string_view bytes, Chunk& c) {
  // The codec's own sequential chunks without a draco::Mesh; any other (and any this reader
  // does not take) through Draco's decoder.
  if (detail::read_sequential_chunk(bytes, kMaxAttributeValue, c.direct)) {
    c.points = c.direct.points;
    c.faces = c.direct.faces;
    c.xyz = c.direct.positions.data();
    c.ids.swap(c.direct.ids);
    c.labels.swap(c.direct.labels);
    return;
  }
  draco::DecoderBuffer buf;
  buf.Init(bytes.data(), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buf);
  if (!type.ok()) {
    c.status = invalid_input("undecodable Draco data: " + type.status().error_msg_string());
    return;
  }
  if (type.value() != draco::TRIANGULAR_MESH) {
    c.status = invalid_input("a Draco point cloud, not a triangle mesh");
    return;
  }
  draco::Decoder dec;
  auto mesh = dec.DecodeMeshFromBuffer(&buf);
  if (!mesh.ok()) {
    c.status = invalid_input("undecodable Draco data: " + mesh.status().error_msg_string());
    return;
  }
  // Draco's header: "DRACO", version (2 bytes), encoder type, encoder method (0 = sequential).
  const bool sequential = bytes.size() > 8 && bytes[8] == 0;
  c.mesh = std::move(mesh).value();
  c.status = read_mesh(*c.mesh, sequential, c);
}

/// A single chunk without fq_vid: a plain Draco mesh, taken in Draco's point order.
fq::Status take_plain(Chunk& c, uint32_t vertex_count, fq::Mesh& out, std::vector<uint32_t>* labels) {
  const uint32_t n = c.points;
  if (vertex_count != 0 && vertex_count != n) {
    return invalid_input("frame header says " + std::to_string(vertex_count) +
                         " vertices, the Draco mesh has " + std::to_string(n));
  }
  out.positions.assign(c.xyz, c.xyz + 3 * size_t(n));
  out.triangles.resize(3 * size_t(c.faces));
  uint32_t bad_face = c.faces;
  for_each_corner(c, [&](uint32_t f, int k, uint32_t p) {
    if (p >= n) bad_face = std::min(bad_face, f);
    out.triangles[3 * size_t(f) + size_t(k)] = p;
  });
  if (bad_face < c.faces) return face_out_of_range(bad_face);
  if (labels) *labels = std::move(c.labels);
  return {};
}

/// Number of vertices of the merged frame: `vertex_count`, or inferred from the largest id.
/// Bounded by the points the chunks carry, so a forged count cannot trigger a huge allocation.
fq::Status merged_count(std::span<const Chunk> cs, uint32_t vertex_count, uint32_t& n) {
  size_t points = 0;
  uint32_t max_id = 0;
  for (const auto& c : cs) {
    points += c.ids.size();
    if (vertex_count == 0) max_id = std::max(max_id, *std::max_element(c.ids.begin(), c.ids.end()));
  }
  n = vertex_count != 0 ? vertex_count : max_id + 1;
  if (n > points) {
    return invalid_input("frame has " + std::to_string(n) + " vertices but its chunks carry only " +
                         std::to_string(points) + " points");
  }
  return {};
}

/// Writes chunk c's points to their global slots and maps its triangles to global ids, at
/// `triangles`. The first fault: a point with an id >= n, or a face naming a point the chunk
/// does not have. Chunks run concurrently: a vertex on a cut is in several chunks, which write
/// the same position (one quantization grid), label and coverage, through relaxed atomic
/// stores (plain stores on x86) so that the concurrent writes are well defined.
fq::Status scatter_chunk(const Chunk& c, uint32_t n, bool with_labels, float* positions, uint32_t* labels,
                         uint8_t* covered, uint32_t* triangles) {
  for (size_t p = 0; p < c.ids.size(); ++p) {
    const uint32_t g = c.ids[p];
    if (g >= n) {
      return invalid_input("vertex id " + std::to_string(g) + " out of range (frame has " +
                           std::to_string(n) + " vertices)");
    }
    for (int k = 0; k < 3; ++k)
      std::atomic_ref<float>(positions[3 * size_t(g) + k]).store(c.xyz[3 * p + k], std::memory_order_relaxed);
    if (with_labels) std::atomic_ref<uint32_t>(labels[g]).store(c.labels[p], std::memory_order_relaxed);
    std::atomic_ref<uint8_t>(covered[g]).store(1, std::memory_order_relaxed);
  }
  uint32_t bad_face = c.faces;
  for_each_corner(c, [&](uint32_t f, int k, uint32_t p) {
    if (p >= c.points) {
      bad_face = std::min(bad_face, f);
      return;
    }
    triangles[3 * size_t(f) + size_t(k)] = c.ids[p];
  });
  return bad_face < c.faces ? face_out_of_range(bad_face) : fq::Status{};
}

fq::Status merge(std::span<Chunk> cs, uint32_t n, int threads, fq::Mesh& out, std::vector<uint32_t>* labels) {
  const bool with_labels =
      labels && std::all_of(cs.begin(), cs.end(), [](const Chunk& c) { return !c.labels.empty(); });
  // Sized, not cleared: every slot is written by a chunk or the frame is refused below (a
  // hole), so zero-filling 12 bytes a vertex on one thread would be wasted; and a reused mesh
  // of the same size (a stream's next frame) keeps its pages.
  out.positions.resize(3 * size_t(n));
  if (with_labels) labels->resize(n);
  std::vector<uint8_t> covered(n, 0);
  // Triangles come out chunk after chunk, each chunk's at its own offset.
  std::vector<size_t> first(cs.size() + 1, 0);
  for (size_t i = 0; i < cs.size(); ++i) first[i + 1] = first[i] + 3 * size_t(cs[i].faces);
  out.triangles.resize(first.back());
  std::vector<fq::Status> fault(cs.size());
  detail::for_each_chunk(cs.size(), threads, [&](size_t i, size_t) {
    fault[i] =
        scatter_chunk(cs[i], n, with_labels, out.positions.data(), with_labels ? labels->data() : nullptr,
                      covered.data(), out.triangles.data() + first[i]);
  });
  for (size_t i = 0; i < cs.size(); ++i) {  // the first fault in chunk order, whatever the threads did
    if (!fault[i].ok()) return invalid_input("chunk " + std::to_string(i) + ": " + fault[i].message());
  }
  const auto hole = std::find(covered.begin(), covered.end(), uint8_t{0});
  if (hole != covered.end()) {
    return invalid_input("vertex " + std::to_string(hole - covered.begin()) +
                         " is in no chunk (missing chunk?)");
  }
  return {};
}

/// Empties a mesh for an error result; its capacity stays for the next frame.
void empty(fq::Mesh& out, std::vector<uint32_t>* labels) {
  out.positions.clear();
  out.triangles.clear();
  if (labels) labels->clear();
}

fq::Status decode_into(const std::vector<std::string_view>& chunks, uint32_t vertex_count,
                       const CodecOptions& options, std::span<Chunk> cs, fq::Mesh& out,
                       std::vector<uint32_t>* labels, std::vector<uint32_t>* chunk_triangles) {
  if (labels) labels->clear();
  if (chunks.empty()) return invalid_input("frame has no Draco chunks");
  if (chunks.size() > kMaxChunks)
    return invalid_input("frame has more than " + std::to_string(kMaxChunks) + " chunks");

  detail::for_each_chunk(chunks.size(), options.threads, [&](size_t i, size_t) {
    try {
      decode_chunk(chunks[i], cs[i]);
    } catch (const std::exception& e) {  // bad_alloc on a forged chunk: this frame fails, not fqd
      cs[i].status = invalid_input(std::string("decoding failed: ") + e.what());
    }
  });
  for (size_t i = 0; i < cs.size(); ++i) {
    if (!cs[i].status.ok())
      return invalid_input("chunk " + std::to_string(i) + ": " + cs[i].status.message());
  }
  if (chunk_triangles) {
    for (const Chunk& c : cs) chunk_triangles->push_back(c.faces);
  }
  if (cs.size() == 1 && cs[0].ids.empty()) return take_plain(cs[0], vertex_count, out, labels);
  for (size_t i = 0; i < cs.size(); ++i) {
    if (cs[i].ids.empty()) {
      return invalid_input("chunk " + std::to_string(i) + " has no " + kVertexIdAttribute +
                           " attribute (required in a multi-chunk frame)");
    }
  }
  uint32_t n = 0;
  FQ_RETURN_IF_ERROR(merged_count(cs, vertex_count, n));
  return merge(cs, n, options.threads, out, labels);
}

}  // namespace

fq::Status decode_frame(const std::vector<std::string_view>& chunks, uint32_t vertex_count,
                        const CodecOptions& options, fq::Mesh& out, std::vector<uint32_t>* labels,
                        std::vector<uint32_t>* chunk_triangles) {
  if (chunk_triangles) chunk_triangles->clear();
  const size_t count = std::min(chunks.size(), size_t(kMaxChunks));
  const auto lease = decoded_chunks().borrow();
  std::vector<Chunk>& kept = *lease;
  if (kept.size() < count) kept.resize(count);
  for (size_t i = 0; i < count; ++i) kept[i].reset();
  fq::Status s = decode_into(chunks, vertex_count, options, std::span<Chunk>(kept.data(), count), out, labels,
                             chunk_triangles);
  size_t held = 0;  // every slot's, also those a larger earlier frame left
  for (Chunk& c : kept) {
    c.mesh.reset();  // Draco's meshes are not reused
    const detail::SequentialChunk& d = c.direct;
    held += 4 * (d.corners.capacity() + d.positions.capacity() + d.values.capacity() + d.ids.capacity() +
                 d.labels.capacity() + c.positions.capacity() + c.ids.capacity() + c.labels.capacity());
  }
  // A frame far beyond what a capture stream sends (a hostile one, say) does not leave its
  // buffers behind in every thread that decoded one.
  if (held > kKeptChunkBytes) std::vector<Chunk>().swap(kept);
  if (!s.ok()) {
    empty(out, labels);
    if (chunk_triangles) chunk_triangles->clear();
  }
  return s;
}

size_t release_memory() {
  return decoded_chunks().release() + detail::chunk_scratch().release() +
         detail::sequential_scratch().release();
}

}  // namespace fq::wire
