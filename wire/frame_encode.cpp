// encode_frame: split, encode the chunks concurrently on one shared quantization grid:
// sequential chunks (Draco speed 10) written straight from the frame, others built as a
// draco::Mesh (positions + fq_vid [+ fq_label]) and encoded by Draco.
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <exception>
#include <memory>
#include <string>

#include "core/mesh_checks.h"
#include "wire/frame_chunk.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"

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

fq::Status unused_vertex(size_t v) {
  return invalid_input("vertex " + std::to_string(v) +
                       " is used by no triangle (the frame codec carries only vertices of triangles)");
}

/// The codec can only carry vertices that some triangle uses (Draco drops the others). A pass
/// of its own, for the error path only: encode_frame marks used vertices while it builds chunks.
fq::Status check_all_used(const fq::MeshView& mesh) {
  std::vector<uint8_t> used(mesh.num_vertices, 0);
  for (size_t i = 0; i < size_t(mesh.num_triangles) * 3; ++i) used[mesh.triangles[i]] = 1;
  const auto it = std::find(used.begin(), used.end(), uint8_t{0});
  return it == used.end() ? fq::Status{} : unused_vertex(size_t(it - used.begin()));
}

/// The smallest vertex whose bit is clear in `used` (one bit per vertex), or n.
uint32_t first_unused(const std::vector<std::atomic<uint64_t>>& used, uint32_t n) {
  for (size_t w = 0; w < used.size(); ++w) {
    const uint64_t missing = ~used[w].load(std::memory_order_relaxed);
    if (missing == 0) continue;
    const uint64_t v = w * 64 + static_cast<uint64_t>(std::countr_zero(missing));
    return v < n ? static_cast<uint32_t>(v) : n;
  }
  return n;
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

/// The checks every encode makes: options, counts, finite coordinates and valid indices (in the
/// box's pass), label and id ranges. Sets `box`.
fq::Status check_frame(const fq::MeshView& mesh, const uint32_t* labels, const CodecOptions& options,
                       detail::Box& box) {
  FQ_RETURN_IF_ERROR(check_options(options));
  FQ_RETURN_IF_ERROR(fq::check_mesh_counts(mesh));
  // The box's pass checks the coordinates and indices too; check_mesh runs only to name a fault.
  bool valid = false;
  box = detail::bounding_box(mesh, options.threads, &valid);
  if (!valid) {
    fq::Status fault = fq::check_mesh(mesh, options.threads);
    return fault.ok() ? fq::Status{fq::StatusCode::kInternal, "mesh check disagrees with the box pass"}
                      : fault;
  }
  if (auto s = check_ranges(mesh, labels); !s.ok()) {
    if (auto u = check_all_used(mesh); !u.ok()) return u;  // the error reported first, as ever
    return s;
  }
  return {};
}

/// Builds and encodes the chunks `parts` of a checked frame, concurrently.
fq::Status encode_parts(const fq::MeshView& mesh, const uint32_t* labels,
                        const std::vector<detail::Part>& parts, const CodecOptions& options,
                        const detail::Box& box, std::vector<std::string>& out) {
  std::vector<std::string> encoded(parts.size());
  std::vector<fq::Status> status(parts.size());
  // Every vertex must be used: the chunks mark theirs while they are built (no extra pass).
  std::vector<std::atomic<uint64_t>> used((size_t(mesh.num_vertices) + 63) / 64);
  detail::for_each_chunk(parts.size(), options.threads, [&](size_t i, size_t) {
    const auto lease = detail::chunk_scratch().borrow();
    detail::ChunkScratch& scratch = *lease;
    scratch.used = used.data();
    try {
      if (detail::sequential_chunk(mesh, options, parts[i])) {
        status[i] = detail::write_sequential_chunk(mesh, labels, parts[i], options, box, scratch, encoded[i]);
      } else {
        draco::Mesh m;
        detail::build_chunk(mesh, labels, true, options, parts[i], scratch, m);
        status[i] = detail::encode_chunk(m, false, options, box, encoded[i]);
      }
    } catch (const std::exception& e) {  // bad_alloc: a fault of this frame, not of the process
      status[i] = {fq::StatusCode::kInternal, std::string("encoding failed: ") + e.what()};
      scratch = {};  // its bitmap may hold half a chunk
    }
    scratch.used = nullptr;  // this frame's bitmap dies with the call
  });
  for (size_t i = 0; i < parts.size(); ++i) {  // first: a failed chunk may not have marked its vertices
    if (!status[i].ok()) return {status[i].code(), "chunk " + std::to_string(i) + ": " + status[i].message()};
  }
  if (const uint32_t v = first_unused(used, mesh.num_vertices); v < mesh.num_vertices)
    return unused_vertex(v);
  out = std::move(encoded);
  return {};
}

}  // namespace

fq::Status encode_frame(const fq::MeshView& mesh, const uint32_t* labels, uint32_t chunks,
                        const CodecOptions& options, std::vector<std::string>& out) {
  out.clear();
  if (chunks == 0 || chunks > kMaxChunks) {
    FQ_RETURN_IF_ERROR(check_options(options));
    return invalid_argument("chunk count " + std::to_string(chunks) + " outside [1, " +
                            std::to_string(kMaxChunks) + "]");
  }
  detail::Box box;
  FQ_RETURN_IF_ERROR(check_frame(mesh, labels, options, box));
  const auto parts = detail::split_parts(mesh, box, std::min(chunks, mesh.num_triangles), options.threads);
  return encode_parts(mesh, labels, parts, options, box, out);
}

fq::Status encode_frame_as(const fq::MeshView& mesh, const uint32_t* labels,
                           const std::vector<uint32_t>& chunk_triangles, const CodecOptions& options,
                           std::vector<std::string>& out) {
  out.clear();
  FQ_RETURN_IF_ERROR(check_options(options));
  if (chunk_triangles.empty() || chunk_triangles.size() > kMaxChunks) {
    return invalid_argument(std::to_string(chunk_triangles.size()) + " chunks: outside [1, " +
                            std::to_string(kMaxChunks) + "]");
  }
  uint64_t total = 0;
  std::vector<detail::Part> parts(chunk_triangles.size());
  for (size_t i = 0; i < chunk_triangles.size(); ++i) {
    if (chunk_triangles[i] == 0) return invalid_argument("chunk " + std::to_string(i) + " has no triangles");
    parts[i].runs.push_back({static_cast<uint32_t>(total), chunk_triangles[i]});
    parts[i].triangles = chunk_triangles[i];
    total += chunk_triangles[i];
  }
  if (total != mesh.num_triangles) {
    return invalid_argument("the chunks hold " + std::to_string(total) + " triangles, the mesh has " +
                            std::to_string(mesh.num_triangles));
  }
  detail::Box box;
  FQ_RETURN_IF_ERROR(check_frame(mesh, labels, options, box));
  return encode_parts(mesh, labels, parts, options, box, out);
}

}  // namespace fq::wire
