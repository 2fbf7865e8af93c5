// Launch shapes shared by the kernels, and the test hook that makes the next launch fail.
#pragma once

#include <cstdint>

namespace fq::cuda {

/// Threads per block of every per-item kernel: 256, or the environment variable
/// FQ_CUDA_BLOCK (a multiple of 32 in 32..1024, read once) for tuning runs.
unsigned block_size();

/// Blocks of block_size() threads covering n items (at least one). Returns 0 -- an invalid
/// launch configuration, a real CUDA error -- once after fail_next_launch() was called.
unsigned blocks_for(uint64_t n);

/// Test hook (see cuda_engine.h): the next blocks_for() returns 0.
void fail_next_launch();

}  // namespace fq::cuda
