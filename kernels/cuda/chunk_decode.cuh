// The device decode of the frame codec's sequential chunks: the kernel's arguments and its
// launch (chunk_decode.cu); chunk_decoder.cu plans the chunks and calls it.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "kernels/cuda/chunk_job.h"
#include "wire/rans_decode.h"

namespace fq::cuda {

/// What the kernel reads and writes (device pointers).
struct ChunkDecodeArgs {
  const uint8_t* bytes = nullptr;
  const ChunkJob* jobs = nullptr;
  uint32_t chunks = 0;
  wire::detail::RansSymbol* symbols = nullptr;  ///< the tables' room (ChunkJob::symbols_at)
  uint32_t* buckets = nullptr;                  ///< kRansBuckets a chunk, for the thread-per-chunk form only
  int32_t* values = nullptr;                    ///< the quantized positions, 3 a point
  float* positions = nullptr;                   ///< 3 a point
  uint32_t* corners = nullptr;                  ///< 3 a face, each the chunk's own point index
  uint32_t* labels = nullptr;                   ///< a point, where the chunk is labelled
  uint32_t* faults = nullptr;                   ///< a ChunkFault a chunk
};

/// Enqueues the decode of every chunk of `a` on `s`.
void launch_chunk_decode(const ChunkDecodeArgs& a, ChunkTeam team, cudaStream_t s);

}  // namespace fq::cuda
