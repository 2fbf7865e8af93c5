// Internals of the frame codec: one chunk of a frame, encoded. A sequentially coded chunk (the
// codec's default, Draco speed 10) is written straight from the frame (write_sequential_chunk);
// any other is built as a draco::Mesh and encoded by Draco (build_chunk, encode_chunk), which is
// also how fqbench builds its floor (the same chunks, positions only, through Draco).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/scratch_pool.h"
#include "common/status.h"
#include "core/mesh_view.h"
#include "wire/draco_sequential.h"
#include "wire/frame_codec.h"
#include "wire/frame_split.h"

namespace draco {
class Mesh;
class PointCloud;
}  // namespace draco

namespace fq::wire::detail {

/// Per-thread scratch space of build_chunk and write_sequential_chunk, reused from chunk to
/// chunk and frame to frame.
struct ChunkScratch {
  std::vector<uint64_t> seen;  ///< one bit per frame vertex: the chunk's; all zero between chunks
  /// global -> point index of the current chunk; only its vertices' entries are ever read, so
  /// it is never initialized (a memset of the whole frame per worker and frame saved).
  std::unique_ptr<uint32_t[]> local;
  size_t local_size = 0;
  /// When set, build_chunk and write_sequential_chunk OR the chunk's vertices into this
  /// frame-wide bitmap (shared by the workers), so that "every vertex is used" needs no pass of
  /// its own.
  std::atomic<uint64_t>* used = nullptr;
  SequentialScratch coder;  ///< write_sequential_chunk's buffers
};

/// The chunk writers' scratch, borrowed for a chunk and kept for the next ones so that frames
/// after the first allocate nothing (each holds what the largest frame so far needed);
/// wire::release_memory() frees it. Reset a scratch (assign {}) when a chunk fails half-way:
/// the bitmap must be all zero between chunks.
ScratchPool<ChunkScratch>& chunk_scratch();

/// Whether the chunk `part` is coded with Draco's sequential coder: at speed 10, or when a
/// face repeats a vertex (edgebreaker would drop it). Only that coder keeps point order, which
/// the id runs (kVertexIdRunsEntry) rely on.
bool sequential_chunk(const fq::MeshView& mesh, const CodecOptions& o, const Part& part);

/// The triangles of `part` as one Draco mesh in `out`, coded sequentially (see
/// sequential_chunk), written directly (wire/draco_sequential.h): the bytes draco::Encoder
/// writes for build_chunk's mesh of the same part at the same options (with ids, and with
/// `labels` when not null). kInternal when Draco's symbol or metadata coder fails.
fq::Status write_sequential_chunk(const fq::MeshView& mesh, const uint32_t* labels, const Part& part,
                                  const CodecOptions& o, const Box& box, ChunkScratch& scratch,
                                  std::string& out);

/// The triangles of `part` (see split_parts) as a draco::Mesh:
/// points = the chunk's vertices in ascending global id, POSITION, then (when `with_ids`) the global ids, and
/// "fq_label" (when `labels`). Built directly (not with a mesh builder) so that no deduplication can merge
/// two vertices. `scratch` is the calling worker's. Returns sequential_chunk(): a sequential chunk carries
/// its ids as kVertexIdRunsEntry (the coder keeps point order), any other as "fq_vid".
bool build_chunk(const fq::MeshView& mesh, const uint32_t* labels, bool with_ids, const CodecOptions& o,
                 const Part& part, ChunkScratch& scratch, draco::Mesh& m);

/// Encodes `m` or `pc` at `o`'s speeds with Draco's coder `method`, positions quantized to
/// o.position_bits on one explicit grid over `box`: every chunk of a frame uses the same grid,
/// so a vertex on a chunk border decodes identically in both. kInternal when Draco fails.
fq::Status encode_on_grid(const draco::Mesh& m, int method, const CodecOptions& o, const Box& box,
                          std::string& out);
fq::Status encode_on_grid(const draco::PointCloud& pc, int method, const CodecOptions& o, const Box& box,
                          std::string& out);

/// Encodes one chunk with the codec's settings: speeds, the frame's shared quantization grid
/// on `box`, and the coder build_chunk chose (`sequential`).
fq::Status encode_chunk(const draco::Mesh& m, bool sequential, const CodecOptions& o, const Box& box,
                        std::string& out);

}  // namespace fq::wire::detail
