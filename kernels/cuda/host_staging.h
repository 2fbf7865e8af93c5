// Host side of a CUDA frame's transfers, on all host threads: the caller's arrays go up
// through pinned staging in chunks, so that copying chunk k into pinned memory overlaps
// the copy engine's transfer of chunk k-1; results come back out of pinned memory by a
// parallel copy.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>

namespace fq::cuda {

/// dst (device) = src (pageable host), `bytes` long, through `staging` (pinned, at least
/// `bytes`). Enqueues the transfers on `s` and returns once every chunk is staged; the
/// caller's memory may then change, the staging not until `s` has passed the copies.
void upload_staged(const void* src, void* dst, size_t bytes, unsigned char* staging, cudaStream_t s);

/// dst = src, `bytes` long, on all host threads.
void parallel_copy(void* dst, const void* src, size_t bytes);

}  // namespace fq::cuda
