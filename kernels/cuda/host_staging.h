// Host side of a CUDA frame's transfers, on a few threads of fq's shared pool: the caller's arrays go up
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

/// A download in chunks through pinned staging, each chunk followed by its own event.
struct StagedDownload {
  const unsigned char* staging = nullptr;
  unsigned char* dst = nullptr;
  size_t bytes = 0, chunk = 0;
  const cudaEvent_t* done = nullptr;
};

/// Enqueues staging (pinned, at least `bytes`) = src (device) on `s` in at most `events`
/// chunks, recording done[k] after chunk k.
StagedDownload enqueue_download(const void* src, void* dst, size_t bytes, unsigned char* staging,
                                const cudaEvent_t* done, int events, cudaStream_t s);

/// Waits for the chunks in turn and copies each out of pinned memory on all host threads
/// while the next one is still in flight (a few threads of the shared pool).
void complete_download(const StagedDownload& d);

/// dst = src, `bytes` long, on a few threads of the shared pool.
void parallel_copy(void* dst, const void* src, size_t bytes);

}  // namespace fq::cuda
