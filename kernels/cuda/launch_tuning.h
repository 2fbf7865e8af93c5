// The launch shapes of the CUDA kernels, in one place: threads per block of each kind of
// kernel and the fixed grids, each with what bounds it. launch.cuh computes the grids of the
// per-item and team kernels from these; the rest launch these shapes as they are.
#pragma once

#include <cstdint>

namespace fq::cuda::tuning {

/// Threads per block of the per-item and team kernels (block_size()), unless FQ_CUDA_BLOCK
/// names another for a tuning run. Bounded by the warp below (a multiple of 32, so every team
/// of 1..32 lanes fits a block whole) and by the hardware's 1024 above; the team kernels'
/// optional __launch_bounds__ (FQ_TEAM_MIN_BLOCKS) is written for this size.
constexpr unsigned kItemBlock = 256;

/// Threads per block of the frame checks' reductions: the width of their cub::BlockReduce and
/// __launch_bounds__, so it is fixed at compile time (FQ_CUDA_BLOCK does not move it).
constexpr unsigned kReduceBlock = 256;

/// Blocks of the frame checks' grid-stride reductions: a fixed grid makes the partial edge sums,
/// and the order they are combined in, the same on every run (a reproducible mean edge);
/// sum_partials reads this many partials with one block.
constexpr unsigned kReduceGrid = 1024;

/// Threads per block of the noise samples: two warps, one fitting each vertex of a sample's
/// pair; the kernel's __launch_bounds__ and its shared fits are sized for exactly two.
constexpr unsigned kNoiseSampleBlock = 64;

/// Threads of the bilateral pass's reset of the centroid bounds: one warp, at least the six
/// bounds it writes (a thread each).
constexpr unsigned kResetBoundsBlock = 32;

/// Threads of a kernel that sets a few fields once (the frame checks' reset): one.
constexpr unsigned kSingleThread = 1;

/// The largest grid.x the hardware takes (2^31 - 1 blocks): the cap of every computed grid.
constexpr uint64_t kMaxGrid = (uint64_t(1) << 31) - 1;

}  // namespace fq::cuda::tuning
