// One chunk of the device decode as the host plans it (chunk_plan.h) and the kernel reads it
// (chunk_decode.cu), and why the kernel may refuse it. No CUDA types: the planning is host code.
#pragma once

#include <cstdint>

namespace fq::cuda {

/// One chunk, as the host planned it (wire::detail::plan_sequential_chunk): where its bytes,
/// sections and outputs lie.
struct ChunkJob {
  uint64_t bytes_at;      ///< its first byte in the packed bytes
  uint64_t first_point;   ///< its first point's slot in positions (3 a point), values (3) and labels (1)
  uint64_t first_corner;  ///< its first corner's slot in corners
  uint64_t symbols_at;    ///< its tables' room in the symbol workspace
  uint32_t size;          ///< its bytes
  uint32_t corners_at, corners_end, values_at;  ///< its sections, from its first byte
  uint32_t points, faces;
  uint32_t symbol_room;  ///< wire::detail::rans_symbol_room of its values' bytes
  uint8_t index_bytes;   ///< wire::detail::sequential_index_bytes(points)
  uint8_t labelled;
};

/// Why the device refused a chunk (kChunkDecoded: it did not).
enum ChunkFault : uint32_t {
  kChunkDecoded = 0,
  kCornerOutOfRange = 1,  ///< a face names a point the chunk does not have
  kPositionValues = 2,    ///< the positions' values are not as Draco's decoder reads them
  kLabelValues = 3,       ///< the labels' values are not
  kQuantization = 4,      ///< the quantization's parameters are not
  kTableRoom = 5,         ///< a table outgrew its room (a fault of the planning, not of the input)
};

/// How the chunks are shared out: a team of threads each, which keeps the tables' lookup in
/// shared memory and runs the passes over points and corners on all its lanes (a block of 256
/// or 1024, or a warp), or a thread each (the lookup in global memory). One lane decodes the
/// rANS stream in every form.
enum class ChunkTeam { kThread = 1, kWarp = 32, kBlock = 256, kWideBlock = 1024 };

/// A word for a ChunkFault.
const char* chunk_fault_name(uint32_t fault);

}  // namespace fq::cuda
