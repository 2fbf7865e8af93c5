// The noise estimate's samples on the device (kernels/noise_estimate.h): the same fits as
// noise_sample(), each made by one warp instead of one thread.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

#include "kernels/noise_estimate.h"
#include "kernels/refine_math.h"

namespace fq::cuda {

/// out[k] = noise_sample(fan, x, k * stride) for k < count (device pointers), enqueued on s.
void noise_samples(const FanView& fan, const Vec3* x, uint32_t stride, uint32_t count, NoiseSample* out,
                   cudaStream_t s);

}  // namespace fq::cuda
