// The one launcher of the CUDA kernels: the grids computed from item counts (per-item and team
// kernels) or fixed shapes (launch_tuning.h), the 64-bit item index, and the test hook that
// makes the next computed launch fail.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>
#include <utility>

#include "kernels/cuda/cuda_check.cuh"
#include "kernels/cuda/launch_tuning.h"

namespace fq::cuda {

/// Threads per block of every per-item and team kernel: tuning::kItemBlock, or the environment
/// variable FQ_CUDA_BLOCK (a multiple of 32 in 32..1024, read once) for tuning runs.
unsigned block_size();

/// The grid of every computed launch: blocks of `per_block` items covering `items` (at least
/// one). Past tuning::kMaxGrid it returns 0 rather than a capped grid -- the kernels are not
/// grid-stride loops, so a capped grid would leave items out -- and 0 is an invalid launch
/// configuration, a real CUDA error; so is the 0 returned once after fail_next_launch().
unsigned grid_size(uint64_t items, uint64_t per_block);

/// Blocks of block_size() threads covering n items, one thread each.
inline unsigned blocks_for(uint64_t n) { return grid_size(n, block_size()); }

/// Blocks of block_size() threads covering n vertices with a team of `team` lanes each (team
/// divides 32, block_size() is a multiple of 32: block_size() / team vertices a block).
inline unsigned team_blocks(uint64_t n, unsigned team) { return grid_size(n, block_size() / team); }

/// Test hook (see cuda_engine.h): the next grid_size() returns 0.
void fail_next_launch();

/// This thread's item in a per-item kernel, in 64 bits: a frame's corners (3 per triangle)
/// pass 2^32 before its vertices do.
__device__ inline uint64_t item_index() { return uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; }

/// A launch's shape: blocks, threads per block and dynamic shared memory.
struct LaunchShape {
  unsigned blocks;
  unsigned threads;
  size_t shared_bytes;
};

/// A shape to hand FQ_LAUNCH (a call, so that its commas stay inside one macro argument).
constexpr LaunchShape launch_shape(unsigned blocks, unsigned threads, size_t shared_bytes = 0) {
  return {blocks, threads, shared_bytes};
}

/// Launches `kernel` with `shape` on `s` and checks the launch, reporting `name`, `file` and
/// `line` (FQ_LAUNCH passes the caller's). A bad configuration throws CudaError; faults inside
/// the kernel surface at the frame's synchronization.
template <class... Params, class... Args>
void launch(const char* name, const char* file, int line, void (*kernel)(Params...), LaunchShape shape,
            cudaStream_t s, Args&&... args) {
  kernel<<<shape.blocks, shape.threads, shape.shared_bytes, s>>>(std::forward<Args>(args)...);
  check(cudaGetLastError(), name, file, line);
}

/// Launches `kernel` over `items` items on `s`: blocks_for(items) blocks of block_size()
/// threads, nothing for no items.
template <class... Params, class... Args>
void launch(const char* name, const char* file, int line, void (*kernel)(Params...), uint64_t items,
            cudaStream_t s, Args&&... args) {
  if (items == 0) return;
  launch(name, file, line, kernel, launch_shape(blocks_for(items), block_size()), s,
         std::forward<Args>(args)...);
}

/// The blocks of `threads` threads of `kernel` that the current device holds at once (its
/// multiprocessors times the kernel's occupancy with no dynamic shared memory): asked of the
/// runtime once per kernel, device and block size and kept, since the occupancy query costs
/// microseconds and track B makes a handful of cooperative launches a frame. A failed query
/// throws CudaError with `name`, `file` and `line`.
uint64_t resident_blocks(const void* kernel, unsigned threads, const char* name, const char* file, int line);

/// Launches `kernel`, a grid-stride kernel over `items` items that synchronizes its whole grid
/// (cooperative_groups' grid.sync()), as a cooperative launch on `s`: blocks_for(items) blocks,
/// or as many as the device holds at once when fewer (the barrier needs every block resident).
/// Nothing for no items; a bad configuration (and the fail_next_launch() hook) throws CudaError.
template <class... Params, class... Args>
void launch_cooperative(const char* name, const char* file, int line, void (*kernel)(Params...),
                        uint64_t items, cudaStream_t s, Args&&... args) {
  if (items == 0) return;
  const unsigned threads = block_size();
  const uint64_t resident = resident_blocks(reinterpret_cast<const void*>(kernel), threads, name, file, line);
  const unsigned wanted = blocks_for(items);
  cudaLaunchConfig_t config{};
  config.gridDim = dim3(unsigned(wanted < resident ? wanted : resident));
  config.blockDim = dim3(threads);
  config.stream = s;
  cudaLaunchAttribute cooperative{};
  cooperative.id = cudaLaunchAttributeCooperative;
  cooperative.val.cooperative = 1;
  config.attrs = &cooperative;
  config.numAttrs = 1;
  check(cudaLaunchKernelEx(&config, kernel, std::forward<Args>(args)...), name, file, line);
}

}  // namespace fq::cuda

/// FQ_LAUNCH_COOPERATIVE(kernel, items, stream, args...): launch_cooperative() with the kernel's
/// name and the caller's file and line.
#define FQ_LAUNCH_COOPERATIVE(kernel, items, s, ...)                                                     \
  ::fq::cuda::launch_cooperative("cooperative launch of " #kernel, __FILE__, __LINE__, kernel, items, s, \
                                 __VA_ARGS__)

/// FQ_LAUNCH(kernel, items or shape, stream, args...): launch() with the kernel's name and the
/// caller's file and line. An item count gets the per-item grid (and no launch for none); a
/// LaunchShape (launch_shape()) is launched as it is.
#define FQ_LAUNCH(kernel, items, s, ...) \
  ::fq::cuda::launch("launch of " #kernel, __FILE__, __LINE__, kernel, items, s, __VA_ARGS__)
