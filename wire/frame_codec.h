// Frames on the wire: a mesh as N spatially coherent Draco chunks that can be encoded and
// decoded in parallel and merged back by global vertex id (see docs/PROTOCOL.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"

namespace fq::wire {

/// Upper bound on the chunks of a frame (FrameHeader.chunk_count, encode_frame's `chunks`).
inline constexpr uint32_t kMaxChunks = 256;

/// Vertex ids and labels must be below this. Draco codes integer attributes exactly only for
/// moderate values: its symbol coder allocates tables in proportion to the largest value
/// (2^28 needs gigabytes) and values near 2^31 come back wrong.
inline constexpr uint32_t kMaxAttributeValue = 1u << 24;

/// Metadata name ("name" entry) of the GENERIC uint32 attribute holding the global vertex id.
inline constexpr const char* kVertexIdAttribute = "fq_vid";
/// Geometry metadata entry (binary) holding the global vertex ids of a chunk coded with Draco's
/// sequential coder, which keeps point order: the ascending ids as runs (wire/vertex_id_runs.h).
/// Such a chunk has no "fq_vid" attribute.
inline constexpr const char* kVertexIdRunsEntry = "fq_vid_runs";
/// Metadata name of the GENERIC uint32 attribute holding the per-vertex cluster label.
inline constexpr const char* kLabelAttribute = "fq_label";

struct CodecOptions {
  int position_bits = 16;  ///< Draco position quantization bits (1..30), on the frame's bbox
  int encode_speed = 5;    ///< Draco encoding speed 0 (best compression) .. 10 (fastest)
  int decode_speed = 5;    ///< Draco decoding speed 0 .. 10
  int threads = 1;         ///< chunks encoded / decoded concurrently (>= 1)
};

/// Encodes `mesh` (and per-vertex `labels`, nullable) as `chunks` Draco meshes into `out`.
/// Triangles are ranked by the smallest Morton code of their vertices and cut into equal
/// counts (detail::split_parts); every chunk carries its vertex ids (and "fq_label") and is
/// quantized on the whole frame's bounding box,
/// so vertices shared by chunks decode identically. Every vertex must be used by a triangle.
/// `chunks` is clamped to the triangle count: out.size() is the number of chunks written.
/// At most kMaxAttributeValue vertices; labels below kMaxAttributeValue.
/// kInvalidArgument for bad options or chunk counts, kInvalidInput for a bad mesh.
fq::Status encode_frame(const fq::MeshView& mesh, const uint32_t* labels, uint32_t chunks,
                        const CodecOptions& options, std::vector<std::string>& out);

/// Encodes `mesh` as the chunks `chunk_triangles` describes, without a split: chunk i holds the
/// next chunk_triangles[i] triangles, in order. That is how decode_frame lays out a frame's
/// chunks, so a result that keeps its input's connectivity (fqd's MESH results) is cut exactly
/// as its input was: the same chunk meshes, no Morton split. Otherwise as encode_frame.
/// kInvalidArgument when the counts are empty, zero, more than kMaxChunks or do not add up to
/// the mesh's triangles.
fq::Status encode_frame_as(const fq::MeshView& mesh, const uint32_t* labels,
                           const std::vector<uint32_t>& chunk_triangles, const CodecOptions& options,
                           std::vector<std::string>& out);

/// Decodes `chunks` and merges them by "fq_vid" into `vertex_count` vertices (0 = infer:
/// the largest id + 1, or the point count of a plain mesh). A single chunk without
/// "fq_vid" (a plain Draco mesh) is taken in Draco point order. `labels` (nullable) is filled
/// when every chunk has "fq_label", cleared otherwise. The triangles come out chunk after
/// chunk; `chunk_triangles` (nullable) gets each chunk's count (see encode_frame_as).
/// kInvalidInput for any malformed input; `out` is then empty. `out`'s buffers keep their
/// capacity, so a reused mesh stops allocating.
fq::Status decode_frame(const std::vector<std::string_view>& chunks, uint32_t vertex_count,
                        const CodecOptions& options, fq::Mesh& out, std::vector<uint32_t>* labels,
                        std::vector<uint32_t>* chunk_triangles = nullptr);

/// Positions only (the POSITIONS result form): the frame's `num_vertices` positions cut into
/// `chunks` contiguous ranges of vertex ids, chunk i holding vertices
/// [i * n / chunks, (i + 1) * n / chunks), each a Draco point cloud with POSITION alone.
/// Draco's sequential point cloud coder keeps the point order, so a decoder (any Draco
/// decoder) gets the vertices in frame order by concatenating the chunks; the faces are the
/// input frame's. Quantized like encode_frame, on one grid (the frame's bounding box).
/// `chunks` is clamped to the vertex count. kInvalidArgument for bad options or chunk counts,
/// kInvalidInput for no vertices or a non-finite coordinate.
fq::Status encode_positions(const float* positions, uint32_t num_vertices, uint32_t chunks,
                            const CodecOptions& options, std::vector<std::string>& out);

/// Decodes point-cloud chunks and concatenates their points in chunk order into `out`
/// (3 floats per vertex). kInvalidInput for malformed chunks, a triangle mesh, or a total
/// point count other than `vertex_count` (0 = any).
fq::Status decode_positions(const std::vector<std::string_view>& chunks, uint32_t vertex_count,
                            const CodecOptions& options, std::vector<float>& out);

/// Frees the buffers the codec keeps for the next frames (the chunk writers', the sequential
/// coder's, the decoded chunks') that no call is using now; returns how many it freed. They
/// are kept per use, not per thread, so this reaches all of them: fqd calls it once frames
/// have stopped for caps.pool_idle_s.
size_t release_memory();

}  // namespace fq::wire
