// encode_frame: split, build one draco::Mesh per chunk (positions + fq_vid [+ fq_label]),
// encode the chunks concurrently on one shared quantization grid.
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>

#include <algorithm>
#include <exception>
#include <memory>
#include <string>

#include "proto/frame_codec.h"
#include "kernels/frame_prep.h"
#include "proto/frame_split.h"

namespace fq::wire {
namespace {

fq::Status check_options(const CodecOptions& o) {
  if (o.position_bits < 1 || o.position_bits > 30) {
    return invalid_argument("position_bits " + std::to_string(o.position_bits) + " outside [1, 30]");
  }
  if (o.encode_speed < 0 || o.encode_speed > 10 || o.decode_speed < 0 || o.decode_speed > 10) {
    return invalid_argument("Draco speeds must be in [0, 10]");
  }
  if (o.threads < 1) return invalid_argument("codec threads must be >= 1");
  return {};
}

/// The codec can only carry vertices that some triangle uses (Draco drops the others).
fq::Status check_all_used(const fq::MeshView& mesh) {
  std::vector<uint8_t> used(mesh.num_vertices, 0);
  for (size_t i = 0; i < size_t(mesh.num_triangles) * 3; ++i) used[mesh.triangles[i]] = 1;
  const auto it = std::find(used.begin(), used.end(), uint8_t{0});
  if (it == used.end()) return {};
  return invalid_input("vertex " + std::to_string(it - used.begin()) +
                       " is used by no triangle (the frame codec carries only vertices of triangles)");
}

fq::Status check_ranges(const fq::MeshView& mesh, const uint32_t* labels) {
  if (mesh.num_vertices > kMaxAttributeValue) {
    return invalid_input(std::to_string(mesh.num_vertices) + " vertices: the frame codec carries at most " +
                         std::to_string(kMaxAttributeValue));
  }
  for (uint32_t v = 0; labels && v < mesh.num_vertices; ++v) {
    if (labels[v] >= kMaxAttributeValue) {
      return invalid_argument("label " + std::to_string(labels[v]) + " of vertex " + std::to_string(v) +
                              " is not below " + std::to_string(kMaxAttributeValue));
    }
  }
  return {};
}

/// Adds a per-point GENERIC uint32 attribute named `name` (attribute metadata) with the values
/// values[global[i]] (or global[i] itself when values is null).
void add_uint_attribute(draco::Mesh& m, const char* name, const std::vector<uint32_t>& global,
                        const uint32_t* values) {
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_UINT32, false, sizeof(uint32_t), 0);
  const int id = m.AddAttribute(ga, true, static_cast<uint32_t>(global.size()));
  draco::PointAttribute* pa = m.attribute(id);
  for (size_t i = 0; i < global.size(); ++i) {
    const uint32_t v = values ? values[global[i]] : global[i];
    pa->SetAttributeValue(draco::AttributeValueIndex(static_cast<uint32_t>(i)), &v);
  }
  auto md = std::make_unique<draco::AttributeMetadata>();
  md->AddEntryString("name", name);
  m.AddAttributeMetadata(id, std::move(md));
}

constexpr uint32_t kNoLocal = ~0u;

/// The chunk's vertices in ascending global id, with local[g] = their index. Ascending ids make
/// fq_vid's deltas small (Draco's symbol coder is slow on a large alphabet) and keep the input's
/// vertex order, usually spatially coherent, for Draco's sequential coder.
std::vector<uint32_t> chunk_vertices(const fq::MeshView& mesh, const std::vector<uint32_t>& tris,
                                     std::vector<uint32_t>& local) {
  std::vector<uint32_t> global;
  global.reserve(tris.size() / 2 + 16);
  for (uint32_t t : tris) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t g = mesh.triangles[3 * size_t(t) + k];
      if (local[g] == kNoLocal) {
        local[g] = 0;  // seen
        global.push_back(g);
      }
    }
  }
  if (global.size() * 8 >= mesh.num_vertices) {  // a large chunk: a linear scan beats a sort
    global.clear();
    for (uint32_t g = 0; g < mesh.num_vertices; ++g) {
      if (local[g] != kNoLocal) global.push_back(g);
    }
  } else {
    std::sort(global.begin(), global.end());
  }
  for (size_t i = 0; i < global.size(); ++i) local[global[i]] = static_cast<uint32_t>(i);
  return global;
}

