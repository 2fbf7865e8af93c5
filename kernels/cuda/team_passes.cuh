// Team-per-vertex versions of the four heaviest passes (see team_passes.cu). `team` is the
// lanes per vertex: 1, 2, 4, 8, 16 or 32; `fast_exp` takes Gaussian weights through __expf.
#pragma once

#include <cuda_runtime.h>

#include "core/params.h"
#include "kernels/cuda/device_frame.cuh"
#include "kernels/frame_plan.h"

namespace fq::cuda {

void team_neighbourhood_quadrics(DeviceFrame& f, Extent sigma_b, int team, bool fast_exp, cudaStream_t s);
void team_diffuse_quadrics(DeviceFrame& f, const RunPlan& run, int team, bool fast_exp, cudaStream_t s);
void team_cluster_scores(DeviceFrame& f, const RunPlan& run, int team, bool fast_exp, cudaStream_t s);
void team_cluster_links(DeviceFrame& f, const RunPlan& run, int team, bool fast_exp, cudaStream_t s);

}  // namespace fq::cuda
