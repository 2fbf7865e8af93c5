// The one launcher of the per-item kernels (one thread per vertex, triangle or corner), their
// 64-bit item index, launch shapes, and the test hook that makes the next launch fail.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>
#include <utility>

#include "kernels/cuda/cuda_check.cuh"

namespace fq::cuda {

/// Threads per block of every per-item kernel: 256, or the environment variable
/// FQ_CUDA_BLOCK (a multiple of 32 in 32..1024, read once) for tuning runs.
unsigned block_size();

/// Blocks of block_size() threads covering n items (at least one). Returns 0 -- an invalid
/// launch configuration, a real CUDA error -- once after fail_next_launch() was called.
unsigned blocks_for(uint64_t n);

/// Test hook (see cuda_engine.h): the next blocks_for() returns 0.
void fail_next_launch();

/// This thread's item in a per-item kernel, in 64 bits: a frame's corners (3 per triangle)
/// pass 2^32 before its vertices do.
__device__ inline uint64_t item_index() { return uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; }

/// Launches `kernel` over `items` items on `s` (blocks_for(items) blocks of block_size()
/// threads; nothing for no items) and checks the launch, reporting `name`, `file` and `line`
/// (FQ_LAUNCH passes the caller's). A bad configuration throws CudaError; faults inside the
/// kernel surface at the frame's synchronization.
template <class... Params, class... Args>
void launch_items(const char* name, const char* file, int line, void (*kernel)(Params...), uint64_t items,
                  cudaStream_t s, Args&&... args) {
  if (items == 0) return;
  kernel<<<blocks_for(items), block_size(), 0, s>>>(std::forward<Args>(args)...);
  check(cudaGetLastError(), name, file, line);
}

}  // namespace fq::cuda

/// FQ_LAUNCH(kernel, items, stream, args...): launch_items with the kernel's name and the
/// caller's file and line.
#define FQ_LAUNCH(kernel, items, s, ...) \
  ::fq::cuda::launch_items("launch of " #kernel, __FILE__, __LINE__, kernel, items, s, __VA_ARGS__)