/// One chunk as a draco::Mesh (points = the chunk's vertices, see chunk_vertices). Built
/// directly (not with a mesh builder) so that no deduplication can merge two vertices.
/// `local` is the worker's global -> local map (num_vertices entries, all kNoLocal on entry
/// and on return). Returns whether a face repeats a vertex (edgebreaker would drop it).
bool build_chunk(const fq::MeshView& mesh, const uint32_t* labels, const std::vector<uint32_t>& tris,
                 std::vector<uint32_t>& local, draco::Mesh& m) {
  const std::vector<uint32_t> global = chunk_vertices(mesh, tris, local);
  m.SetNumFaces(tris.size());
  bool repeated_index = false;
  for (size_t t = 0; t < tris.size(); ++t) {
    const uint32_t* f = mesh.triangles + 3 * size_t(tris[t]);
    repeated_index |= f[0] == f[1] || f[1] == f[2] || f[2] == f[0];
    m.SetFace(
        draco::FaceIndex(static_cast<uint32_t>(t)),
        {draco::PointIndex(local[f[0]]), draco::PointIndex(local[f[1]]), draco::PointIndex(local[f[2]])});
  }
  for (uint32_t g : global) local[g] = kNoLocal;

  const auto n = static_cast<uint32_t>(global.size());
  m.set_num_points(n);
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 3 * sizeof(float), 0);
  draco::PointAttribute* pos = m.attribute(m.AddAttribute(ga, true, n));
  for (uint32_t i = 0; i < n; ++i) {
    pos->SetAttributeValue(draco::AttributeValueIndex(i), mesh.positions + 3 * size_t(global[i]));
  }
  add_uint_attribute(m, kVertexIdAttribute, global, nullptr);
  if (labels) add_uint_attribute(m, kLabelAttribute, global, labels);
  return repeated_index;
}

fq::Status encode_chunk(const draco::Mesh& m, bool repeated_index, const CodecOptions& o,
                        const detail::Box& box, std::string& out) {
  draco::Encoder enc;
  enc.SetSpeedOptions(o.encode_speed, o.decode_speed);
  // Edgebreaker drops faces with a repeated vertex; the sequential coder keeps every face as is.
  if (repeated_index) enc.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  // One explicit grid for every chunk: a vertex on a chunk border decodes identically in both.
  const float extent = box.max_extent();
  enc.SetAttributeExplicitQuantization(draco::GeometryAttribute::POSITION, o.position_bits, 3, box.lo,
                                       extent > 0.f ? extent : 1.f);
  draco::EncoderBuffer buf;
  const draco::Status s = enc.EncodeMeshToBuffer(m, &buf);
  if (!s.ok()) return {fq::StatusCode::kInternal, "Draco encoding failed: " + s.error_msg_string()};
  out.assign(buf.data(), buf.size());
  return {};
}

}  // namespace

fq::Status encode_frame(const fq::MeshView& mesh, const uint32_t* labels, uint32_t chunks,
                        const CodecOptions& options, std::vector<std::string>& out) {
  out.clear();
  if (auto s = check_options(options); !s.ok()) return s;
  if (chunks == 0 || chunks > kMaxChunks) {
    return invalid_argument("chunk count " + std::to_string(chunks) + " outside [1, " +
                            std::to_string(kMaxChunks) + "]");
  }
  if (auto s = fq::check_mesh(mesh); !s.ok()) return s;
  if (auto s = check_all_used(mesh); !s.ok()) return s;
  if (auto s = check_ranges(mesh, labels); !s.ok()) return s;

  const detail::Box box = detail::bounding_box(mesh);
  const auto parts = detail::split_triangles(mesh, box, std::min(chunks, mesh.num_triangles), options.threads);
  std::vector<std::string> encoded(parts.size());
  std::vector<fq::Status> status(parts.size());
  // Per worker, a dense global -> local vertex map: cheaper than sorting each chunk's ids.
  std::vector<std::vector<uint32_t>> local(detail::chunk_workers(parts.size(), options.threads));
  detail::for_each_chunk(parts.size(), options.threads, [&](size_t i, size_t w) {
    try {
      if (local[w].empty()) local[w].assign(mesh.num_vertices, kNoLocal);
      draco::Mesh m;
      const bool repeated_index = build_chunk(mesh, labels, parts[i], local[w], m);
      status[i] = encode_chunk(m, repeated_index, options, box, encoded[i]);
    } catch (const std::exception& e) {  // bad_alloc: a fault of this frame, not of the process
      status[i] = {fq::StatusCode::kInternal, std::string("encoding failed: ") + e.what()};
    }
  });
  for (size_t i = 0; i < parts.size(); ++i) {
    if (!status[i].ok()) return {status[i].code(), "chunk " + std::to_string(i) + ": " + status[i].message()};
  }
  out = std::move(encoded);
  return {};
}

}  // namespace fq::wire
