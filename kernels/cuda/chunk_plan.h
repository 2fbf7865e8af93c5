// The host's checks of a frame's chunks before the device decodes them, and their places in
// the device's arrays. Every check the host reader (read_sequential_chunk) makes before the
// attribute values is made here, by the same parser (wire/sequential_layout.h), so a chunk
// the device gets is bounded as the host reader bounds it: its counts by its bytes, its ids
// by the limit. What is left (the indices' bounds, the values) the kernel checks as it reads.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "kernels/cuda/chunk_job.h"

namespace fq::cuda {

/// A frame's chunks as the device decodes them.
struct ChunkPlan {
  std::vector<ChunkJob> jobs;
  std::vector<std::vector<uint32_t>> ids;  ///< each chunk's global vertex ids, from its runs
  uint64_t bytes = 0;                      ///< the chunks' bytes, packed one after another
  uint64_t points = 0;                     ///< all chunks' points
  uint64_t corners = 0;                    ///< all chunks' corners
  uint64_t symbols = 0;                    ///< the tables' room of all chunks
  bool labelled = false;                   ///< some chunk is labelled
};

/// Chunks larger than this are the host's (the kernel's offsets within a chunk are 32-bit).
inline constexpr uint64_t kMaxDeviceChunkBytes = uint64_t(1) << 30;

/// Plans every chunk (wire::detail::plan_sequential_chunk, ids below `id_limit`). kInvalidInput
/// naming the first chunk that is not the codec's sequential layout or fails a check (such a
/// frame is for the host codec, which reads any Draco mesh), or for no chunks or too many.
fq::Status plan_chunks(const std::vector<std::string_view>& chunks, uint32_t id_limit, ChunkPlan& plan);

}  // namespace fq::cuda
