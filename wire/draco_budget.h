// A decoded-size budget for one Draco chunk, read from its header before decoding.
//
// Draco trusts the counts in its stream: a chunk of a few hundred bytes that declares
// hundreds of millions of faces makes the decoder allocate gigabytes before it notices
// that the data ends. This reads the header, the metadata and the connectivity counts
// (bitstream 2.2, the version every Draco since 1.3 writes) without allocating, and
// refuses counts over the caps or beyond what the chunk's bytes could carry.
#pragma once

#include <cstdint>
#include <string_view>

#include "common/status.h"
#include "common/status_or.h"

namespace fq::wire {

struct ChunkBudget {
  uint64_t max_points = 4'000'000;  ///< points (vertices) one chunk may declare
  /// Points or faces per byte of the chunk beyond which the counts cannot be genuine.
  /// Real capture meshes take several bytes per vertex; a synthetic, perfectly regular grid
  /// compresses to well under a byte per face, so the default leaves a wide margin while
  /// still capping a 245-byte chunk at about 250K items instead of billions.
  uint64_t max_items_per_byte = 1024;
};

/// What a chunk's header declares.
struct ChunkCounts {
  uint64_t points = 0;
  uint64_t faces = 0;
};

/// Reads the counts a Draco mesh chunk declares. kInvalidInput for data that is not a
/// Draco 2.2 triangle mesh or whose header is cut short.
StatusOr<ChunkCounts> read_chunk_counts(std::string_view chunk);

/// read_chunk_counts plus the budget: kInvalidInput naming the count and the limit.
Status check_chunk_budget(std::string_view chunk, const ChunkBudget& budget);

}  // namespace fq::wire
