// Factory of the CUDA engine and its process-wide counters. CUDA-free on purpose: device
// state stays behind the Engine, so this header compiles without nvcc.
#pragma once

#include <cstdint>
#include <memory>

#include "kernels/engine.h"

namespace fq {

/// The CUDA engine on device `device` ("cuda:<device name>") with the kernel choices of
/// `tuning`, or null with a kUnavailable status and a reason (no device, no driver, bad
/// ordinal, device refused a stream, a team size CudaTuning does not accept...).
std::unique_ptr<Engine> make_cuda_engine(int device, Status* why, const CudaTuning& tuning = {});

/// Device allocations (cudaMalloc) made so far by every CUDA engine of this process. After
/// the first frame of a given size, further frames of that size leave it unchanged.
uint64_t cuda_allocation_count();

/// Device bytes held right now by the buffers of every CUDA engine of this process. A frame
/// far smaller than the largest one so far (a quarter of its vertices or fewer) makes the
/// engine give the larger frame's buffers back, as the CPU engine does with its scratch.
uint64_t cuda_device_bytes_held();

/// Test hook: the next kernel launch of any CUDA engine fails with a real CUDA error (an
/// invalid launch configuration), which the engine reports as kInternal for that frame.
void cuda_fail_next_launch_for_testing();

}  // namespace fq
